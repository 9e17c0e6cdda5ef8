# SPDX-License-Identifier: BSD-3-Clause
"""The graphs of seed 001 labs 4-7 from a run's setpoints: q, qd, qdd of every
joint against time (goal boundaries marked, each goal's leading joint drawn
bold: see leading_joints), each joint's jerk (the change of the logged qdd
from one setpoint to the next over their time step; with the arm's model its
limit qddd_max marked), the tool's speed along its path, and the tool path
in 3-D and on the XY, XZ and YZ planes, one colour per goal_id.

    from kinctl.plot import plot_run
    info = plot_run("run.csv", "run.png", events="events.csv")   # or an LCM log, or .svg

The log is a setpoint CSV (kinctl log --csv) or an LCM event log (lcm-logger,
kinctl record); see kinctl.runlog. Uses matplotlib's Agg backend (no display
needed). Returns what was drawn, so that tests can check the axes without
looking at pixels. shapes: extra 3-D geometry (kinctl.shapes) drawn into the
path panels; so are forbidden zones (zones_file, zones: as kinctl-calc zones
takes them) and, with volumes=True and the arm's model, its link volumes at
the first and the last setpoint (kinctl.zonedraw; kinctl plot asks for them
whenever --model or --model-file is given, unless --no-volumes).
"""
import os

from kinctl import runlog

# Shaded spans of these states, with their colours.
SHADE = {"STOPPING": "#f4c7c3", "PAUSED": "#fce8b2", "ESTOP": "#e06666", "FAULT": "#e06666"}
FORMATS = (".png", ".svg")
PLANES = (("x", "y", "top view (XY)"), ("x", "z", "side view (XZ)"), ("y", "z", "front view (YZ)"))


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


def leading_joint(cols, n, a, b):
    """The joint (1-based) that travels farthest over setpoints a..b-1,
    sum |q(k+1) - q(k)|: for a joint move that is |dq|, seed 001 (4.2)'s
    leading joint (equal limits). 0 when nothing moves."""
    best, lead = 0.0, 0
    for j in range(1, n + 1):
        q = cols[f"q{j}"][a:b]
        travel = sum(abs(v - u) for u, v in zip(q, q[1:]))
        if travel > best:
            best, lead = travel, j
    return lead


def is_joint_line(cols, n, a, b, tol=1e-9):
    """True when setpoints a..b-1 lie on the straight line in joint space
    between the first and the last (a joint move; also one cut short by a
    stop on its path), within tol (rad or m, relative to the move's length)."""
    import numpy as np
    Q = np.array([cols[f"q{j}"][a:b] for j in range(1, n + 1)]).T
    d = Q[-1] - Q[0]
    length = float(np.linalg.norm(d))
    if length == 0.0:
        return False
    d /= length
    rel = Q - Q[0]
    off = rel - np.outer(rel @ d, d)
    return float(np.abs(off).max()) <= tol * max(1.0, length)


def leading_joints(cols, n, segs, model=None, model_file=None):
    """{goal_id: (joint (1-based), how)} for every goal segment. With the
    arm's model, a joint move's leading joint is the planner's (kinctl-calc
    interp joint: the joint whose own fastest move takes longest, with each
    joint's limits), how = "planner"; otherwise, and for Cartesian and
    multi-point motions (no single leading joint there), the joint that
    travels farthest, how = "travel"."""
    out, moves = {}, []
    for a, b, gid in segs:
        if gid in out:
            continue
        out[gid] = (leading_joint(cols, n, a, b), "travel")
        if (model or model_file) and is_joint_line(cols, n, a, b):
            moves.append((gid, [cols[f"q{j}"][a] for j in range(1, n + 1)],
                          [cols[f"q{j}"][b - 1] for j in range(1, n + 1)]))
    if moves:
        from kinctl.kinematics import planned_leads
        for (gid, _, _), lead in zip(moves, planned_leads([(q0, q1) for _, q0, q1 in moves], model, model_file)):
            out[gid] = (lead, "planner")
    return out


def tool_speed(t, x, y, z):
    """|d(x, y, z)/dt| (m/s) by central differences (one-sided at the ends)."""
    import numpy as np
    p = np.array([x, y, z])
    if len(t) < 2:
        return np.zeros(len(t))
    v = np.gradient(p, np.asarray(t, dtype=float), axis=1)
    return np.sqrt((v * v).sum(axis=0))


def check_output(path):
    ext = os.path.splitext(path)[1].lower()
    if ext not in FORMATS:
        raise ValueError(f"{path}: the output's extension picks the format: .png or .svg")
    return ext


def plot_run(log, out_path, events=None, title=None, labels=None, dpi=100, prefix="KINCTL_", shapes=(),
             progress=False, model=None, model_file=None, zones_file=None, zones=(), volumes=False):
    """Writes the figure (PNG or SVG by out_path's extension). log: a path
    (CSV or LCM log) or columns as logcsv.read gives them. labels: {goal_id:
    text} for the goal markers (default "goal <id>"). model / model_file: the
    arm, for the planner's leading joint of joint moves (leading_joints).
    Returns {"rows", "joints", "period_s", "out", "goals": [ids in order],
    "leading": {id: joint}, "leading_how": {id: "planner" or "travel"},
    "max_speed", "zones" (the zones' geometry), "volumes" ([start, end]
    volumes' geometry, or []), "axes": [{"title", "name", "xlabel", "ylabel",
    "xlim", "ylim", "lines", "curves" (labelled lines), "data" (each line's x, y (, z) arrays)}...] in
    the order q, qd, qdd, 3-D path, XY, XZ, YZ, speed, jerk}, "jerk_limits" (each joint's qddd_max
    from the model, or None without one), "max_jerk" (the largest |jerk| of each joint)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.gridspec import GridSpec
    from kinctl.msgs import STATES
    from kinctl import shapes as shp

    check_output(out_path)
    if isinstance(log, dict):
        cols, ev = log, events or []
    else:
        cols, ev = runlog.read_run(log, events, prefix=prefix, progress=progress)
        if isinstance(events, list):
            ev = events
    rows = len(cols["cycle"])
    if rows < 2:
        raise ValueError(f"{log if isinstance(log, str) else 'the log'}: fewer than 2 setpoints to plot")
    n = sum(1 for k in cols if k.startswith("qd") and not k.startswith("qdd"))
    t, dt = runlog.trajectory_time(cols)
    labels = dict(labels or {})
    segs = _segments(cols["goal_id"])
    outcome = {}
    for e in ev:
        if e["event"] in ("COMPLETED", "PREEMPTED", "ABORTED", "FAULT"):
            outcome[e["goal_id"]] = e["event"].lower()
    lead_how = leading_joints(cols, n, segs, model, model_file)
    leading = {gid: j for gid, (j, _) in lead_how.items()}

    fig = plt.figure(figsize=(18, 14.5), dpi=dpi)
    gs = GridSpec(5, 4, figure=fig, width_ratios=[1.3, 1.3, 1, 1], hspace=0.38, wspace=0.3,
                  left=0.045, right=0.985, top=0.92, bottom=0.045)
    axq = fig.add_subplot(gs[0, :2])
    axqd = fig.add_subplot(gs[1, :2], sharex=axq)
    axqdd = fig.add_subplot(gs[2, :2], sharex=axq)
    axj = fig.add_subplot(gs[3, :2], sharex=axq)
    axv = fig.add_subplot(gs[4, :2], sharex=axq)
    ax3 = fig.add_subplot(gs[0:3, 2:], projection="3d")
    axxy = fig.add_subplot(gs[3, 2])
    axxz = fig.add_subplot(gs[3, 3])
    axyz = fig.add_subplot(gs[4, 2])
    axkey = fig.add_subplot(gs[4, 3])
    joint_colors = plt.get_cmap("tab10").colors
    seg_colors = plt.get_cmap("Dark2").colors

    def seg_label(k, gid):
        lab = labels.get(gid, f"goal {gid}")
        if gid in outcome and outcome[gid] != "completed":
            lab += f" ({outcome[gid]})"
        return lab

    for ax, key, name, unit in ((axq, "q", "position q", "rad"),
                                (axqd, "qd", "velocity qd", "rad/s"),
                                (axqdd, "qdd", "acceleration qdd", "rad/s²")):
        for j in range(1, n + 1):
            ax.plot(t, cols[f"{key}{j}"], lw=1.1, color=joint_colors[(j - 1) % 10], label=f"{key}{j}")
        # Each goal's leading joint, bold over its span.
        for a, b, gid in segs:
            j = leading[gid]
            if j:
                ax.plot(t[a:b], cols[f"{key}{j}"][a:b], lw=3.2, alpha=0.45, color=joint_colors[(j - 1) % 10],
                        solid_capstyle="butt")
        ax.set_ylabel(f"{name} ({unit})")
        ax.grid(True, alpha=0.3)
        for state, colour in SHADE.items():
            for a, b in _spans(cols["state"], STATES.get(state, -99)):
                ax.axvspan(t[a], t[b], color=colour, alpha=0.6, lw=0, zorder=0)
        for a, _, _ in segs:
            ax.axvline(t[a], color="0.35", ls="--", lw=0.8, zorder=1)
        ax.legend(loc="upper right", ncol=n, fontsize=8, framealpha=0.8, handlelength=1.2)
    hows = {how for _, how in lead_how.values()}
    axq.plot([], [], color="0.4", lw=3.2, alpha=0.45,
             label="leading joint" + (" (travels farthest)" if hows == {"travel"} else ""))
    axq.legend(loc="upper right", ncol=n + 1, fontsize=8, framealpha=0.8, handlelength=1.2)
    # Goal names above the q panel, at their start, in three staggered rows.
    for k, (a, b, gid) in enumerate(segs):
        text = seg_label(k, gid) + (f" · lead q{leading[gid]}" if leading[gid] else "")
        axq.annotate(text, xy=(t[a], 1.0), xycoords=("data", "axes fraction"),
                     xytext=(2, 3 + 12 * (k % 3)), textcoords="offset points", ha="left", va="bottom",
                     fontsize=8.5, color=seg_colors[k % len(seg_colors)], fontweight="bold")
    for state, colour in SHADE.items():
        if _spans(cols["state"], STATES.get(state, -99)):
            axqd.plot([], [], color=colour, lw=8, label=state.lower())
    axqd.legend(loc="upper right", ncol=n + 2, fontsize=8, framealpha=0.8, handlelength=1.2)

    # Jerk: the change of the logged qdd per setpoint over its time step,
    # with each joint's limit dashed (from the model). Beyond 1.3 times the
    # largest limit (a trapezoid's steps, an e-stop) the panel is clipped.
    import numpy as np
    tt = np.asarray(t, dtype=float)
    step = np.diff(tt)
    step[step <= 0.0] = np.nan
    limits = [None] * n
    if model or model_file:
        from kinctl.kinematics import jerk_limits
        limits = jerk_limits(n, model, model_file)
    max_jerk = []
    for j in range(1, n + 1):
        jerk = np.diff(np.asarray(cols[f"qdd{j}"], dtype=float)) / step
        max_jerk.append(float(np.nanmax(np.abs(jerk))) if len(jerk) else 0.0)
        colour = joint_colors[(j - 1) % 10]
        axj.plot(tt[1:], jerk, lw=1.0, color=colour, label=f"jerk{j}")
        if limits[j - 1]:
            for sign in (1.0, -1.0):
                axj.axhline(sign * limits[j - 1], color=colour, ls=":", lw=1.0, alpha=0.9)
    known = [v for v in limits if v]
    if known:
        axj.plot([], [], color="0.3", ls=":", lw=1.0, label="±qddd_max")
        top = 1.3 * max(known)
        if max(max_jerk) > top:
            axj.set_ylim(-top, top)
            axj.set_title(f"jerk beyond the panel (up to {max(max_jerk):.3g}): acceleration steps", loc="right",
                          fontsize=9, color="0.35")
    axj.set_ylabel("jerk Δqdd/Δt (rad/s³)")
    axj.grid(True, alpha=0.3)
    for state, colour in SHADE.items():
        for a, b in _spans(cols["state"], STATES.get(state, -99)):
            axj.axvspan(t[a], t[b], color=colour, alpha=0.6, lw=0, zorder=0)
    for a, _, _ in segs:
        axj.axvline(t[a], color="0.35", ls="--", lw=0.8, zorder=1)
    axj.legend(loc="upper right", ncol=n + 1, fontsize=8, framealpha=0.8, handlelength=1.2)

    # Speed along the path, one colour per goal; idle parts grey.
    x, y, z = cols["x"], cols["y"], cols["z"]
    speed = tool_speed(t, x, y, z)
    axv.plot(t, speed, color="0.7", lw=0.9)
    for k, (a, b, gid) in enumerate(segs):
        axv.plot(t[a:b], speed[a:b], color=seg_colors[k % len(seg_colors)], lw=1.6, label=seg_label(k, gid))
    for a, _, _ in segs:
        axv.axvline(t[a], color="0.35", ls="--", lw=0.8, zorder=1)
    axv.set_ylabel("tool speed (m/s)")
    axv.set_xlabel("time (s)")
    axv.grid(True, alpha=0.3)
    axv.set_title("speed along the tool path", loc="left", fontsize=10)
    for ax in (axq, axqd, axqdd, axj):
        for lab in ax.get_xticklabels():
            lab.set_visible(False)

    # Tool path, one colour per goal; idle parts grey.
    coord = {"x": x, "y": y, "z": z}
    ax3.plot(x, y, z, color="0.75", lw=0.8)
    planes = ((axxy,) + PLANES[0], (axxz,) + PLANES[1], (axyz,) + PLANES[2])
    for axp, un, vn, what in planes:
        axp.plot(coord[un], coord[vn], color="0.75", lw=0.8)
        axp.set_xlabel(f"{un} (m)")
        axp.set_ylabel(f"{vn} (m)")
        axp.set_aspect("equal", adjustable="datalim")
        axp.grid(True, alpha=0.3)
        axp.set_title(f"tool path, {what}", loc="left", fontsize=10)
    for k, (a, b, gid) in enumerate(segs):
        col = seg_colors[k % len(seg_colors)]
        ax3.plot(x[a:b], y[a:b], z[a:b], color=col, lw=1.8)
        for axp, un, vn, _ in planes:
            axp.plot(coord[un][a:b], coord[vn][a:b], color=col, lw=1.8,
                     label=seg_label(k, gid) if axp is axxy else None)
    # Start (circle) and end (square).
    for i, marker in ((0, "o"), (-1, "s")):
        ax3.plot([x[i]], [y[i]], [z[i]], marker=marker, color="k", ms=4, ls="")
        for axp, un, vn, _ in planes:
            axp.plot([coord[un][i]], [coord[vn][i]], marker=marker, color="k", ms=4, ls="")
    zone_geo, vol_geo, extra = _zones_and_volumes(cols, n, x, y, z, model, model_file, zones_file, zones, volumes)
    for s in list(shapes) + extra:
        shp.draw3d(ax3, s)
        for axp, un, vn, _ in planes:
            shp.draw_plane(axp, s, "xyz".index(un), "xyz".index(vn))
    ax3.set_title("tool path (● start, ■ end)", loc="left", fontsize=11)
    ax3.set_xlabel("x (m)")
    ax3.set_ylabel("y (m)")
    ax3.set_zlabel("z (m)")
    ax3.tick_params(labelsize=7)
    # The goals' key, in the fourth slot beside the YZ view.
    axkey.axis("off")
    handles, texts = axxy.get_legend_handles_labels()
    if handles:
        axkey.legend(handles, texts, loc="center", fontsize=9, framealpha=0.9,
                     title="goals (goal_id)" + (", zones, volumes" if extra else ""),
                     ncol=1 if len(handles) <= 8 else 2)
    fig.suptitle(title or f"kinctld setpoints: {rows} cycles of {dt * 1e3:g} ms", fontsize=13)
    fig.savefig(out_path, dpi=dpi)

    axes = []
    for ax in (axq, axqd, axqdd, ax3, axxy, axxz, axyz, axv, axj):
        axes.append({"title": ax.get_title(loc="left"), "name": ax.name, "xlabel": ax.get_xlabel(),
                     "ylabel": ax.get_ylabel(), "xlim": tuple(ax.get_xlim()), "ylim": tuple(ax.get_ylim()),
                     "lines": len(ax.get_lines()),
                     "curves": [ln.get_label() for ln in ax.get_lines() if not ln.get_label().startswith("_")],
                     # matplotlib's own arrays (no copies).
                     "data": [ln.get_data_3d() if ax.name == "3d"
                              else (ln.get_xdata(orig=True), ln.get_ydata(orig=True)) for ln in ax.get_lines()]})
    plt.close(fig)
    return {"rows": rows, "joints": n, "png": out_path, "out": out_path, "axes": axes,
            "goals": [g for _, _, g in segs], "leading": leading,
            "leading_how": {gid: how for gid, (_, how) in lead_how.items()}, "period_s": dt,
            "max_speed": float(max(speed)), "zones": zone_geo, "volumes": vol_geo,
            "jerk_limits": limits, "max_jerk": max_jerk}


def _zones_and_volumes(cols, n, x, y, z, model, model_file, zones_file, zones, volumes):
    """(zones' geometry, [start, end] volumes' geometry, kinctl.shapes to draw):
    the zones, half-spaces clipped to a box around the path, the volumes and
    the other zones; the volumes only with the arm's model."""
    import numpy as np
    from kinctl import zonedraw as zd
    vols = []
    if (model or model_file) and volumes:
        ends = [[cols[f"q{j}"][i] for j in range(1, n + 1)] for i in (0, -1)]
        geos = [zd.geometry(model, model_file, q, zones_file, zones) for q in ends]
        zone_geo = geos[0]["zones"]
        vols = [g["volumes"] for g in geos]
    else:
        zone_geo = zd.zones_only(zones_file, zones)
    if not zone_geo and not any(vols):
        return zone_geo, vols, []
    pts = [np.column_stack([x, y, z]), zd.bounded_points(zone_geo)] + [zd.bounded_points(v) for v in vols]
    pts = np.vstack(pts)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.1 * float(max(hi - lo)) + 0.05
    out = zd.zone_shapes(zone_geo, (lo - pad, hi + pad))
    for v, (what, alpha) in zip(vols, (("link volumes at the start", 0.45), ("link volumes at the end", 0.85))):
        out += zd.volume_shapes(v, label=what, alpha=alpha)
    return zone_geo, vols, out
