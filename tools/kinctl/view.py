"""`kinctl view`: the arm's skeleton and every link frame, drawn from kinctld's
setpoints, in seed 001 lab 3's three projections (frontal dimetric,
horizontal isometric, orthographic; kinctl.projection) and a free 3-D view.

Live, a matplotlib window follows <prefix>SETPOINT on LCM. With --save the
same picture goes to a file without a display (Agg): FILE.png a still,
FILE.gif (pillow) or FILE.mp4 (ffmpeg) an animation of --duration seconds of
live setpoints, or of a recorded log (--log, a CSV or an LCM event log).

The frames come from the core's forward kinematics through kinctl-calc
(kinctl.kinematics): --model / --model-file must name the daemon's arm; a
tool position that disagrees with the setpoint's is reported.

    from kinctl import logcsv
    from kinctl.kinematics import ArmFK
    from kinctl.view import render, samples_from_columns
    with ArmFK(model="puma560") as fk:
        info = render(samples_from_columns(logcsv.read("run.csv"), fps=25), "arm.gif", fk)

Extra 3-D geometry (kinctl.shapes) is drawn in every panel: render(...,
shapes=[...]). Forbidden zones (--zones-file, --zone) are drawn where they
are, the arm's link volumes (whenever --model or --model-file names it)
moving with it (kinctl.zonedraw): render(..., zones=..., volumes=...).
"""
import math
import os
import sys
import time

from kinctl.argtypes import add_command, nonneg, positive, say

SAVE_FORMATS = (".png", ".gif", ".mp4")
PANELS = ("frontal_dimetric", "horizontal_isometric", "orthographic", "3d")
AXIS_COLORS = ("#d62728", "#2ca02c", "#1f77b4")  # x red, y green, z blue
EXAMPLE = ("kinctl view                                  # live window (needs a display)\n"
           "  kinctl view --save arm.gif --duration 5        # headless: 5 s of live setpoints\n"
           "  kinctl view --log run.csv --save run.mp4       # a recorded log (CSV or LCM log); mp4 needs ffmpeg\n"
           "  kinctl view --model-file models/panda.cfg --save now.png\n"
           "  kinctl view --model puma560 --zones-file kinctld.cfg --zone sphere:0.5,0.3,0.4,0.1 --save cell.png")


def register(sub, parents):
    """The `view` subcommand on the CLI's subparsers."""
    v = add_command(sub, "view", "draw the arm (skeleton and every link frame) from its setpoints: frontal "
                                 "dimetric, horizontal isometric, orthographic and 3-D views, live or saved",
                    EXAMPLE, parents)
    m = v.add_mutually_exclusive_group()
    m.add_argument("--model", default=None, metavar="NAME",
                   help="the daemon's built-in arm (default puma560, kinctld's default): puma560, panda, rrr3, "
                        "planar2, rb211, rm01")
    m.add_argument("--model-file", default=None, metavar="PATH", help="the daemon's robot description file")
    v.add_argument("--log", default=None, metavar="FILE",
                   help="draw a recorded log (setpoint CSV of kinctl log, or LCM event log) instead of live LCM")
    v.add_argument("--save", default=None, metavar="FILE",
                   help="write FILE.png (a still: the last setpoint), FILE.gif or FILE.mp4 (an animation; mp4 "
                        "needs ffmpeg, which scripts/setup.sh installs) instead of opening a window")
    v.add_argument("--duration", type=positive, default=None, metavar="S",
                   help="live --save: record S seconds of setpoints (default 5 for .gif/.mp4; .png: the next "
                        "setpoint); with --log: only the first S seconds; a window: close it after S seconds")
    v.add_argument("--fps", type=positive, default=25.0, metavar="N", help="frames per second (default 25)")
    v.add_argument("--trail", type=nonneg, default=3.0, metavar="S",
                   help="seconds of tool path drawn behind the tool (default 3; 0: none)")
    v.add_argument("--dpi", type=positive, default=80.0, help="resolution of saved files (default 80)")
    from kinctl.zonedraw import add_options
    add_options(v)
    v.set_defaults(run=cmd_view)


def check_save(path):
    ext = os.path.splitext(path)[1].lower()
    if ext not in SAVE_FORMATS:
        raise ValueError(f"--save {path}: the extension picks the format: .png (a still), .gif or .mp4")
    if ext == ".mp4":
        from matplotlib import animation
        if not animation.writers.is_available("ffmpeg"):
            raise ValueError(f"--save {path}: writing .mp4 needs ffmpeg (Debian package ffmpeg, which "
                             f"scripts/setup.sh installs); or save a .gif")
    return ext


# -- samples -----------------------------------------------------------------

class Sample:
    """One drawn instant: t (s from the first), the setpoint's cycle, goal_id,
    state (code), q and the daemon's tool position."""
    __slots__ = ("t", "cycle", "goal_id", "state", "q", "tool")

    def __init__(self, t, cycle, goal_id, state, q, tool):
        self.t, self.cycle, self.goal_id, self.state, self.q, self.tool = t, cycle, goal_id, state, q, tool


def samples_from_columns(cols, fps, duration=None):
    """Samples of a log (logcsv columns) for frames every 1/fps s of
    trajectory time (runlog.trajectory_time) up to the end or duration: each
    the latest setpoint at or before the frame's time, so that setpoints a
    logger lost do not change the pace (their frames repeat the one before);
    without duration the last setpoint is always included."""
    from kinctl.runlog import trajectory_time
    rows = len(cols["cycle"])
    if rows == 0:
        raise ValueError("the log holds no setpoints")
    n = sum(1 for k in cols if k.startswith("qd") and not k.startswith("qdd"))
    times, _ = trajectory_time(cols)
    end = times[-1] if duration is None else min(times[-1], duration)

    def sample(i):
        return Sample(times[i], cols["cycle"][i], cols["goal_id"][i], cols["state"][i],
                      [cols[f"q{j}"][i] for j in range(1, n + 1)], (cols["x"][i], cols["y"][i], cols["z"][i]))
    out, i = [], 0
    for k in range(int(math.floor(end * fps + 1e-6)) + 1):
        t = k / fps
        while i + 1 < rows and times[i + 1] <= t + 1e-9:
            i += 1
        out.append(sample(i))
    if duration is None and i < rows - 1:
        out.append(sample(rows - 1))
    return out


# -- the scene ---------------------------------------------------------------

def skeleton_points(pose):
    """Base origin, every frame's origin, tool origin: (m + 2) x 3."""
    import numpy as np
    base, frames, tool = pose
    return np.array([base[:3, 3]] + [f[:3, 3] for f in frames] + [tool[:3, 3]])


def triad_lines(pose, length):
    """For each axis (x, y, z) an array of segments origin -> origin + length * axis
    of the base, every frame and the tool, NaN rows between: 3 arrays of (3k - 1) x 3."""
    import numpy as np
    base, frames, tool = pose
    out = []
    for k in range(3):
        rows = []
        for T in [base] + list(frames) + [tool]:
            o = T[:3, 3]
            rows += [o, o + length * T[:3, k], [np.nan] * 3]
        out.append(np.array(rows[:-1], dtype=float))
    return out


class Scene:
    """The four panels and their artists; update(pose, sample, trail) redraws."""

    def __init__(self, fig, bounds, triad, shapes=(), title="", points=None, status_in_axes=False, volumes=None):
        """bounds: (lo, hi) of the 3-D view; points: N x 3 world points every
        frame will stay near (the 2-D views are fitted to their images; by
        default the corners of bounds). status_in_axes: the changing text
        (time, cycle, goal, state, q) in the 3-D panel instead of the figure's
        title, where a live window's blitting redraws it. volumes: the link
        volumes (kinctl.zonedraw.MovingVolumes) drawn at every pose."""
        import numpy as np
        from kinctl import projection as pj
        from kinctl import shapes as shp
        self.fig, self.triad, self.title, self.volumes = fig, triad, title, volumes
        lo, hi = np.asarray(bounds[0], float), np.asarray(bounds[1], float)
        corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]).T
        fit = corners if points is None else np.asarray(points, dtype=float).T
        gs = fig.add_gridspec(2, 2, left=0.065, right=0.98, top=0.9, bottom=0.055, wspace=0.14, hspace=0.2)
        self.panels = {}
        for idx, name in enumerate(PANELS):
            r, c = divmod(idx, 2)
            if name == "3d":
                ax = fig.add_subplot(gs[r, c], projection="3d")
                ax.set_xlim(lo[0], hi[0])
                ax.set_ylim(lo[1], hi[1])
                ax.set_zlim(lo[2], hi[2])
                ax.set_box_aspect(hi - lo)
                ax.set_xlabel("x (m)")
                ax.set_ylabel("y (m)")
                ax.set_zlabel("z (m)")
                ax.tick_params(labelsize=7)
                ax.set_title("3-D (free view)", loc="left", fontsize=10)
                M = None
            else:
                ax = fig.add_subplot(gs[r, c])
                M = pj.matrix(name)
                uv = M @ fit
                # One scale on u and v, the limits widened to the panel's shape so that it is filled.
                pos = ax.get_position()
                w_in, h_in = pos.width * fig.get_figwidth(), pos.height * fig.get_figheight()
                du, dv = max(np.ptp(uv[0]), 1e-3) * 1.1, max(np.ptp(uv[1]), 1e-3) * 1.1
                scale = max(du / w_in, dv / h_in)
                cu, cv = (uv[0].min() + uv[0].max()) / 2, (uv[1].min() + uv[1].max()) / 2
                ax.set_xlim(cu - scale * w_in / 2, cu + scale * w_in / 2)
                ax.set_ylim(cv - scale * h_in / 2, cv + scale * h_in / 2)
                ax.set_aspect("equal", adjustable="box")
                ax.set_xlabel("u (m)")
                ax.set_ylabel("v (m)")
                ax.grid(True, alpha=0.25)
                ax.tick_params(labelsize=7)
                ax.set_title(pj.TITLES[name] + " (seed 001 lab 3)", loc="left", fontsize=10)
            p = {"ax": ax, "M": M}
            p["trail"] = self._line(ax, M, color="0.55", lw=1.0, ls="-", label="tool path")
            p["skeleton"] = self._line(ax, M, color="0.15", lw=2.6, marker="o", ms=4, mfc="#ffb000",
                                       mec="0.15", label="links")
            p["triads"] = [self._line(ax, M, color=col, lw=1.4, label=f"{a} axes")
                           for a, col in zip("xyz", AXIS_COLORS)]
            if volumes is not None:
                from kinctl.zonedraw import VOLUME_COLOR
                p["volumes"] = self._line(ax, M, color=VOLUME_COLOR, lw=0.8, alpha=0.7, label="link volumes")
            for s in shapes:
                if M is None:
                    shp.draw3d(ax, s)
                else:
                    shp.draw_projected(ax, s, M)
            self.panels[name] = p
        self.panels["frontal_dimetric"]["ax"].legend(loc="upper left", fontsize=7.5, framealpha=0.8, ncol=1)
        self.status_in_axes = status_in_axes
        if status_in_axes:
            fig.suptitle(title, fontsize=12)
            self.text = self.panels["3d"]["ax"].text2D(0.0, 1.0, "", transform=self.panels["3d"]["ax"].transAxes,
                                                      ha="left", va="top", fontsize=8, family="monospace")
        else:
            self.text = fig.suptitle(title, fontsize=12)

    @staticmethod
    def _line(ax, M, **kw):
        if M is None:
            return ax.plot([], [], [], **kw)[0]
        return ax.plot([], [], **kw)[0]

    @staticmethod
    def _set(line, M, pts):
        """pts: N x 3 (world, m)."""
        import numpy as np
        pts = np.asarray(pts, dtype=float).reshape(-1, 3)
        if M is None:
            line.set_data_3d(pts[:, 0], pts[:, 1], pts[:, 2])
        else:
            uv = M @ pts.T
            line.set_data(uv[0], uv[1])

    def moving_artists(self):
        """What update() changes: every panel's lines and the title."""
        out = []
        for p in self.panels.values():
            out += [p["trail"], p["skeleton"]] + p["triads"] + ([p["volumes"]] if "volumes" in p else [])
        return out + [self.text]

    def update(self, pose, sample, trail_pts):
        from kinctl.msgs import state_name
        skel = skeleton_points(pose)
        triads = triad_lines(pose, self.triad)
        artists = []
        vol = self.volumes.points(pose[1]) if self.volumes is not None else None
        for p in self.panels.values():
            if vol is not None:
                self._set(p["volumes"], p["M"], vol)
                artists.append(p["volumes"])
            self._set(p["skeleton"], p["M"], skel)
            for line, pts in zip(p["triads"], triads):
                self._set(line, p["M"], pts)
            self._set(p["trail"], p["M"], trail_pts if len(trail_pts) else [[float("nan")] * 3])
            artists += [p["skeleton"], p["trail"]] + p["triads"]
        q = ", ".join(f"{v:+.3f}" for v in sample.q)
        if self.status_in_axes:
            self.text.set_text(f"t = {sample.t:.2f} s  cycle {sample.cycle}\n"
                               f"goal {sample.goal_id or '-'}  {state_name(sample.state)}\n"
                               f"q = [{q.replace(', ', ',')}]")
        else:
            self.text.set_text(f"{self.title}t = {sample.t:6.2f} s   cycle {sample.cycle}   "
                               f"goal {sample.goal_id or '-'}   {state_name(sample.state)}\nq = [{q}]")
        return artists + [self.text]


def bounds_of(poses, margin=0.08, extra=None):
    """A cube around every drawn point (lo, hi) (the arm's, and extra: N x 3),
    padded: every panel keeps one scale on all three axes."""
    import numpy as np
    pts = np.vstack([skeleton_points(p) for p in poses] + ([np.asarray(extra)] if extra is not None else []))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    half = (float(max(hi - lo)) or 1.0) * (0.5 + margin)
    mid = (lo + hi) / 2
    return mid - half, mid + half


def reach_space(pose0):
    """For a live window, where the poses to come are unknown: the points the
    arm can reach at most, a sphere around its first frame (the shoulder of
    most arms) as large as the links beyond it stretched out, and the base.
    Returns (bounds (lo, hi) of a cube holding them, the points: N x 3)."""
    import numpy as np
    skel = skeleton_points(pose0)
    centre = skel[1] if len(skel) > 2 else skel[0]
    reach = float(np.sum(np.linalg.norm(np.diff(skel[1:], axis=0), axis=1))) or 1.0
    dirs = np.array([[x, y, z] for x in (-1, 0, 1) for y in (-1, 0, 1) for z in (-1, 0, 1) if (x, y, z) != (0, 0, 0)],
                    dtype=float)
    pts = np.vstack([centre + reach * dirs / np.linalg.norm(dirs, axis=1)[:, None], skel[:1]])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    mid, half = (lo + hi) / 2, float(max(hi - lo)) / 2 * 1.05
    return (mid - half, mid + half), pts


def triad_length(pose0):
    import numpy as np
    skel = skeleton_points(pose0)
    reach = float(np.sum(np.linalg.norm(np.diff(skel, axis=0), axis=1))) or 1.0
    return 0.07 * reach


def trail_of(samples, i, seconds):
    import numpy as np
    if seconds <= 0:
        return np.zeros((0, 3))
    t = samples[i].t
    return np.array([s.tool for s in samples[: i + 1] if s.t >= t - seconds - 1e-9])


def fk_mismatch(poses, samples):
    """Largest distance (m) between the FK tool position and the setpoints' own."""
    import numpy as np
    return max(float(np.linalg.norm(p[2][:3, 3] - np.asarray(s.tool))) for p, s in zip(poses, samples))


def render(samples, path, fk, fps=25.0, trail=3.0, dpi=80, shapes=(), title="", progress=False, zones=(),
           volumes=None):
    """Draws samples to path (.png: the last sample; .gif, .mp4: all of them at
    fps). zones: forbidden zones as kinctl.zonedraw.geometry gives them
    (a half-space clipped to the view); volumes: the link volumes
    (zonedraw.MovingVolumes) drawn at every sample. Returns {"frames", "size",
    "fk_mismatch_m", "bounds", "panels": {name: {"title", "xlim", "ylim",
    "skeleton", "triads", "trail", "volumes", "zones"}}} with the last frame's
    drawn data (u, v, or x, y, z per line; "zones": every zone's polylines,
    projected)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from kinctl.progress import bar

    ext = check_save(path)
    if not samples:
        raise ValueError("nothing to draw: no setpoints")
    todo = samples[-1:] if ext == ".png" else samples
    poses = fk.frames_many([s.q for s in todo], progress=progress)
    mismatch = fk_mismatch(poses, todo)
    fig = plt.figure(figsize=(12, 9.5), dpi=dpi)
    triad = triad_length(poses[0])
    # The 2-D views fit what is drawn: links, triads (a triad's reach around each joint) and the trail.
    pts = [skeleton_points(p) for p in poses] + [np.array([s.tool for s in samples])]
    pts = np.vstack(pts)
    cube = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * triad
    pts = np.vstack([pts + d for d in cube])
    bounds = bounds_of(poses)
    zone_shapes = []
    if zones or volumes is not None:
        from kinctl import zonedraw as zd
        extra = [zd.bounded_points(zones)]
        if volumes is not None:
            extra += [zd.joined(volumes.lines(p[1])) for p in (poses[0], poses[-1])]
        extra = np.vstack(extra)
        extra = extra[np.isfinite(extra).all(axis=1)]
        if len(extra):
            pts = np.vstack([pts, extra])
            bounds = bounds_of(poses, extra=extra)
        zone_shapes = zd.zone_shapes(zones, bounds)
    scene = Scene(fig, bounds, triad, list(shapes) + zone_shapes, title, points=pts, volumes=volumes)
    offset = len(samples) - len(todo)

    def frame(k):
        return scene.update(poses[k], todo[k], trail_of(samples, offset + k, trail))

    if ext == ".png":
        frame(0)
        fig.savefig(path, dpi=dpi)
        count = 1
    else:
        # Blitting: the axes, ticks and texts are drawn once; each frame redraws only what
        # moves onto a copy of that background (several times faster than a full draw).
        moving = scene.moving_artists()
        for a in moving:
            a.set_animated(True)
        fig.canvas.draw()
        background = fig.canvas.copy_from_bbox(fig.bbox)

        def image(k):
            frame(k)
            fig.canvas.restore_region(background)
            for a in moving:
                (a.axes or fig).draw_artist(a)
            return np.asarray(fig.canvas.buffer_rgba())

        with bar(len(todo), f"writing {os.path.basename(path)}", unit="frame", show=progress) as b:
            write_frames(path, ext, fps, len(todo), image, b.update)
        for a in moving:
            a.set_animated(False)
        count = len(todo)
    info = {"frames": count, "size": tuple(int(v) for v in fig.get_size_inches() * dpi),
            "fk_mismatch_m": mismatch, "bounds": bounds, "panels": {}}
    for name, p in scene.panels.items():
        ax = p["ax"]

        def data(line):
            if p["M"] is None:
                return [list(v) for v in line.get_data_3d()]
            return [list(v) for v in line.get_data()]
        info["panels"][name] = {"title": ax.get_title(loc="left"), "xlim": tuple(ax.get_xlim()),
                                "ylim": tuple(ax.get_ylim()), "skeleton": data(p["skeleton"]),
                                "triads": [data(t) for t in p["triads"]], "trail": data(p["trail"]),
                                "lines": len(ax.get_lines()),
                                "volumes": data(p["volumes"]) if "volumes" in p else None,
                                "zones": [[_projected(l, p["M"]) for l in z.lines()] for z in zone_shapes]}
        if p["M"] is None:
            info["panels"][name]["zlim"] = tuple(ax.get_zlim())
    plt.close(fig)
    return info


def _projected(pts, M):
    """A polyline as a panel draws it: u, v rows (M) or x, y, z rows (3-D)."""
    import numpy as np
    return np.asarray(pts).T if M is None else np.asarray(M) @ np.asarray(pts).T


def write_frames(path, ext, fps, count, image, advance):
    """Writes count frames, image(k) an H x W x 4 RGBA array, as a GIF
    (pillow, every frame quantised to its own palette) or an H.264 MP4
    (ffmpeg reading raw frames on a pipe); advance(1) after each."""
    import numpy as np
    if ext == ".gif":
        from PIL import Image
        frames = []
        for k in range(count):
            frames.append(Image.fromarray(np.ascontiguousarray(image(k)[:, :, :3])).quantize(
                colors=256, method=Image.Quantize.FASTOCTREE))
            advance(1)
        frames[0].save(path, save_all=True, append_images=frames[1:], duration=int(round(1000.0 / fps)),
                       loop=0)
        return
    import shutil
    import subprocess
    ffmpeg = shutil.which("ffmpeg")
    first = image(0)
    h, w = first.shape[:2]
    argv = [ffmpeg, "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgba", "-s", f"{w}x{h}",
            "-r", f"{fps:g}", "-i", "-", "-c:v", "libx264", "-pix_fmt", "yuv420p", path]
    p = subprocess.Popen(argv, stdin=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        for k in range(count):
            p.stdin.write((first if k == 0 else image(k)).tobytes())
            advance(1)
        p.stdin.close()
    except BrokenPipeError:
        pass
    err = p.stderr.read().decode(errors="replace")
    if p.wait() != 0:
        raise RuntimeError(f"ffmpeg could not write {path}: {err.strip()}")


# -- the command -------------------------------------------------------------

def _warn_mismatch(m, fk):
    """A warning when the drawn tool is m (m) from where the daemon says it is."""
    if m > 1e-6:
        print(f"kinctl view: warning: the drawn tool is {m * 1e3:.3g} mm from the setpoints' tool position: "
              f"the daemon runs another arm than {fk.describe()}? pass its --model or --model-file",
              file=sys.stderr, flush=True)


def record(args, seconds):
    """Setpoints of the daemon spanning `seconds` of trajectory time (cycles
    times the period, as runlog.trajectory_time counts it; a cycle the daemon
    skipped under load is not time the arm moved), or the next one when
    seconds is 0, as logcsv columns."""
    from kinctl.client import Client, DaemonNotFound
    from kinctl.progress import bar
    from kinctl.runlog import setpoint_columns
    got = []
    with Client(url=args.lcm_url, prefix=args.prefix, on_setpoint=got.append) as c:
        c.wait_daemon(args.connect_timeout)
        start = len(got)
        deadline = time.monotonic() + 2 * seconds + args.connect_timeout + 5.0
        period = {}

        def span():
            """Trajectory time from the first recorded setpoint to the last (s)."""
            if len(got) <= start:
                return -1.0
            if "dt" not in period:
                steps = [b.utime - a.utime for a, b in zip(got[start:start + 50], got[start + 1:start + 51])
                         if b.cycle == a.cycle + 1 and b.utime > a.utime]
                if len(steps) < 10 and len(got) - start < 51:
                    return -1.0 if seconds > 0 else 0.0
                import statistics
                period["dt"] = statistics.median(steps) / 1e6 if steps else 1e-3
            return (got[-1].cycle - got[start].cycle) * period["dt"]

        def spanned():
            return span() >= seconds - 1e-9
        with bar(seconds, "recording setpoints", unit="s", show=seconds >= 1.0,
                 bar_format="{desc}: {bar} {n:.1f}/{total:.1f} s") as b:
            while not spanned():
                if time.monotonic() > deadline:
                    raise DaemonNotFound(f"the setpoints stopped coming after {len(got) - start} of them: "
                                       f"did kinctld stop? (kinctl status)")
                time.sleep(0.05)
                b.n = min(seconds, max(0.0, span()))
                b.refresh()
        sps = got[start:]
    return setpoint_columns(sps)


def zones_of(args, fk, q):
    """The zones and the moving link volumes the options ask for (the volumes
    whenever --model or --model-file names the arm, unless --no-volumes)."""
    from kinctl.zonedraw import for_arm
    return for_arm(fk, q, args.zones_file, args.zone,
                   volumes=bool(args.model or args.model_file) and not args.no_volumes)


def cmd_view(args):
    from kinctl.kinematics import ArmFK
    ext = check_save(args.save) if args.save else None
    if args.log and not args.save:
        raise ValueError("--log draws to a file: add --save FILE.gif, .mp4 or .png (to watch an LCM log in "
                         "the window, play it with lcm-logplayer and run kinctl view)")
    with ArmFK(model=args.model, model_file=args.model_file) as fk:
        # Bad --zone or --zones-file: exit 2 before anything is recorded.
        zones_of(args, fk, [0.0] * fk.n_joints)
        if args.log:
            from kinctl.runlog import read_run
            cols, _ = read_run(args.log, prefix=args.prefix, progress=True)
            title = f"{os.path.basename(args.log)}: "
        elif args.save:
            seconds = args.duration if args.duration is not None else (5.0 if ext != ".png" else 0.0)
            cols = record(args, seconds)
            title = f"kinctld ({fk.describe().lstrip('-')}): "
        else:
            return live(args, fk)
        samples = samples_from_columns(cols, args.fps, args.duration)
        if len(samples[0].q) != fk.n_joints:
            raise ValueError(f"the setpoints have {len(samples[0].q)} joints, {fk.describe()} has {fk.n_joints}: "
                             f"pass the daemon's --model or --model-file")
        zones, volumes = zones_of(args, fk, samples[0].q)
        info = render(samples, args.save, fk, fps=args.fps, trail=args.trail, dpi=args.dpi, title=title,
                      progress=True, zones=zones, volumes=volumes)
        _warn_mismatch(info["fk_mismatch_m"], fk)
        if info["frames"] == 1:
            say(f"view: {args.save} (1 frame, {info['size'][0]}x{info['size'][1]}, the setpoint of cycle "
                f"{samples[-1].cycle})")
        else:
            say(f"view: {args.save} ({info['frames']} frames, {info['size'][0]}x{info['size'][1]}, "
                f"{samples[-1].t - samples[0].t:.2f} s of setpoints)")
    return 0


def live(args, fk):
    """A window following the daemon's setpoints until it is closed."""
    import matplotlib
    if not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY") and sys.platform != "darwin":
        raise ValueError("no display for a window ($DISPLAY is not set): save to a file instead, e.g. "
                         "kinctl view --save arm.gif --duration 5")
    import matplotlib.pyplot as plt
    if matplotlib.get_backend().lower() == "agg":
        raise ValueError("matplotlib has no interactive backend here (install python3-tk or PyQt), or use "
                         "--save arm.gif")
    from matplotlib import animation
    from kinctl.client import Client

    with Client(url=args.lcm_url, prefix=args.prefix) as c:
        sp = c.wait_daemon(args.connect_timeout)
        if sp.n != fk.n_joints:
            raise ValueError(f"the daemon's setpoints have {sp.n} joints, {fk.describe()} has {fk.n_joints}: "
                             f"pass the daemon's --model or --model-file")
        pose0 = fk.frames(list(sp.q[:sp.n]))
        fig = plt.figure(figsize=(12, 9.5))
        bounds, reachable = reach_space(pose0)
        zones, volumes = zones_of(args, fk, list(sp.q[:sp.n]))
        from kinctl.zonedraw import zone_shapes
        scene = Scene(fig, bounds, triad_length(pose0), zone_shapes(zones, bounds),
                      f"kinctld live ({fk.describe().lstrip('-')})", points=reachable, status_in_axes=True,
                      volumes=volumes)
        history = []
        state = {"last_cycle": None, "warned": False, "drawn": 0}

        def frame(_):
            s = c.setpoint
            if s is None or s.cycle == state["last_cycle"]:
                return []
            state["last_cycle"] = s.cycle
            # Live, time is the daemon's clock at the cycle (utime).
            smp = Sample((s.utime - sp.utime) / 1e6, s.cycle, s.goal_id, s.state, list(s.q[:s.n]),
                         tuple(s.position))
            history.append(smp)
            while history and history[0].t < smp.t - args.trail - 1.0:
                history.pop(0)
            pose = fk.frames(smp.q)
            if not state["warned"]:
                import numpy as np
                _warn_mismatch(float(np.linalg.norm(pose[2][:3, 3] - np.asarray(smp.tool))), fk)
                state["warned"] = True
            state["drawn"] += 1
            return scene.update(pose, smp, trail_of(history, len(history) - 1, args.trail))

        anim = animation.FuncAnimation(fig, frame, interval=1000.0 / args.fps, blit=True,
                                       cache_frame_data=False)
        fig._kinctl_anim = anim  # keep a reference while the window is open
        if args.duration:
            timer = fig.canvas.new_timer(interval=int(args.duration * 1000))
            timer.single_shot = True

            def close():
                anim.event_source.stop()
                plt.close(fig)
            timer.add_callback(close)
            timer.start()
        plt.show()
    say(f"view: window closed after {len(history) and history[-1].t:.2f} s of setpoints, "
        f"{state['drawn']} frames drawn")
    return 0
