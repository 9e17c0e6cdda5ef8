# SPDX-License-Identifier: BSD-3-Clause
"""kinctl plot from a real run: the CSV of kinctl log and the LCM log of
lcm-logger, to PNG and SVG, checked against the logged data."""
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from conftest import LINE_SPEED

from kinctl import logcsv
from kinctl.plot import plot_run
from kinctl.runlog import read_run
from kinctl_testing import run_kinctl

GOALS = [11, 20, 12, 21, 13, 14]
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def csv_plot(recorded, tmp_path_factory):
    out = str(tmp_path_factory.mktemp("plot") / "run.png")
    return plot_run(recorded["csv"], out, events=recorded["events"]), logcsv.read(recorded["csv"])


def segment(cols, gid):
    idx = [i for i, g in enumerate(cols["goal_id"]) if g == gid]
    assert idx == list(range(idx[0], idx[-1] + 1)), "one run per goal"
    return idx[0], idx[-1] + 1


def times(cols):
    dt = 1e-3  # kinctld's default period
    return [(c - cols["cycle"][0]) * dt for c in cols["cycle"]]


def test_panels_and_goals(csv_plot):
    info, cols = csv_plot
    assert info["rows"] == len(cols["cycle"]) > 3000
    assert info["joints"] == 6
    assert abs(info["period_s"] - 1e-3) < 1e-6
    assert info["goals"] == GOALS
    q, qd, qdd, p3, xy, xz, yz, speed, jerk = info["axes"]
    for ax, key, unit in ((q, "q", "rad"), (qd, "qd", "rad/s"), (qdd, "qdd", "rad/s²")):
        assert ax["ylabel"].endswith(f"({unit})")
        assert [c for c in ax["curves"] if c.startswith(key)] == [f"{key}{j}" for j in range(1, 7)]
        # Six joint curves, per goal a bold leading-joint overlay and a start line (and in q the legend entry).
        assert ax["lines"] == 6 + 2 * len(GOALS) + (1 if key == "q" else 0)
    assert "leading joint (travels farthest)" in q["curves"]
    # Jerk: each joint's change of the logged qdd per setpoint over its time
    # step, computed here from the CSV and the q panel's time axis; the
    # largest of each is reported.
    assert [c for c in jerk["curves"] if c.startswith("jerk")] == [f"jerk{j}" for j in range(1, 7)]
    t = np.asarray(q["data"][0][0], dtype=float)
    curves = [d for d in jerk["data"] if len(d[0]) == len(t) - 1]  # the limits are 2-point lines
    assert len(curves) == 6
    for j in range(1, 7):
        x, y = (np.asarray(v, dtype=float) for v in curves[j - 1])
        want = np.diff(np.asarray(cols[f"qdd{j}"], dtype=float)) / np.diff(t)
        assert np.array_equal(x, t[1:])
        assert np.allclose(y, want, rtol=1e-12, atol=0.0), j
        assert info["max_jerk"][j - 1] == pytest.approx(float(np.nanmax(np.abs(np.asarray(y)))))
    assert speed["xlabel"] == "time (s)" and speed["ylabel"] == "tool speed (m/s)"
    assert p3["name"] == "3d" and p3["title"].startswith("tool path")
    for ax, (u, v) in ((xy, "xy"), (xz, "xz"), (yz, "yz")):
        assert (ax["xlabel"], ax["ylabel"]) == (f"{u} (m)", f"{v} (m)")
        assert f"({u.upper()}{v.upper()})" in ax["title"]
    assert xy["curves"] == [f"goal {g}" for g in GOALS]


def test_curves_are_the_logged_data(csv_plot):
    info, cols = csv_plot
    t = times(cols)
    q, qd, qdd = info["axes"][:3]
    for ax, key in ((q, "q"), (qd, "qd"), (qdd, "qdd")):
        for j in range(1, 7):
            x, y = ax["data"][j - 1]
            assert list(x) == pytest.approx(t, abs=1e-12) and list(y) == cols[f"{key}{j}"]
        lo = min(min(cols[f"{key}{j}"]) for j in range(1, 7))
        hi = max(max(cols[f"{key}{j}"]) for j in range(1, 7))
        assert ax["ylim"][0] <= lo and hi <= ax["ylim"][1]
        # The axis is not blown up beyond the data (matplotlib's 5 % margins).
        assert ax["ylim"][1] - ax["ylim"][0] < (hi - lo) * 1.25 + 1e-9
    assert q["xlim"][0] <= 0 and q["xlim"][1] >= t[-1]


def test_leading_joint_is_the_one_that_travels_farthest(csv_plot):
    info, cols = csv_plot
    # Goals 11 and 20 move joint 2 by 1 rad (the others 0.1 rad or less); 13 moves joint 1 by 0.8 rad.
    assert info["leading"][11] == 2 and info["leading"][20] == 2 and info["leading"][13] == 1
    t = times(cols)
    a, b = segment(cols, 13)
    # The bold overlay of goal 13 in the q panel is joint 1's own curve over the goal.
    overlays = [d for d in info["axes"][0]["data"][6:] if len(d[0]) == b - a and d[0][0] == t[a]]
    assert len(overlays) == 1 and list(overlays[0][1]) == cols["q1"][a:b]


def test_leading_joint_of_the_planner_with_the_model(recorded, tmp_path):
    plain = plot_run(recorded["csv"], str(tmp_path / "a.png"))
    info = plot_run(recorded["csv"], str(tmp_path / "b.png"), model="puma560")
    # Goal 14: joint 6 travels farthest, but joint 1 (half its rate limits) sets the move's time.
    assert plain["leading"][14] == 6 and plain["leading_how"][14] == "travel"
    assert info["leading"][14] == 1 and info["leading_how"][14] == "planner"
    # The other joint moves lead with the same joint either way; the line has no planner's leading joint.
    assert {g: info["leading"][g] for g in (11, 20, 21, 13)} == {11: 2, 20: 2, 21: 2, 13: 1}
    assert {g: info["leading_how"][g] for g in GOALS} == {11: "planner", 20: "planner", 12: "travel",
                                                          21: "planner", 13: "planner", 14: "planner"}
    assert "leading joint" in info["axes"][0]["curves"]
    r = run_kinctl(None, "plot", recorded["csv"], "--model", "nosuch", "-o", str(tmp_path / "c.png"))
    assert r.returncode == 2 and "unknown model" in r.stderr, r.stderr


def test_tool_path_projections_per_goal(csv_plot):
    info, cols = csv_plot
    _, _, _, p3, xy, xz, yz, _, _ = info["axes"]
    for ax, (u, v) in ((xy, ("x", "y")), (xz, ("x", "z")), (yz, ("y", "z"))):
        # Line 0 is the whole path (grey), then one line per goal.
        assert [list(d) for d in ax["data"][0]] == [cols[u], cols[v]]
        for k, gid in enumerate(GOALS):
            a, b = segment(cols, gid)
            assert [list(d) for d in ax["data"][1 + k]] == [cols[u][a:b], cols[v][a:b]], (u, v, gid)
        assert ax["xlim"][0] <= min(cols[u]) and max(cols[u]) <= ax["xlim"][1]
        assert ax["ylim"][0] <= min(cols[v]) and max(cols[v]) <= ax["ylim"][1]
    x3, y3, z3 = p3["data"][0]
    assert (list(x3), list(y3), list(z3)) == (cols["x"], cols["y"], cols["z"])


def test_speed_along_the_path(csv_plot, recorded):
    info, cols = csv_plot
    speed = info["axes"][7]
    a, b = segment(cols, 12)
    x, v = speed["data"][1 + GOALS.index(12)]
    assert len(v) == b - a
    # The 0.15 m line cruises at its commanded 0.2 m/s (finite differences of the logged positions).
    assert max(v) == pytest.approx(LINE_SPEED, rel=2e-3)
    assert v[0] < 0.01 and v[-1] < 0.01
    # Its length: the integral of the speed is the 0.15 m the line covers.
    assert float(np.trapezoid(v, x)) == pytest.approx(0.15, rel=2e-3)
    assert info["max_speed"] >= LINE_SPEED * 0.998


def test_png_from_the_cli(recorded, tmp_path):
    out = tmp_path / "cli.png"
    r = run_kinctl(None, "plot", recorded["csv"], "--events", recorded["events"], "-o", str(out))
    assert r.returncode == 0, r.stderr
    assert "6 goals" in r.stdout
    with open(out, "rb") as f:
        assert f.read(8) == PNG_SIGNATURE
    import matplotlib.image
    img = matplotlib.image.imread(str(out))
    assert img.shape[:2] == (1450, 1800)
    # Not a blank canvas: a good share of the pixels are not white.
    assert (img[:, :, :3] < 0.9).any(axis=2).mean() > 0.03


def test_lcm_log_reads_the_same_setpoints_as_the_csv(recorded):
    import lcm
    csv_cols = logcsv.read(recorded["csv"])
    lcm_cols, events = read_run(recorded["lcmlog"])
    # Every setpoint in the file is read (lcm-logger itself may miss a few on a loaded machine).
    in_file = sum(1 for ev in lcm.EventLog(recorded["lcmlog"], "r") if ev.channel == "KINCTL_SETPOINT")
    assert len(lcm_cols["cycle"]) == in_file
    # Both recorded the same stream: on the cycles they share, every value is equal.
    common = sorted(set(csv_cols["cycle"]) & set(lcm_cols["cycle"]))
    assert len(common) > 1000
    ic = {c: i for i, c in enumerate(csv_cols["cycle"])}
    il = {c: i for i, c in enumerate(lcm_cols["cycle"])}
    assert list(csv_cols) == list(lcm_cols)
    for k in csv_cols:
        assert [csv_cols[k][ic[c]] for c in common] == [lcm_cols[k][il[c]] for c in common], k
    # Status events come from the LCM log itself.
    assert [e["goal_id"] for e in events if e["event"] == "COMPLETED"] == GOALS


def test_svg_from_an_lcm_log(recorded, tmp_path):
    out = tmp_path / "run.svg"
    r = run_kinctl(None, "plot", recorded["lcmlog"], "-o", str(out))
    assert r.returncode == 0, r.stderr
    root = ET.parse(out).getroot()
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    ids = {g.get("id") for g in root.iter("{http://www.w3.org/2000/svg}g")}
    # Ten axes: q, qd, qdd, jerk, speed, 3-D, XY, XZ, YZ and the goals' key.
    assert {f"axes_{i}" for i in range(1, 11)} <= ids and "axes_11" not in ids
    svg = out.read_text()
    # matplotlib draws text as glyphs and keeps each string in a comment beside it.
    for title in ("tool path, top view (XY)", "tool path, side view (XZ)", "tool path, front view (YZ)",
                  "speed along the tool path", "goal 12", "lead q1"):
        assert title in svg, title
    info = plot_run(recorded["lcmlog"], str(tmp_path / "again.svg"))
    assert info["goals"] == GOALS and info["leading"][13] == 1


def test_extra_shapes_are_drawn(recorded, tmp_path):
    from kinctl.shapes import Polyline, box_edges
    lo, hi = (0.3, -0.3, 0.2), (0.5, -0.1, 0.4)
    box = Polyline(box_edges(lo, hi), label="a box")
    plain = plot_run(recorded["csv"], str(tmp_path / "a.png"))
    boxed = plot_run(recorded["csv"], str(tmp_path / "b.png"), shapes=[box])
    for i in (3, 4, 5, 6):  # 3-D, XY, XZ, YZ
        assert boxed["axes"][i]["lines"] == plain["axes"][i]["lines"] + 12
    xs = [v for d in boxed["axes"][4]["data"][-12:] for v in d[0]]
    assert min(xs) == lo[0] and max(xs) == hi[0]


@pytest.mark.parametrize("args, message", [
    (["plot", "nosuch.csv"], "no such file"),
    (["plot", "{csv}", "-o", "out.jpg"], ".png or .svg"),
    (["plot", "{lcmlog}", "--prefix", "ARM2_"], "try --prefix KINCTL_"),
    (["plot", "{events}"], "not a setpoint CSV"),
])
def test_bad_input_says_what_to_do(recorded, tmp_path, args, message):
    args = [a.format(**recorded) for a in args]
    r = run_kinctl(None, *args)
    assert r.returncode == 2, r.stdout + r.stderr
    assert message in r.stderr, r.stderr


def test_help_has_an_example():
    r = run_kinctl(None, "plot", "--help")
    assert r.returncode == 0 and "example:" in r.stdout and "kinctl plot run.lcmlog" in r.stdout
