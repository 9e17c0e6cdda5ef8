# SPDX-License-Identifier: BSD-3-Clause
"""Black-box tests of kinctl-calc: its JSON answers against tests/vectors,
batch mode, and every kind of bad input.

Environment: KINCTL_CALC (the binary), KINCTL_VECTORS (tests/vectors),
KINCTL_MODELS (models/), KINCTL_REAL (double or float: the tolerance).
"""
import json
import math
import os
import subprocess

import pytest

CALC = os.environ.get("KINCTL_CALC", "kinctl-calc")
VECTORS = os.environ.get("KINCTL_VECTORS", os.path.join(os.path.dirname(__file__), "..", "vectors"))
MODELS = os.environ.get("KINCTL_MODELS", os.path.join(os.path.dirname(__file__), "..", "..", "models"))
FLOAT = os.environ.get("KINCTL_REAL", "double") == "float"
TOL = 2e-5 if FLOAT else 1e-12
ROUND_TRIP_TOL = 2e-5 if FLOAT else 1e-9


def load(name):
    with open(os.path.join(VECTORS, name)) as f:
        return json.load(f)


FK = load("fk.json")
ORIENT = load("orientation.json")
TRANSFORMS = load("transforms.json")


def run(args, stdin=None):
    return subprocess.run([CALC] + [str(a) for a in args], input=stdin, capture_output=True, text=True, timeout=60)


def ok(args):
    r = run(args)
    assert r.returncode == 0, f"{args}: exit {r.returncode}, stderr: {r.stderr}"
    return json.loads(r.stdout)


def csv(values):
    return ",".join(repr(float(v)) for v in values)


def assert_near(got, want, tol=TOL, what=""):
    if isinstance(want, (list, tuple)):
        assert isinstance(got, list) and len(got) == len(want), f"{what}: shape {got} vs {want}"
        for i, (g, w) in enumerate(zip(got, want)):
            assert_near(g, w, tol, f"{what}[{i}]")
    else:
        assert got is not None and abs(got - want) <= tol, f"{what}: {got} vs {want}"


def angle_near(got, want, tol):
    d = (got - want + math.pi) % (2 * math.pi) - math.pi
    return abs(d) <= tol


# ---- fk and jacobian against fk.json ----

FK_CASES = (
    [("rrr3", c["q_rad"], c["T"], c["J0_6x3"], None) for c in FK["rrr"]["configs"]]
    + [("puma560", c["q_rad"], c["T"], c["J0_6x6"], c["T0i_cumulative"]) for c in FK["puma560"]["configs"]]
    + [("panda", c["q_rad"], c["T_tool"], c["J0_6x7_tool_point"], None) for c in FK["panda"]["configs"]]
)


@pytest.mark.parametrize("model,q,T,J,frames", FK_CASES, ids=[f"{c[0]}-{i}" for i, c in enumerate(FK_CASES)])
def test_fk_and_jacobian_vectors(model, q, T, J, frames):
    out = ok(["fk", "--model", model, "--q", csv(q)] + (["--frames"] if frames else []))
    assert_near(out["pose"], T, what="pose")
    if frames:
        assert_near(out["frames"], frames, what="frames")
    else:
        assert "frames" not in out
    out = ok(["jacobian", "--model", model, "--q", csv(q)])
    assert_near(out["jacobian"], J, what="jacobian")


def test_fk_deg_equals_rad():
    q = FK["puma560"]["configs"][7]["q_rad"]
    rad = ok(["fk", "--model", "puma560", "--q", csv(q)])
    deg = ok(["fk", "--model", "puma560", "--deg", "--q", csv(math.degrees(v) for v in q)])
    assert_near(deg["pose"], rad["pose"], 1e-12 if not FLOAT else 1e-4)
    jd = ok(["jacobian", "--model", "puma560", "--deg", "--q", csv(math.degrees(v) for v in q)])
    jr = ok(["jacobian", "--model", "puma560", "--q", csv(q)])
    assert_near(jd["jacobian"], jr["jacobian"], 1e-12 if not FLOAT else 1e-4)


@pytest.mark.parametrize("model", ["puma560", "panda", "rrr3", "planar2", "rb211", "rm01"])
def test_model_file_equals_builtin(model):
    builtin = ok(["fk", "--model", model, "--q", ",".join(["0.3"] * {"panda": 7, "rrr3": 3, "planar2": 2}.get(model, 6)), "--frames"])
    path = os.path.join(MODELS, model + ".cfg")
    filed = ok(["fk", "--model-file", path, "--q", ",".join(["0.3"] * {"panda": 7, "rrr3": 3, "planar2": 2}.get(model, 6)), "--frames"])
    assert_near(filed["pose"], builtin["pose"])
    assert_near(filed["frames"], builtin["frames"])


def test_fk_frames_print_the_base(tmp_path):
    # rrr3 on a base 0.5 m up and turned 90 deg about z: "base" is that pose,
    # every frame and the tool are the base times the arm's own (base = I).
    with open(os.path.join(MODELS, "rrr3.cfg")) as f:
        text = f.read()
    path = tmp_path / "raised.cfg"
    path.write_text(text.replace('angles = "rad";', 'angles = "rad";\n  base = { xyz = [0.1, 0.2, 0.5]; '
                                                     'rpy = [0.0, 0.0, 1.5707963267948966]; };'))
    q = "0.3,-0.4,0.7"
    plain = ok(["fk", "--model", "rrr3", "--q", q, "--frames"])
    raised = ok(["fk", "--model-file", path, "--q", q, "--frames"])
    assert_near(plain["base"], [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], what="identity base")
    B = [[0, -1, 0, 0.1], [1, 0, 0, 0.2], [0, 0, 1, 0.5], [0, 0, 0, 1]]
    assert_near(raised["base"], B, tol=max(TOL, 1e-15), what="base")

    def mul(A, C):
        return [[sum(A[i][k] * C[k][j] for k in range(4)) for j in range(4)] for i in range(4)]
    assert len(raised["frames"]) == len(plain["frames"]) == 3
    for f_raised, f_plain in zip(raised["frames"], plain["frames"]):
        assert_near(f_raised, mul(B, f_plain), tol=ROUND_TRIP_TOL, what="frame")
    assert_near(raised["pose"], mul(B, plain["pose"]), tol=ROUND_TRIP_TOL, what="tool")
    assert "base" not in ok(["fk", "--model", "rrr3", "--q", q])


def test_param_lengths():
    default = ok(["fk", "--model", "rrr3", "--q", "0.1,0.2,0.3"])
    same = ok(["fk", "--model", "rrr3", "--param", "l1=0.4,l2=0.3,l3=0.25", "--q", "0.1,0.2,0.3"])
    assert same == default
    # planar2 at q = 0 reaches l1 + l2 along x.
    out = ok(["fk", "--model", "planar2", "--param", "l1=1.5,l2=0.25", "--q", "0,0"])
    assert_near(out["pose"][0][3], 1.75)


def test_fk_outside_limits_warns():
    r = run(["fk", "--model", "puma560", "--q", "0,0,0,0,0,5"])
    assert r.returncode == 0
    assert "warning" in r.stderr and "outside joint 6's limits" in r.stderr
    json.loads(r.stdout)


# ---- orient against orientation.json ----

def orient(frm, to, values, deg=False):
    return ok(["orient", "--from", frm, "--to", to] + (["--deg"] if deg else []) + [repr(float(v)) for v in values])


def flat(m):
    return [x for row in m for x in row]


def check_quat(got, want):
    # w >= 0; at w = 0 the sign is a convention: accept either.
    if abs(want[0]) < 1e-9:
        if all(abs(g + w) <= TOL for g, w in zip(got, want)):
            return
    assert_near(got, want, what="quat")


@pytest.mark.parametrize("v", ORIENT["rpy_variants"], ids=lambda v: f"rpy{v['variant']}")
def test_orient_rpy_variants(v):
    angles = [v["roll_phi_about_Z_deg"], v["pitch_theta_about_Y_deg"], v["yaw_psi_about_X_deg"]]
    out = orient("rpy", "matrix", angles, deg=True)
    assert_near(out["matrix"], v["R"])
    assert out["singular"] is False
    ex = orient("matrix", "rpy", flat(v["R"]))
    e = v["extracted"]
    assert ex["singular"] == e["gimbal_lock"]
    for got, want in zip(ex["rpy"], [e["phi_rad"], e["theta_rad"], e["psi_rad"]]):
        assert angle_near(got, want, ROUND_TRIP_TOL)
    check_quat(orient("matrix", "quat", flat(v["R"]))["quat"], v["quaternion_wxyz"])


@pytest.mark.parametrize("v", ORIENT["zyz_variants"], ids=lambda v: f"zyz{v['variant']}")
def test_orient_zyz_variants(v):
    out = orient("zyz", "matrix", [v["phi_deg"], v["theta_deg"], v["psi_deg"]], deg=True)
    assert_near(out["matrix"], v["R"])
    ex = orient("matrix", "zyz", flat(v["R"]), deg=True)
    e = v["extracted"]
    assert ex["singular"] == e["gimbal_lock"]
    for got, want in zip(ex["zyz"], [e["phi_deg"], e["theta_deg"], e["psi_deg"]]):
        assert angle_near(math.radians(got), math.radians(want), ROUND_TRIP_TOL)
    check_quat(orient("matrix", "quat", flat(v["R"]))["quat"], v["quaternion_wxyz"])


@pytest.mark.parametrize("v", ORIENT["axis_angle_variants"], ids=lambda v: f"aa{v['variant']}")
def test_orient_axis_angle_variants(v):
    out = orient("axis-angle", "matrix", v["K"] + [v["theta_deg"]], deg=True)
    assert_near(out["matrix"], v["R"])
    ex = orient("matrix", "axis-angle", flat(v["R"]))
    assert_near(ex["axis"], v["extracted_canonical"]["k"], ROUND_TRIP_TOL)
    assert_near(ex["angle"], v["extracted_canonical"]["theta_rad"], ROUND_TRIP_TOL)
    check_quat(orient("axis-angle", "quat", v["K"] + [v["theta_deg"]], deg=True)["quat"], v["quaternion_wxyz"])


@pytest.mark.parametrize("form,cases", [("rpy", ORIENT["round_trip_rpy"]), ("zyz", ORIENT["round_trip_zyz"])])
def test_orient_round_trips(form, cases):
    for c in cases:
        out = orient(form, "matrix", c["input_deg"], deg=True)
        assert_near(out["matrix"], c["R"], ROUND_TRIP_TOL, c["case"])
        ex = orient("matrix", form, flat(c["R"]))
        assert ex["singular"] == c["gimbal_lock"], c["case"]
        back = orient(form, "matrix", ex[form])
        assert_near(back["matrix"], c["R"], ROUND_TRIP_TOL, c["case"])
        if not FLOAT:
            for got, want in zip(ex[form], c["extracted_rad"]):
                assert angle_near(got, want, 1e-9), c["case"]


def test_orient_axis_angle_round_trips():
    for c in ORIENT["round_trip_axis_angle"]:
        out = orient("axis-angle", "matrix", c["k_in"] + [c["theta_in_deg"]], deg=True)
        assert_near(out["matrix"], c["R"], ROUND_TRIP_TOL, c["case"])
        ex = orient("matrix", "axis-angle", flat(c["R"]))
        assert_near(ex["angle"], c["extracted_theta_rad"], ROUND_TRIP_TOL, c["case"])
        if c["extracted_k"] is not None and c["extracted_theta_rad"] > 1e-6:
            assert_near(ex["axis"], c["extracted_k"], ROUND_TRIP_TOL, c["case"])
        check_quat(orient("matrix", "quat", flat(c["R"]))["quat"], c["quaternion_wxyz"])


def test_orient_quat_identity_is_singular_axis_angle():
    out = orient("quat", "axis-angle", [2, 0, 0, 0])
    assert out == {"axis": [0, 0, 1], "angle": 0, "singular": True}


# ---- transform against transforms.json ----

def transform_args(task, v):
    p = task["parameter"]
    t = task["task"]
    if t in (1, 2, 3):
        d = [0.0, 0.0, 0.0]
        d[t - 1] = v[p]
        return ["--translate", csv(d)]
    if t in (4, 5, 6):
        return ["--deg", "--rotate", f"{'xyz'[t - 4]},{v[p]}"]
    if t == 7:
        return ["--scale", v[p]]
    axis = v["optical_axis"][-1].lower()
    return ["--perspective", f"{axis},{v[p]}"]


TRANSFORM_CASES = [(task, v) for task in TRANSFORMS["tasks"] for v in task["variants"]]


@pytest.mark.parametrize("task,v", TRANSFORM_CASES, ids=[f"task{t['task']}-v{v['variant']}" for t, v in TRANSFORM_CASES])
def test_transform_vectors(task, v):
    A = TRANSFORMS["pyramid_A_3x5"]
    points = [[A[0][i], A[1][i], A[2][i]] for i in range(5)]
    args = ["transform"] + transform_args(task, v)
    for p in points:
        args += ["--point", csv(p)]
    out = ok(args)
    assert_near(out["matrix"], v["M"], what="M")
    H = v["homogeneous_result_4x5"]
    C = v["cartesian_result_3x5"]
    assert_near(out["homogeneous"], [[H[r][i] for r in range(4)] for i in range(5)], what="homogeneous")
    assert_near(out["cartesian"], [[C[r][i] for r in range(3)] for i in range(5)], what="cartesian")


def test_transform_composes_in_order():
    # Rotate (0,0,2)... first translate by x = 1, then rotate 90 deg about z.
    out = ok(["transform", "--translate", "1,0,0", "--rotate", "z,90", "--deg", "--point", "0,0,2"])
    assert_near(out["cartesian"], [[0.0, 1.0, 2.0]], 1e-12 if not FLOAT else 1e-6)
    out = ok(["transform", "--rotate", "z,90", "--translate", "1,0,0", "--deg", "--point", "0,0,2"])
    assert_near(out["cartesian"], [[1.0, 0.0, 2.0]], 1e-12 if not FLOAT else 1e-6)


def test_transform_vanishing_plane_is_null():
    out = ok(["transform", "--perspective", "z,2", "--point", "0,0,2", "--point", "0,0,1"])
    assert out["homogeneous"][0][3] == 0
    assert out["cartesian"][0] is None
    assert_near(out["cartesian"][1], [0.0, 0.0, 2.0])


# ---- batch ----

def test_batch_many_lines_in_order():
    reqs = []
    expect = []
    for i, c in enumerate(FK["puma560"]["configs"][:20]):
        reqs.append(json.dumps({"op": "fk", "model": "puma560", "q": c["q_rad"], "id": i}))
        expect.append(("pose", c["T"], i))
        if i % 5 == 2:
            reqs.append('{"op": "fk", "model": "puma560", "q": [1, 2]}')
            expect.append(("error", "q has 2 values but the model has 6 joints", None))
            reqs.append("this is not json")
            expect.append(("error", "invalid JSON", None))
            reqs.append('{"op": "teleport"}')
            expect.append(("error", "unknown op", None))
            reqs.append('{"op": "fk", "model": "nosuch", "q": [0]}')
            expect.append(("error", "unknown model", None))
            reqs.append('{"op": "fk", "model": "puma560", "q": [0,0,0,0,0,0], "frmaes": true}')
            expect.append(("error", "unknown key \\\"frmaes\\\"", None))
    reqs.append(json.dumps({"op": "jacobian", "model": "rrr3", "q": FK["rrr"]["configs"][3]["q_rad"]}))
    expect.append(("jacobian", FK["rrr"]["configs"][3]["J0_6x3"], None))
    reqs.append(json.dumps({"op": "orient", "from": "rpy", "to": "matrix", "deg": True, "values": [0, 0, 90]}))
    expect.append(("matrix", [[1, 0, 0], [0, 0, -1], [0, 1, 0]], None))
    reqs.append(json.dumps({"op": "transform", "ops": [{"translate": [1, 2, 3]}, {"rotate": {"axis": "z", "angle": 90}},
                                                      {"scale": 2}, {"perspective": {"axis": "x", "f": 100}}],
                            "deg": True, "points": [[0, 0, 0]]}))
    expect.append(("matrix", None, None))
    reqs.append(json.dumps({"op": "fk", "model_file": os.path.join(MODELS, "panda.cfg"), "q": FK["panda"]["configs"][2]["q_rad"]}))
    expect.append(("pose", FK["panda"]["configs"][2]["T_tool"], None))
    stdin = "\n".join(reqs[:10]) + "\n\n" + "\n".join(reqs[10:]) + "\n"
    r = run(["batch"], stdin)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert len(lines) == len(expect)
    for line, (key, want, ident) in zip(lines, expect):
        ans = json.loads(line)
        if key == "error":
            assert set(ans) <= {"error", "id"} and want.replace('\\"', '"') in ans["error"], line
            assert ans["error"].startswith("line "), line
        else:
            assert key in ans, line
            if want is not None:
                assert_near(ans[key], want, TOL, line)
        if ident is not None:
            assert ans["id"] == ident


def test_batch_transform_equals_cli():
    cli = ok(["transform", "--translate", "1,2,3", "--rotate", "y,30", "--deg", "--point", "1,1,1"])
    line = json.dumps({"op": "transform", "deg": True, "ops": [{"translate": [1, 2, 3]}, {"rotate": {"axis": "y", "angle": 30}}],
                       "points": [[1, 1, 1]]})
    r = run(["batch"], line + "\n")
    assert json.loads(r.stdout) == cli


def test_batch_warnings_in_line():
    r = run(["batch"], '{"op":"fk","model":"puma560","q":[0,0,0,0,0,5]}\n')
    ans = json.loads(r.stdout)
    assert "pose" in ans and "outside joint 6" in ans["warnings"][0]


def test_batch_no_trailing_newline_and_empty_input():
    r = run(["batch"], '{"op":"orient","from":"quat","to":"quat","values":[1,0,0,0]}')
    assert json.loads(r.stdout)["quat"] == [1, 0, 0, 0]
    r = run(["batch"], "")
    assert r.returncode == 0 and r.stdout == ""


# ---- bad input: non-zero exit, a clear message on stderr, nothing on stdout ----

BAD = [
    (["fk", "--model", "nosuch", "--q", "0"], "unknown model \"nosuch\""),
    (["fk", "--model", "puma560", "--q", "0,0,0"], "q has 3 values but the model has 6 joints"),
    (["fk", "--model", "puma560", "--q", "0,0,nan,0,0,0"], "not a finite number: \"nan\""),
    (["fk", "--model", "puma560", "--q", "0,0,inf,0,0,0"], "not a finite number"),
    (["fk", "--model", "puma560", "--q", "0,0,1e999,0,0,0"], "not a finite number"),
    (["fk", "--model", "puma560", "--q", "0,0,abc,0,0,0"], "not a number: \"abc\""),
    (["fk", "--model", "puma560", "--q", "0,,0,0,0,0"], "empty number"),
    (["fk", "--model", "puma560"], "missing q"),
    (["fk", "--q", "0"], "give a model"),
    (["fk", "--model", "puma560", "--model-file", "x.cfg", "--q", "0"], "not both"),
    (["fk", "--model", "puma560", "--q"], "--q needs a value"),
    (["fk", "--model", "puma560", "--model", "panda", "--q", "0"], "--model given twice"),
    (["fk", "--model", "puma560", "--qq", "0"], "unknown option \"--qq\""),
    (["fk", "--model", "puma560", "-q", "0"], "unknown option \"-q\""),
    (["fk", "--model", "puma560", "--q", "0,0,0,0,0,0", "extra"], "unexpected argument \"extra\""),
    (["fk", "--model", "puma560", "--frames=yes", "--q", "0,0,0,0,0,0"], "--frames takes no value"),
    (["fk", "--model-file", "/nonexistent/robot.cfg", "--q", "0"], "/nonexistent/robot.cfg: cannot open"),
    (["fk", "--model", "puma560", "--param", "l1=1", "--q", "0,0,0,0,0,0"], "model puma560 takes no parameters"),
    (["fk", "--model", "rrr3", "--param", "l4=1", "--q", "0,0,0"], "no parameter \"l4\""),
    (["fk", "--model", "rrr3", "--param", "l1=-1", "--q", "0,0,0"], "l1 must be > 0"),
    (["fk", "--model", "rrr3", "--param", "l1", "--q", "0,0,0"], "expected NAME=VALUE"),
    (["jacobian", "--model", "panda", "--q", "0,0,0,0,0,0"], "q has 6 values but the model has 7 joints"),
    (["orient", "--from", "rpy", "--to", "quat", "1", "2"], "rpy takes 3 values, got 2"),
    (["orient", "--from", "euler", "--to", "quat", "1", "2", "3"], "unknown from form \"euler\""),
    (["orient", "--from", "rpy", "1", "2", "3"], "missing to"),
    (["orient", "--from", "quat", "--to", "rpy", "0", "0", "0", "0"], "must not be zero"),
    (["orient", "--from", "axis-angle", "--to", "rpy", "0", "0", "0", "1"], "axis must not be zero"),
    (["orient", "--from", "matrix", "--to", "rpy", "1", "0", "0", "0", "1", "0", "0", "0", "2"], "not a rotation"),
    (["orient", "--from", "rpy", "--to", "quat", "1", "nan", "3"], "not a finite number"),
    (["transform", "--point", "1,2,3"], "at least one operation"),
    (["transform", "--rotate", "w,90", "--point", "1,2,3"], "AXIS x, y or z"),
    (["transform", "--translate", "1,2", "--point", "1,2,3"], "expected DX,DY,DZ"),
    (["transform", "--scale", "0", "--point", "1,2,3"], "scale must not be 0"),
    (["transform", "--perspective", "z,0", "--point", "1,2,3"], "focal length must not be 0"),
    (["transform", "--translate", "1,2,3", "--point", "1,2"], "expected X,Y,Z"),
    (["teleport"], "unknown subcommand \"teleport\""),
    ([], "usage: kinctl-calc SUBCOMMAND"),
]


@pytest.mark.parametrize("args,message", BAD, ids=[" ".join(a) or "(none)" for a, _ in BAD])
def test_bad_input(args, message):
    r = run(args)
    assert r.returncode != 0
    assert r.returncode == 2
    assert message in r.stderr, r.stderr
    assert r.stdout == ""


def test_bad_model_file(tmp_path):
    bad = tmp_path / "bad.cfg"
    bad.write_text('robot = {\n  name = "x"; angles = "rad";\n  dh = (\n'
                   '    { type = "revolute"; a = 0.1; alpha = 0.0; d = 0.0; theta = 0.0;\n'
                   '      limits = { q = [1.0, -1.0]; }; }\n  );\n};\n')
    r = run(["fk", "--model-file", bad, "--q", "0"])
    assert r.returncode == 2
    assert f"{bad}:5: dh row 1 limits: q min 1 > max -1" in r.stderr
    assert r.stdout == ""
    bad.write_text('robot = {\n  name = "x"; angles = "rad";\n  dh = (\n'
                   '    { type = "revolut"; a = 0.1; alpha = 0.0; d = 0.0; theta = 0.0; }\n  );\n};\n')
    r = run(["jacobian", "--model-file", bad, "--q", "0"])
    assert r.returncode == 2 and f"{bad}:4: dh row 1: unknown joint type \"revolut\"" in r.stderr


# ---- help ----

@pytest.mark.parametrize("sub", ["fk", "jacobian", "orient", "transform", "batch"])
def test_help(sub):
    r = run([sub, "--help"])
    assert r.returncode == 0
    assert r.stdout.startswith("usage: kinctl-calc " + sub) and "Example: " in r.stdout


def test_main_help_lists_subcommands():
    r = run(["--help"])
    assert r.returncode == 0
    for sub in ["fk", "jacobian", "orient", "transform", "batch"]:
        assert f"\n  {sub} " in r.stdout
