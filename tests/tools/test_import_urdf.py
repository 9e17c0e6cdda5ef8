# SPDX-License-Identifier: BSD-3-Clause
"""kinctl import-urdf: robot descriptions from real URDFs (the ones the
pybullet wheel ships in pybullet_data) and from a URDF written here with
every joint kind, rpy origins and oblique axes. Each description is read by
kinctl-calc (core/desc) and its FK compared with the URDF's own FK
(yourdfpy) at many random configurations."""
import json
import math
import os
import random
import subprocess
import sys

import numpy as np
import pybullet_data  # the URDFs: pybullet's wheel ships them (tools/requirements.txt)
import pytest

from kinctl_testing import run_kinctl
from kinctl import urdf
DATA = pybullet_data.getDataPath()
CALC = os.environ.get("KINCTL_CALC", "")
CONFIGS = 300
TOL = 1e-12  # m and rotation-matrix entries (seen: below 1e-15): the two FKs differ only by rounding

ROBOTS = [
    # (URDF, tip or None, moving joints on the chain)
    ("franka_panda/panda.urdf", "panda_grasptarget", 7),
    ("franka_panda/panda.urdf", "panda_leftfinger", 8),   # the prismatic finger on the chain
    ("kuka_iiwa/model.urdf", None, 7),
    ("xarm/xarm6_robot.urdf", None, 6),
]

# Every supported joint kind; origins with rpy; oblique and negative axes.
SYNTHETIC = """<?xml version="1.0"?>
<robot name="oblique">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="l4"/>
  <link name="l5"/><link name="flange"/><link name="tcp"/><link name="side"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/>
    <origin xyz="0.1 -0.05 0.3" rpy="0.2 -0.4 0.7"/>
    <axis xyz="0.267261241912424 0.534522483824849 0.801783725737273"/>
    <limit lower="-2.5" upper="2.0" velocity="1.5" effort="10"/>
  </joint>
  <joint name="j2" type="continuous">
    <parent link="l1"/><child link="l2"/>
    <origin xyz="0 0.2 0.05" rpy="1.5707963267948966 0 0"/>
    <axis xyz="0 -1 0"/>
  </joint>
  <joint name="j3" type="prismatic">
    <parent link="l2"/><child link="l3"/>
    <origin xyz="0.3 0 0" rpy="0 0.3 0"/>
    <axis xyz="0.6 0 -0.8"/>
    <limit lower="0.0" upper="0.25" velocity="0.4" effort="100"/>
  </joint>
  <joint name="fixed_mid" type="fixed">
    <parent link="l3"/><child link="l4"/>
    <origin xyz="0.05 0.02 -0.01" rpy="-0.5 1.5707963267948966 0.25"/>
  </joint>
  <joint name="j4" type="revolute">
    <parent link="l4"/><child link="l5"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/>
    <axis xyz="0 0 -1"/>
    <limit lower="-1.0" upper="3.0" velocity="2.0" effort="10"/>
  </joint>
  <joint name="j5" type="revolute">
    <parent link="l5"/><child link="flange"/>
    <origin xyz="0.07 0 0" rpy="3.0 -0.1 -2.0"/>
    <limit lower="-1.5" upper="1.5" velocity="2.5" effort="10"/>
  </joint>
  <joint name="tool" type="fixed">
    <parent link="flange"/><child link="tcp"/>
    <origin xyz="0 0.01 0.12" rpy="0.1 0.2 0.3"/>
  </joint>
  <joint name="side_joint" type="revolute">
    <parent link="l2"/><child link="side"/>
    <axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" velocity="1" effort="1"/>
  </joint>
</robot>
"""


def calc_fk(cfg, qs):
    if not CALC:
        pytest.skip("KINCTL_CALC is not set (run through ctest)")
    lines = "".join(json.dumps({"op": "fk", "model_file": cfg, "q": list(q), "id": i}) + "\n"
                    for i, q in enumerate(qs))
    r = subprocess.run([CALC, "batch"], input=lines, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    out = [json.loads(line) for line in r.stdout.splitlines()]
    assert len(out) == len(qs) and all("pose" in o for o in out), r.stdout[:500]
    return [np.array(o["pose"]) for o in out]


def random_q(joints, rng):
    q = []
    for j in joints:
        lim = j.limit
        if j.type == "continuous" or lim is None or lim.lower is None or not lim.upper > lim.lower:
            q.append(rng.uniform(-math.pi, math.pi))
        else:
            q.append(rng.uniform(lim.lower, lim.upper))
    return q


def check_import(path, tip, n_moving, tmp_path, seed):
    cfg = str(tmp_path / "robot.cfg")
    args = ["import-urdf", path, "-o", cfg] + (["--tip", tip] if tip else [])
    r = run_kinctl(None, *args)
    assert r.returncode == 0, r.stderr
    robot = urdf.load(path)
    base, tip, joints = urdf.chain_joints(robot, None, tip)
    moving = [j for j in joints if j.type != "fixed"]
    assert len(moving) == n_moving
    text = open(cfg).read()
    # limits: position (not for continuous joints) and velocity, as the URDF gives them
    for j in moving:
        row = next(line for line in text.splitlines() if f'name = "{j.name}"' in line)
        if j.type == "continuous":
            assert "q = [" not in row
        else:
            assert f"q = [{float(j.limit.lower)!r}, {float(j.limit.upper)!r}]" in row
        if j.limit is not None and j.limit.velocity:
            assert f"qd = {float(j.limit.velocity)!r}" in row
        else:
            assert "qd =" not in row
        assert ('op = "tz"' in row) == (j.type == "prismatic")
    rng = random.Random(seed)
    qs = [random_q(moving, rng) for _ in range(CONFIGS)]
    got = calc_fk(cfg, qs)
    worst = 0.0
    for q, T in zip(qs, got):
        ref = urdf.fk_reference(robot, [j.name for j in moving], q, base, tip)
        worst = max(worst, float(np.max(np.abs(T - ref))))
    assert worst <= TOL, f"{path}: largest FK difference {worst:.3g}"
    # and the configurations are not all alike: the tool moves by decimetres
    spread = np.ptp(np.array([T[:3, 3] for T in got]), axis=0)
    assert max(spread) > 0.1
    return text


@pytest.mark.parametrize("rel, tip, n", ROBOTS, ids=[f"{r}:{t}" for r, t, _ in ROBOTS])
def test_real_robot_matches_urdf_fk(rel, tip, n, tmp_path):
    check_import(os.path.join(DATA, rel), tip, n, tmp_path, seed=len(rel) + n)


def test_every_joint_kind_and_oblique_axes(tmp_path):
    path = tmp_path / "oblique.urdf"
    path.write_text(SYNTHETIC)
    text = check_import(str(path), "tcp", 5, tmp_path, seed=7)
    assert "side_joint" in text.split("robot =")[0]  # named as left out
    assert "No velocity limit in the URDF for: j2" in text


def test_frames_are_the_moving_links(tmp_path):
    """kinctl-calc's frame k is the k-th moving joint's child link turned by
    that joint's axis alignment: its origin is the link's origin."""
    path = os.path.join(DATA, "kuka_iiwa/model.urdf")
    cfg = str(tmp_path / "iiwa.cfg")
    assert run_kinctl(None, "import-urdf", path, "-o", cfg).returncode == 0
    robot = urdf.load(path)
    base, tip, joints = urdf.chain_joints(robot)
    moving = [j for j in joints if j.type != "fixed"]
    q = [0.3, -0.5, 0.7, 1.1, -0.2, 0.4, 0.9]
    r = subprocess.run([CALC, "fk", "--model-file", cfg, "--q", ",".join(map(repr, q)), "--frames"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    frames = json.loads(r.stdout)["frames"]
    assert len(frames) == len(moving)
    for j, F in zip(moving, frames):
        ref = urdf.fk_reference(robot, [m.name for m in moving], q, base, j.child)
        assert np.allclose(np.array(F)[:3, 3], ref[:3, 3], atol=TOL, rtol=0)


@pytest.mark.parametrize("args, text", [
    (["/nonexistent.urdf"], "no such file"),
    (["__FILE__"], "not a readable URDF (not XML"),
    (["__SDF__"], "not a URDF (its root element is <sdf>"),
    ([os.path.join(DATA, "franka_panda/panda.urdf")], "give --tip (one of"),
    ([os.path.join(DATA, "franka_panda/panda.urdf"), "--tip", "nosuch"], "--tip nosuch: no such link"),
    ([os.path.join(DATA, "franka_panda/panda.urdf"), "--tip", "panda_rightfinger"], "mimic"),
])
def test_bad_input_exits_2(tmp_path, args, text):
    sdf = tmp_path / "model.sdf"
    sdf.write_text('<?xml version="1.0"?>\n<sdf version="1.6"><model name="m"/></sdf>\n')
    args = [__file__ if a == "__FILE__" else str(sdf) if a == "__SDF__" else a for a in args]
    r = run_kinctl(None, "import-urdf", *args, "-o", str(tmp_path / "x.cfg"))
    assert r.returncode == 2, r.stdout + r.stderr
    assert text in r.stderr, r.stderr


def test_refuses_to_overwrite(tmp_path):
    out = tmp_path / "x.cfg"
    out.write_text("keep")
    r = run_kinctl(None, "import-urdf", os.path.join(DATA, "kuka_iiwa/model.urdf"), "-o", str(out))
    assert r.returncode == 2 and "--force" in r.stderr
    assert out.read_text() == "keep"


# Collision geometry on the chain's links: every converted shape, a second
# shape on one link, a mesh, a link with none, shapes behind a fixed joint
# and before the first joint (the base never moves: no volume).
COLLIDING = SYNTHETIC.replace('<link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="l4"/>',
                              "").replace('<link name="l5"/><link name="flange"/><link name="tcp"/><link name="side"/>', """
  <link name="base"><collision><origin xyz="0 0 0.05"/><geometry><box size="0.3 0.3 0.1"/></geometry></collision></link>
  <link name="l1"><collision><origin xyz="0.01 0.02 0.1" rpy="0.3 -0.2 0.5"/>
    <geometry><cylinder radius="0.06" length="0.2"/></geometry></collision></link>
  <link name="l2"><collision><origin xyz="0.15 0 0" rpy="0 1.5707963267948966 0"/>
    <geometry><capsule radius="0.05" length="0.3"/></geometry></collision>
    <collision><origin xyz="0 0.03 0"/><geometry><sphere radius="0.07"/></geometry></collision></link>
  <link name="l3"><collision><geometry><mesh filename="l3.stl"/></geometry></collision></link>
  <link name="l4"><collision><origin xyz="0.02 -0.01 0.04" rpy="0.7 0.1 -1.2"/>
    <geometry><box size="0.08 0.12 0.05"/></geometry></collision></link>
  <link name="l5"/>
  <link name="flange"><collision><origin xyz="0 0 0.03"/><geometry><sphere radius="0.04"/></geometry></collision></link>
  <link name="tcp"><collision><origin xyz="0 0 -0.02" rpy="0 0 0.4"/>
    <geometry><cylinder radius="0.02" length="0.06"/></geometry></collision></link>
  <link name="side"><collision><geometry><sphere radius="0.5"/></geometry></collision></link>""")


def _urdf_origin(col):
    """<origin xyz rpy> of an XML element: Trans(xyz) Rz Ry Rx, as URDF defines it."""
    o = col.find("origin")
    xyz = [float(v) for v in (o.get("xyz", "0 0 0") if o is not None else "0 0 0").split()]
    r, p, y = [float(v) for v in (o.get("rpy", "0 0 0") if o is not None else "0 0 0").split()]
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    T = np.eye(4)
    T[:3, :3] = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]]) @ np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]]) \
        @ np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    T[:3, 3] = xyz
    return T


def test_link_volumes_from_collision_geometry(tmp_path):
    """The volumes kinctl-calc places from the imported file (zones --geometry)
    against the URDF's own link poses (yourdfpy) times each collision origin,
    at random configurations; the mesh link and the link without geometry
    are named in a warning; the base link's box and the off-chain link's
    sphere give no volume."""
    import xml.etree.ElementTree as ET
    if not CALC:
        pytest.skip("KINCTL_CALC is not set (run through ctest)")
    path = tmp_path / "colliding.urdf"
    path.write_text(COLLIDING)
    cfg = tmp_path / "colliding.cfg"
    r = run_kinctl(None, "import-urdf", str(path), "-o", str(cfg), "--tip", "tcp")
    assert r.returncode == 0, r.stderr
    assert "6 link volumes" in r.stdout
    assert "warning: no link volume for base, l3, l5 (their collision geometry is a mesh" in r.stderr, r.stderr
    # the reference: link -> [(kind, dims, pose in the link frame)] from the XML
    expect = []
    for link in ET.fromstring(COLLIDING).findall("link"):
        if link.get("name") in ("base", "side"):
            continue
        for col in link.findall("collision"):
            g = next(iter(col.find("geometry")))
            if g.tag != "mesh":
                expect.append((link.get("name"), g.tag, g.attrib, _urdf_origin(col)))
    robot = urdf.load(str(path))
    _, _, joints = urdf.chain_joints(robot, None, "tcp")
    moving = [j for j in joints if j.type != "fixed"]
    rng = random.Random(7)
    worst = 0.0
    for _ in range(20):
        q = random_q(moving, rng)
        r = subprocess.run([CALC, "zones", "--model-file", str(cfg), "--q", ",".join(repr(v) for v in q),
                            "--geometry"], capture_output=True, text=True, timeout=60)
        assert r.returncode == 0, r.stderr
        got = json.loads(r.stdout)["geometry"]["volumes"]
        assert [v["kind"] for v in got] == [k for _, k, _, _ in expect]
        robot.update_cfg({j.name: np.float64(v) for j, v in zip(moving, q)})
        for v, (link, kind, attrs, T_col) in zip(got, expect):
            ref = robot.get_transform(frame_to=link, frame_from="base") @ T_col
            pose = np.array(v["pose"])
            worst = max(worst, float(np.max(np.abs(pose[:3, 3] - ref[:3, 3]))))
            if kind in ("cylinder", "capsule"):
                # axis along the collision frame's z (either way), radius, half length
                worst = max(worst, 1.0 - abs(float(pose[:3, 2] @ ref[:3, 2])))
                assert v["dim"][:2] == pytest.approx([float(attrs["radius"]), float(attrs["length"]) / 2], abs=1e-12)
            elif kind == "box":
                worst = max(worst, float(np.max(np.abs(pose[:3, :3] - ref[:3, :3]))))
                assert v["dim"][:3] == pytest.approx([float(s) / 2 for s in attrs["size"].split()], abs=1e-12)
            else:
                assert v["dim"][0] == pytest.approx(float(attrs["radius"]), abs=1e-12)
    assert worst <= 1e-12, f"largest difference from the URDF's collision poses: {worst:.3g}"


def test_acceleration_limits_and_kinctld_accepts(tmp_path):
    """qdd = 5 x qd per joint (the help's default), or --acc for every joint;
    kinctld --check accepts the file either way."""
    kinctld = os.environ.get("KINCTLD")
    if not kinctld:
        pytest.skip("KINCTLD is not set (run through ctest)")
    src = os.path.join(DATA, "kuka_iiwa/model.urdf")
    robot = urdf.load(src)
    _, _, joints = urdf.chain_joints(robot)
    moving = [j for j in joints if j.type != "fixed"]
    for extra, qdd_of in (([], lambda j: 5.0 * float(j.limit.velocity)), (["--acc", "7.5"], lambda j: 7.5)):
        cfg = tmp_path / f"iiwa{len(extra)}.cfg"
        r = run_kinctl(None, "import-urdf", src, "-o", str(cfg), *extra)
        assert r.returncode == 0, r.stderr
        text = cfg.read_text()
        for j in moving:
            row = next(line for line in text.splitlines() if f'name = "{j.name}"' in line)
            assert f"qdd = {qdd_of(j)!r};" in row, row
        c = subprocess.run([kinctld, "--config", str(cfg), "--check"], capture_output=True, text=True, timeout=60)
        assert c.returncode == 0, c.stderr
        assert "robot lbr_iiwa (7 joints" in c.stdout + c.stderr


def test_help_examples_run(tmp_path):
    """Every line of import-urdf's --help example, run as written (panda.urdf
    is pybullet's Panda), with this build's kinctl-calc and kinctld."""
    kinctld = os.environ.get("KINCTLD")
    if not (CALC and kinctld):
        pytest.skip("KINCTL_CALC and KINCTLD are not set (run through ctest)")
    r = run_kinctl(None, "import-urdf", "--help")
    assert r.returncode == 0
    lines = [line.strip() for line in r.stdout.split("example:\n", 1)[1].splitlines() if line.strip()]
    assert len(lines) == 3, lines
    import shutil
    shutil.copy(os.path.join(DATA, "franka_panda/panda.urdf"), tmp_path / "panda.urdf")
    programs = {"kinctl": [sys.executable, "-m", "kinctl"], "kinctl-calc": [CALC], "kinctld": [kinctld]}
    for line in lines:
        argv = line.split()
        assert argv[0] in programs, line
        p = subprocess.run(programs[argv[0]] + argv[1:], cwd=tmp_path, capture_output=True, text=True, timeout=60)
        assert p.returncode == 0, f"{line}: {p.stderr}"
