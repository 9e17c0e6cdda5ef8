# SPDX-License-Identifier: BSD-3-Clause
"""The arm's skeleton and every link frame, drawn from kinctld's setpoints, in
seed 001 lab 3's three projections (frontal dimetric, horizontal isometric,
orthographic; kinctl.projection) and a free 3-D view: the drawing of
`kinctl view` (kinctl.viewcmd, which follows the daemon live or records it).

Saved without a display (Agg): FILE.png a still, FILE.gif (pillow) or
FILE.mp4 (ffmpeg) an animation; Scene draws the panels, live windows too.

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

SAVE_FORMATS = (".png", ".gif", ".mp4")
PANELS = ("frontal_dimetric", "horizontal_isometric", "orthographic", "3d")
AXIS_COLORS = ("#d62728", "#2ca02c", "#1f77b4")  # x red, y green, z blue


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
                ax.set_title(pj.TITLES[name], loc="left", fontsize=10)
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
