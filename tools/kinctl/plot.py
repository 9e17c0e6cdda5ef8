"""A plot of a setpoint log: q, qd, qdd against time (one panel each, every
joint, goal boundaries marked) and the tool path (3-D, XY and XZ).

    from kinctl.plot import plot_run
    info = plot_run("run.csv", "run.png", events="events.csv")

Uses matplotlib's Agg backend (no display needed). Returns what was drawn, so
that tests can check the axes without looking at pixels.
"""
import statistics

from kinctl import logcsv

# Shaded spans of these states, with their colours.
SHADE = {"STOPPING": "#f4c7c3", "PAUSED": "#fce8b2", "ESTOP": "#e06666", "FAULT": "#e06666"}


def _segments(goal_ids):
    """[(start index, end index (exclusive), goal_id)] of runs of one goal_id != 0."""
    segs, start = [], None
    for i, g in enumerate(goal_ids + [None]):
        if start is not None and (g != goal_ids[start]):
            if goal_ids[start] != 0:
                segs.append((start, i, goal_ids[start]))
            start = None
        if start is None and g is not None:
            start = i
    return segs


def _spans(states, code):
    out, start = [], None
    for i, s in enumerate(states + [None]):
        if s == code and start is None:
            start = i
        elif s != code and start is not None:
            out.append((start, i - 1))
            start = None
    return out


def plot_run(csv_path, png_path, events=None, title=None, labels=None, dpi=100):
    """Writes the PNG. labels: {goal_id: text} for the goal markers (default:
    "goal <id>"). Returns {"rows", "joints", "png", "axes": [{"title", "xlabel",
    "ylabel", "lines", "curves" (labelled lines)}...], "goals": [goal ids in order]}."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.gridspec import GridSpec
    from kinctl.msgs import STATES

    cols = logcsv.read(csv_path) if isinstance(csv_path, str) else csv_path
    rows = len(cols["cycle"])
    if rows < 2:
        raise ValueError(f"{csv_path}: fewer than 2 setpoints to plot")
    n = sum(1 for k in cols if k.startswith("qd") and not k.startswith("qdd"))
    dts = [b - a for a, b in zip(cols["utime"], cols["utime"][1:]) if b > a]
    dt = statistics.median(dts) / 1e6 if dts else 1e-3
    c0 = cols["cycle"][0]
    # Trajectory time: cycles executed times the period (a stall does not show as a jump).
    t = [(c - c0) * dt for c in cols["cycle"]]
    ev = logcsv.read_events(events) if isinstance(events, str) else (events or [])
    labels = dict(labels or {})
    segs = _segments(cols["goal_id"])
    outcome = {}
    for e in ev:
        if e["event"] in ("COMPLETED", "PREEMPTED", "ABORTED", "FAULT"):
            outcome[e["goal_id"]] = e["event"].lower()

    fig = plt.figure(figsize=(16, 10), dpi=dpi)
    gs = GridSpec(3, 3, figure=fig, width_ratios=[1.35, 1.35, 1], hspace=0.32, wspace=0.28,
                  left=0.05, right=0.98, top=0.87, bottom=0.06)
    axq = fig.add_subplot(gs[0, :2])
    axqd = fig.add_subplot(gs[1, :2], sharex=axq)
    axqdd = fig.add_subplot(gs[2, :2], sharex=axq)
    ax3 = fig.add_subplot(gs[0, 2], projection="3d")
    axxy = fig.add_subplot(gs[1, 2])
    axxz = fig.add_subplot(gs[2, 2])
    joint_colors = plt.get_cmap("tab10").colors
    seg_colors = plt.get_cmap("Dark2").colors

    for ax, key, name, unit in ((axq, "q", "position q", "rad"),
                                (axqd, "qd", "velocity qd", "rad/s"),
                                (axqdd, "qdd", "acceleration qdd", "rad/s²")):
        for j in range(1, n + 1):
            ax.plot(t, cols[f"{key}{j}"], lw=1.2, color=joint_colors[(j - 1) % 10], label=f"{key}{j}")
        ax.set_ylabel(f"{name} ({unit})")
        ax.grid(True, alpha=0.3)
        for state, colour in SHADE.items():
            for a, b in _spans(cols["state"], STATES.get(state, -99)):
                ax.axvspan(t[a], t[b], color=colour, alpha=0.6, lw=0, zorder=0)
        for a, _, _ in segs:
            ax.axvline(t[a], color="0.35", ls="--", lw=0.8, zorder=1)
        ax.legend(loc="upper right", ncol=n, fontsize=8, framealpha=0.8, handlelength=1.2)
    axqdd.set_xlabel("time (s)")
    for lab in axq.get_xticklabels() + axqd.get_xticklabels():
        lab.set_visible(False)
    # Goal names above the q panel, at their start, in three staggered rows.
    for k, (a, b, gid) in enumerate(segs):
        text = labels.get(gid, f"goal {gid}")
        if gid in outcome and outcome[gid] != "completed":
            text += f" ({outcome[gid]})"
        axq.annotate(text, xy=(t[a], 1.0), xycoords=("data", "axes fraction"),
                     xytext=(2, 3 + 12 * (k % 3)), textcoords="offset points", ha="left", va="bottom",
                     fontsize=8.5, color=seg_colors[k % len(seg_colors)], fontweight="bold")
    for state, colour in SHADE.items():
        if _spans(cols["state"], STATES.get(state, -99)):
            axqd.plot([], [], color=colour, lw=8, label=state.lower())
    axqd.legend(loc="upper right", ncol=n + 2, fontsize=8, framealpha=0.8, handlelength=1.2)

    # Tool path, one colour per goal; idle parts grey.
    x, y, z = cols["x"], cols["y"], cols["z"]
    ax3.plot(x, y, z, color="0.75", lw=0.8)
    for axp, (u, v, un, vn) in ((axxy, (x, y, "x", "y")), (axxz, (x, z, "x", "z"))):
        axp.plot(u, v, color="0.75", lw=0.8)
        axp.set_xlabel(f"{un} (m)")
        axp.set_ylabel(f"{vn} (m)")
        axp.set_aspect("equal", adjustable="datalim")
        axp.grid(True, alpha=0.3)
    for k, (a, b, gid) in enumerate(segs):
        col = seg_colors[k % len(seg_colors)]
        lab = labels.get(gid, f"goal {gid}")
        ax3.plot(x[a:b], y[a:b], z[a:b], color=col, lw=1.8)
        axxy.plot(x[a:b], y[a:b], color=col, lw=1.8, label=lab)
        axxz.plot(x[a:b], z[a:b], color=col, lw=1.8)
    # Start (circle) and end (square).
    for i, marker in ((0, "o"), (-1, "s")):
        ax3.plot([x[i]], [y[i]], [z[i]], marker=marker, color="k", ms=4, ls="")
        axxy.plot([x[i]], [y[i]], marker=marker, color="k", ms=4, ls="")
        axxz.plot([x[i]], [z[i]], marker=marker, color="k", ms=4, ls="")
    ax3.set_title("tool path (● start, ■ end)", loc="left", fontsize=11)
    ax3.set_xlabel("x (m)")
    ax3.set_ylabel("y (m)")
    ax3.set_zlabel("z (m)")
    ax3.tick_params(labelsize=7)
    axxy.set_title("tool path, top view (XY)", loc="left", fontsize=11)
    axxz.set_title("tool path, side view (XZ)", loc="left", fontsize=11)
    if segs:
        axxy.legend(fontsize=7.5, loc="best", framealpha=0.8)
    fig.suptitle(title or f"kinctld setpoints: {rows} cycles of {dt * 1e3:g} ms", fontsize=13)
    fig.savefig(png_path, dpi=dpi)

    axes = []
    for ax in (axq, axqd, axqdd, ax3, axxy, axxz):
        axes.append({"title": ax.get_title(loc="left"), "name": ax.name, "xlabel": ax.get_xlabel(),
                     "ylabel": ax.get_ylabel(),
                     "lines": len(ax.get_lines()),
                     "curves": [ln.get_label() for ln in ax.get_lines() if not ln.get_label().startswith("_")]})
    plt.close(fig)
    return {"rows": rows, "joints": n, "png": png_path, "axes": axes, "goals": [g for _, _, g in segs],
            "period_s": dt}
