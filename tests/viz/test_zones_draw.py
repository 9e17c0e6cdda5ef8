# SPDX-License-Identifier: BSD-3-Clause
"""Forbidden zones and link volumes drawn by kinctl view and kinctl plot
(kinctl.zonedraw), from a real run's setpoints: the drawn wireframes checked
numerically against the zones' sizes, lab 3's projections and the core's
own placement of the volumes (kinctl-calc zones --geometry)."""

import numpy as np
import pytest

from conftest import csv_of, goal_columns, live_view_while_moving

from kinctl import logcsv
from kinctl import projection as pj
from kinctl import zonedraw as zd
from kinctl.kinematics import ArmFK
from kinctl.plot import plot_run
from kinctl.view import render, samples_from_columns
from kinctl_testing import QN, run_kinctl

SPHERE_C, SPHERE_R = np.array([0.55, 0.35, 0.35]), 0.12
BOX_C, BOX_H = np.array([0.1, -0.75, 0.3]), np.array([0.6, 0.05, 0.5])
TABLE_P, TABLE_N = np.array([0.0, 0.0, -0.2]), np.array([0.0, 0.0, 1.0])
ZONES = ["sphere:" + ",".join(map(str, list(SPHERE_C) + [SPHERE_R])),
         "box:" + ",".join(map(str, list(BOX_C) + list(BOX_H))),
         "halfspace:" + ",".join(map(str, list(TABLE_P) + list(TABLE_N)))]
PROJECTIONS = ("frontal_dimetric", "horizontal_isometric", "orthographic")


@pytest.fixture(scope="module")
def zoned_view(recorded, tmp_path_factory):
    """render() of 1 s of goal 13 (a joint move) with the zones and puma560's volumes."""
    part = goal_columns(recorded, 13)
    samples = samples_from_columns(part, fps=5, duration=1.0)
    path = str(tmp_path_factory.mktemp("zview") / "cell.png")
    with ArmFK(model="puma560") as fk:
        zones, volumes = zd.for_arm(fk, samples[0].q, zones=ZONES)
        info = render(samples, path, fk, fps=5, zones=zones, volumes=volumes)
    return info, samples, zones


def drawn_points(lines):
    """Every finite point of a panel's polylines (rows of coordinates) as N x k."""
    pts = np.hstack([np.asarray(p, dtype=float) for p in lines]).T
    return pts[np.isfinite(pts).all(axis=1)]


def test_the_zones_are_the_ones_given(zoned_view):
    _, _, zones = zoned_view
    assert [z["kind"] for z in zones] == ["sphere", "box", "halfspace"]
    assert np.allclose(np.asarray(zones[0]["pose"])[:3, 3], SPHERE_C) and zones[0]["dim"][0] == SPHERE_R


def test_sphere_points_lie_at_its_radius(zoned_view):
    info, _, _ = zoned_view
    p3 = drawn_points(info["panels"]["3d"]["zones"][0])
    assert len(p3) > 60
    assert np.allclose(np.linalg.norm(p3 - SPHERE_C, axis=1), SPHERE_R, atol=1e-12)
    # Viewed along -X (orthographic), its outline is the circle of radius r about (cy, cz), nothing outside.
    uv = drawn_points(info["panels"]["orthographic"]["zones"][0])
    d = np.linalg.norm(uv - SPHERE_C[1:], axis=1)
    assert d.max() == pytest.approx(SPHERE_R, abs=1e-12) and (d <= SPHERE_R + 1e-12).all()
    assert (d > SPHERE_R - 1e-12).sum() >= 24
    # Every projection draws the same 3-D points through lab 3's matrix.
    for name in PROJECTIONS:
        assert np.allclose(drawn_points(info["panels"][name]["zones"][0]), p3 @ pj.matrix(name).T, atol=1e-12)


def test_box_corners_project_to_lab3_places(zoned_view):
    info, _, _ = zoned_view
    corners = np.array([BOX_C + BOX_H * np.array([sx, sy, sz]) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    for name in PROJECTIONS:
        M = pj.matrix(name)
        uv = drawn_points(info["panels"][name]["zones"][1])
        want = corners @ M.T
        # every corner drawn, and nothing but corners (a box's edges are straight segments between them)
        for c in want:
            assert np.linalg.norm(uv - c, axis=1).min() < 1e-12, (name, c)
        for p in uv:
            assert np.linalg.norm(want - p, axis=1).min() < 1e-12, (name, p)
    p3 = drawn_points(info["panels"]["3d"]["zones"][1])
    assert len(np.unique(np.round(p3, 9), axis=0)) == 8


def test_table_is_its_plane_clipped_to_the_view(zoned_view):
    info, _, _ = zoned_view
    lo, hi = info["bounds"]
    p3 = drawn_points(info["panels"]["3d"]["zones"][2])
    assert np.allclose((p3 - TABLE_P) @ TABLE_N, 0.0, atol=1e-12)
    assert (p3 >= lo - 1e-9).all() and (p3 <= hi + 1e-9).all()
    # the outline reaches the view's box on all four sides of the plane
    for k in (0, 1):
        assert p3[:, k].min() == pytest.approx(lo[k]) and p3[:, k].max() == pytest.approx(hi[k])


def test_link_volumes_move_with_the_setpoints_frames(zoned_view):
    """The last frame's drawn volumes are where the core places them at the
    last sample's q (kinctl-calc zones --geometry there), not at the first."""
    info, samples, _ = zoned_view
    q0, q1 = samples[0].q, samples[-1].q
    assert np.abs(np.subtract(q1, q0)).max() > 0.3  # the arm moved in between
    at1 = zd.geometry(model="puma560", q=q1)["volumes"]
    at0 = zd.geometry(model="puma560", q=q0)["volumes"]
    want = np.vstack([p for s in at1 for p in zd.shape_lines(s)])
    drawn3 = drawn_points([info["panels"]["3d"]["volumes"]])
    assert drawn3.shape == want.shape
    assert np.abs(drawn3 - want).max() < 1e-9
    assert np.abs(drawn3 - np.vstack([p for s in at0 for p in zd.shape_lines(s)])).max() > 0.05
    for name in PROJECTIONS:
        assert np.abs(drawn_points([info["panels"][name]["volumes"]]) - want @ pj.matrix(name).T).max() < 1e-9
    # Each capsule's wireframe lies on its surface: radius r from its axis segment (an independent check).
    k = 0
    for s in at1:
        assert s["kind"] == "capsule"
        T = np.asarray(s["pose"])
        r, h = s["dim"][:2]
        a, b = T[:3, 3] - h * T[:3, 2], T[:3, 3] + h * T[:3, 2]
        n = sum(len(p) for p in zd.shape_lines(s))
        pts = drawn3[k:k + n]
        k += n
        t = np.clip((pts - a) @ (b - a) / np.dot(b - a, b - a), 0.0, 1.0)
        dist = np.linalg.norm(pts - (a + t[:, None] * (b - a)), axis=1)
        assert np.allclose(dist, r, atol=1e-9)


def test_frustum_and_cylinder_wireframes():
    T = np.eye(4)
    T[:3, 3] = [0.1, 0.2, 0.3]
    fr = np.vstack(zd.shape_lines({"kind": "frustum", "pose": T, "dim": [0.2, 0.1, 0.05, 0.04, 0.3]}))
    want = {(0.1 + sx * a, 0.2 + sy * b, 0.3 + z) for a, b, z in ((0.2, 0.1, -0.3), (0.05, 0.04, 0.3))
            for sx in (-1, 1) for sy in (-1, 1)}
    assert {tuple(np.round(p, 12)) for p in fr} == {tuple(np.round(p, 12)) for p in want}
    cy = np.vstack(zd.shape_lines({"kind": "cylinder", "pose": T, "dim": [0.07, 0.2, 0, 0, 0]}))
    assert np.allclose(np.hypot(cy[:, 0] - 0.1, cy[:, 1] - 0.2), 0.07)
    assert np.allclose(np.abs(cy[:, 2] - 0.3), 0.2)


def test_plot_draws_zones_and_the_volumes_at_start_and_end(recorded, tmp_path):
    cols = logcsv.read(recorded["csv"])
    info = plot_run(recorded["csv"], str(tmp_path / "z.png"), model="puma560", zones=ZONES, volumes=True)
    first = [cols[f"q{j}"][0] for j in range(1, 7)]
    last = [cols[f"q{j}"][-1] for j in range(1, 7)]
    for vols, q in zip(info["volumes"], (first, last)):
        ref = zd.geometry(model="puma560", q=q)["volumes"]
        assert [np.allclose(a["pose"], b["pose"], atol=1e-12) for a, b in zip(vols, ref)] == [True] * len(ref)
    axes = {a["title"]: a for a in info["axes"]}
    xy = axes["tool path, top view (XY)"]
    assert {"forbidden zones", "link volumes at the start", "link volumes at the end"} <= set(xy["curves"])
    # the box's corners on the XY plane are drawn
    pts = np.hstack([np.array(d) for d in xy["data"]]).T
    for sx in (-1, 1):
        for sy in (-1, 1):
            c = BOX_C[:2] + BOX_H[:2] * [sx, sy]
            assert np.linalg.norm(pts - c, axis=1).min() < 1e-12
    # without the model, the zones alone
    bare = plot_run(recorded["csv"], str(tmp_path / "b.png"), zones=ZONES[:1], volumes=True)
    assert bare["volumes"] == [] and [z["kind"] for z in bare["zones"]] == ["sphere"]


def test_plot_cli_draws_the_volumes_unless_no_volumes(recorded, tmp_path):
    """With --model the CLI asks for the volumes: the PNG differs from the
    --no-volumes one, which is the one drawn with the zones alone."""
    import matplotlib.image
    imgs = {}
    for name, extra in (("vol", []), ("novol", ["--no-volumes"])):
        out = str(tmp_path / f"{name}.png")
        r = run_kinctl(None, "plot", recorded["csv"], "-o", out, "--model", "puma560", "--zone", ZONES[0], *extra)
        assert r.returncode == 0, r.stderr
        imgs[name] = matplotlib.image.imread(out)
    plot_run(recorded["csv"], str(tmp_path / "api.png"), model="puma560", zones=ZONES[:1])
    assert (imgs["vol"] != imgs["novol"]).any(axis=2).mean() > 0.001
    assert (matplotlib.image.imread(str(tmp_path / "api.png")) == imgs["novol"]).all()


@pytest.mark.parametrize("cmd", ["view", "plot"])
@pytest.mark.parametrize("zone,message", [
    ("box:1,2", 'zone "box:1,2": box takes 6 numbers, got 2'),
    ("blob:1,2,3,4", 'zone "blob:1,2,3,4": unknown kind'),
    ("sphere:0,0,0,-1", "sizes must be positive"),
    ("sphere", "expected KIND:NUMBERS"),
])
def test_bad_zone_exits_2_saying_why(recorded, tmp_path, cmd, zone, message):
    out = str(tmp_path / "x.png")
    args = (["view", "--log", recorded["csv"], "--save", out] if cmd == "view"
            else ["plot", recorded["csv"], "-o", out])
    r = run_kinctl(None, *args, "--model", "puma560", "--zone", zone)
    assert r.returncode == 2, r.stdout + r.stderr
    assert message in r.stderr


def test_missing_zones_file_exits_2(recorded, tmp_path):
    r = run_kinctl(None, "view", "--log", recorded["csv"], "--save", str(tmp_path / "x.png"),
                   "--zones-file", str(tmp_path / "none.cfg"))
    assert r.returncode == 2 and "none.cfg" in r.stderr


@pytest.mark.parametrize("cmd", ["view", "plot"])
def test_help_shows_a_zone_example(cmd):
    r = run_kinctl(None, cmd, "--help")
    assert r.returncode == 0
    assert "--zones-file" in r.stdout and "--no-volumes" in r.stdout
    assert "--zone " in r.stdout.split("example")[-1]


def test_live_window_draws_zones_and_moving_volumes(recorded):
    """The live window's path (zones and volumes set up from the daemon's first
    setpoint, volumes redrawn at each new one) runs and follows the daemon."""
    zone_args = [a for z in ZONES for a in ("--zone", z)]
    try:
        out, _, drawn = live_view_while_moving(recorded["url"], "--model", "puma560", *zone_args)
    finally:
        run_kinctl(recorded["url"], "goal", "joint", "--q", csv_of(QN), "--wait")
    assert drawn >= 5, out
