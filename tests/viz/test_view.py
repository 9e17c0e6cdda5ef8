# SPDX-License-Identifier: BSD-3-Clause
"""kinctl view, headless: the arm drawn from a real run's setpoints (a recorded
log and live LCM) to PNG, GIF and MP4, checked against the setpoints."""
import os
import shutil
import signal
import subprocess
import sys

import numpy as np
import pytest

from conftest import Q11, csv_of, goal_columns, live_view_while_moving

from kinctl import logcsv
from kinctl import projection as pj
from kinctl.kinematics import ArmFK
from kinctl.view import render, samples_from_columns
from kinctl_testing import QN, SLOW, run_kinctl

W, H = 960, 760  # 12 x 9.5 in at the default 80 dpi


def quat_to_matrix(w, x, y, z):
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def gif_frames(path):
    from PIL import Image, ImageSequence
    im = Image.open(path)
    return im.size, [np.asarray(f.convert("RGB")) for f in ImageSequence.Iterator(im)]


@pytest.fixture(scope="module")
def logged_view(recorded, tmp_path_factory):
    """render() of the first 2 s of goal 12 (the line) at 10 frames/s."""
    part = goal_columns(recorded, 12)
    samples = samples_from_columns(part, fps=10, duration=2.0)
    path = str(tmp_path_factory.mktemp("view") / "line.gif")
    with ArmFK(model="puma560") as fk:
        info = render(samples, path, fk, fps=10, trail=3.0)
    return info, samples, part, path


def test_samples_every_tenth_of_a_second(logged_view):
    _, samples, part, _ = logged_view
    assert [round(s.t, 9) for s in samples] == [round(0.1 * k, 9) for k in range(21)]
    c0 = part["cycle"][0]
    assert [s.cycle - c0 for s in samples] == [100 * k for k in range(21)]
    assert samples[5].q == [part[f"q{j}"][500] for j in range(1, 7)]
    assert samples[5].tool == (part["x"][500], part["y"][500], part["z"][500])


def test_gif_has_a_frame_per_sample(logged_view):
    info, samples, _, path = logged_view
    assert info["frames"] == len(samples) == 21
    size, frames = gif_frames(path)
    assert size == (W, H) == info["size"] and len(frames) == 21
    # The arm moves along the line: the first and last frames differ.
    assert (frames[0] != frames[-1]).any(axis=2).mean() > 0.002


def test_skeleton_ends_at_the_daemons_tool_in_every_projection(logged_view):
    info, samples, _, _ = logged_view
    last = samples[-1]
    tool = np.array(last.tool)
    assert info["fk_mismatch_m"] < 1e-9
    for name in pj.NAMES:
        p = info["panels"][name]
        u, v = p["skeleton"]
        assert len(u) == 8  # base, puma560's six frames, tool
        uv_tool = pj.matrix(name) @ tool
        assert abs(u[-1] - uv_tool[0]) < 1e-9 and abs(v[-1] - uv_tool[1]) < 1e-9, name
        assert (u[0], v[0]) == (0.0, 0.0)  # the base at the origin
        assert p["xlim"][0] < min(u) and max(u) < p["xlim"][1]
        assert p["ylim"][0] < min(v) and max(v) < p["ylim"][1]
        assert lab3_title(name) in p["title"]
    x, y, z = info["panels"]["3d"]["skeleton"]
    assert np.allclose([x[-1], y[-1], z[-1]], tool, atol=1e-9, rtol=0)
    assert "3-D" in info["panels"]["3d"]["title"]


def lab3_title(name):
    return {"frontal_dimetric": "frontal dimetric", "horizontal_isometric": "horizontal isometric",
            "orthographic": "orthographic"}[name]


def test_triads_show_every_frame_and_the_tool_orientation(logged_view):
    info, samples, part, _ = logged_view
    idx = part["cycle"].index(samples[-1].cycle)
    R = quat_to_matrix(*(part[k][idx] for k in ("qw", "qx", "qy", "qz")))
    triads = info["panels"]["3d"]["triads"]
    lengths = []
    for k in range(3):
        pts = np.array(triads[k]).T  # (3 * 8 - 1) x 3: origin, tip, NaN, ...
        assert pts.shape == (23, 3)
        assert np.isnan(pts[2::3]).all()
        seg = pts[1::3] - pts[0::3]
        lengths += list(np.linalg.norm(seg, axis=1))
        # The tool's triad (the last) points along the setpoint's own orientation.
        assert np.allclose(seg[-1] / np.linalg.norm(seg[-1]), R[:, k], atol=1e-7)
        # The base's triad is the world's axes.
        assert np.allclose(seg[0] / np.linalg.norm(seg[0]), np.eye(3)[k], atol=1e-12)
    assert max(lengths) - min(lengths) < 1e-9
    # In a projection each triad line is the same segments through M.
    u, v = info["panels"]["frontal_dimetric"]["triads"][2]
    pts = np.array(triads[2])
    uv = pj.matrix("frontal_dimetric") @ np.nan_to_num(pts)
    ok = ~np.isnan(pts[0])
    assert np.allclose(np.array(u)[ok], uv[0][ok], atol=1e-12) and np.allclose(np.array(v)[ok], uv[1][ok], atol=1e-12)


def test_trail_is_the_tool_path_so_far(logged_view):
    info, samples, _, _ = logged_view
    x, y, z = info["panels"]["3d"]["trail"]
    assert np.allclose(np.array([x, y, z]).T, [s.tool for s in samples], atol=0)
    # During goal 12 (its first 0.8 s) the line moves the tool along +y only.
    line = np.array([s.tool for s in samples if s.goal_id == 12])
    assert len(line) >= 8
    assert np.ptp(line[:, 0]) < 1e-5 and np.ptp(line[:, 2]) < 1e-5 and line[-1, 1] > line[0, 1] + 0.1


def test_extra_shapes_in_every_panel(recorded, tmp_path):
    from kinctl.shapes import Polyline, box_edges
    cols = logcsv.read(recorded["csv"])
    samples = samples_from_columns(cols, fps=10, duration=0.1)
    with ArmFK() as fk:
        plain = render(samples, str(tmp_path / "a.png"), fk)
        boxed = render(samples, str(tmp_path / "b.png"), fk, shapes=[Polyline(box_edges((0.3, -0.3, 0.0),
                                                                                       (0.5, 0.0, 0.3)))])
    for name in plain["panels"]:
        assert boxed["panels"][name]["lines"] == plain["panels"][name]["lines"] + 12


def start_view(url, *args):
    env = dict(os.environ)
    env.pop("LCM_DEFAULT_URL", None)
    return subprocess.Popen([sys.executable, "-m", "kinctl", "--lcm-url", url, "view"] + list(args),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)


def test_live_gif_while_the_arm_moves(recorded, tmp_path):
    url = recorded["url"]
    out = tmp_path / "live.gif"
    r = run_kinctl(url, "goal", "joint", "--q", csv_of(Q11), "--wait")
    assert r.returncode == 0, r.stderr
    # A slow move (joint 2 by 1 rad at a tenth of its rate limit: over 5 s), under way while the view records.
    r = run_kinctl(url, "goal", "joint", "--q", csv_of(QN), "--speed", "0.1")
    assert r.returncode == 0, r.stderr
    v = start_view(url, "--save", str(out), "--duration", "1.5", "--fps", "10")
    try:
        stdout, stderr = v.communicate(timeout=120 * SLOW)
    finally:
        if v.poll() is None:
            v.kill()
            v.communicate()
        r = run_kinctl(url, "goal", "joint", "--q", csv_of(QN), "--wait")
    assert v.returncode == 0, stderr
    assert "warning" not in stderr, stderr
    size, frames = gif_frames(out)
    # 1.5 s at 10 frames/s: t = 0, 0.1, ..., 1.5.
    assert size == (W, H) and len(frames) == 16
    assert f"{len(frames)} frames" in stdout
    assert (frames[0] != frames[-1]).any(axis=2).mean() > 0.002


def test_live_png_is_the_current_pose(recorded, tmp_path):
    out = tmp_path / "now.png"
    v = start_view(recorded["url"], "--save", str(out))
    stdout, stderr = v.communicate(timeout=60 * SLOW)
    assert v.returncode == 0, stderr
    assert "1 frame," in stdout
    import matplotlib.image
    img = matplotlib.image.imread(str(out))
    assert img.shape[:2] == (H, W)
    assert (img[:, :, :3] < 0.5).any(axis=2).mean() > 0.005  # dark links and text are drawn


def test_gaps_in_a_log_keep_the_pace():
    # Setpoints of cycles 0..999 with 200..599 lost: frames every 0.1 s still, the gap's repeating cycle 199.
    cols = {k: [] for k in logcsv.header(1)}
    for c in list(range(200)) + list(range(600, 1000)):
        for k, v in (("utime", 1000 * c), ("cycle", c), ("goal_id", 1), ("state", 1), ("q1", c * 1e-3),
                     ("qd1", 0.0), ("qdd1", 0.0), ("x", c * 1e-3), ("y", 0.0), ("z", 0.0), ("qw", 1.0),
                     ("qx", 0.0), ("qy", 0.0), ("qz", 0.0)):
            cols[k].append(v)
    s = samples_from_columns(cols, fps=10)
    assert [x.cycle for x in s] == [0, 100, 199, 199, 199, 199, 600, 700, 800, 900, 999]
    assert [x.cycle for x in samples_from_columns(cols, fps=10, duration=0.5)] == [0, 100, 199, 199, 199, 199]


def test_mp4_from_an_lcm_log(recorded, tmp_path):
    if shutil.which("ffmpeg") is None or shutil.which("ffprobe") is None:
        pytest.skip("ffmpeg is not installed (scripts/setup.sh installs Debian's ffmpeg)")
    out = tmp_path / "run.mp4"
    r = run_kinctl(None, "view", "--log", recorded["lcmlog"], "--save", str(out), "--duration", "1")
    assert r.returncode == 0, r.stderr
    assert "26 frames" in r.stdout
    probe = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                            "stream=nb_read_frames,width,height,codec_name", "-of", "default=nw=1", str(out)],
                           capture_output=True, text=True, timeout=60)
    assert probe.returncode == 0, probe.stderr
    fields = dict(line.split("=", 1) for line in probe.stdout.split())
    assert fields == {"codec_name": "h264", "width": str(W), "height": str(H), "nb_read_frames": "26"}


@pytest.mark.parametrize("args, message", [
    (["view", "--save", "arm.avi", "--log", "{csv}"], ".png (a still), .gif or .mp4"),
    (["view", "--model", "panda", "--log", "{csv}", "--save", "x.png"], "panda has 7"),
    (["view", "--model", "nosuch", "--log", "{csv}", "--save", "x.png"], "unknown model \"nosuch\""),
    (["view", "--model-file", "nosuch.cfg", "--log", "{csv}", "--save", "x.png"], "no such file"),
    (["view", "--log", "nosuch.csv", "--save", "x.png"], "no such file"),
    (["view", "--log", "{csv}"], "--log draws to a file: add --save"),
    (["view", "--fps", "0", "--save", "x.gif"], "must be > 0"),
])
def test_bad_input_says_what_to_do(recorded, tmp_path, args, message):
    args = [a.format(**recorded) for a in args]
    r = subprocess.run([sys.executable, "-m", "kinctl"] + args, capture_output=True, text=True, cwd=tmp_path,
                       timeout=60)
    assert r.returncode == 2, r.stdout + r.stderr
    assert message in r.stderr, r.stderr


def test_live_window_follows_the_setpoints(recorded):
    out, _, drawn = live_view_while_moving(recorded["url"])
    # A frame is drawn only for a new setpoint: the window followed the daemon, several times.
    assert drawn >= 5, out


def test_no_display_asks_for_save(recorded):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "LCM_DEFAULT_URL")}
    r = subprocess.run([sys.executable, "-m", "kinctl", "--lcm-url", recorded["url"], "view"], capture_output=True,
                       text=True, env=env, timeout=60)
    assert r.returncode == 2 and "--save arm.gif" in r.stderr, r.stderr


def test_help_has_examples():
    r = run_kinctl(None, "view", "--help")
    assert r.returncode == 0 and "example:" in r.stdout
    assert "kinctl view --save arm.gif --duration 5" in r.stdout and ".mp4" in r.stdout
