# SPDX-License-Identifier: BSD-3-Clause
"""kinctl-calc ik (and the ik batch op) against tests/vectors/ik.json, the
target forms, masks, --deg, and bad input.

Environment as test_calc.py: KINCTL_CALC, KINCTL_VECTORS, KINCTL_REAL.
"""
import json
import math
import os
import subprocess

CALC = os.environ.get("KINCTL_CALC", "kinctl-calc")
VECTORS = os.environ.get("KINCTL_VECTORS", os.path.join(os.path.dirname(__file__), "..", "vectors"))
FLOAT = os.environ.get("KINCTL_REAL", "double") == "float"
# ik.json's acceptance: every entry of FK(q) within 1e-6 of the target; in a
# float build the solver stops at 1e-5 m / 1e-4 rad.
TOL = 1e-4 if FLOAT else 1e-6

with open(os.path.join(VECTORS, "ik.json")) as f:
    IK = json.load(f)
QLIM = [row["qlim_rad"] for row in IK["dh_table"]]


def run(args, stdin=None):
    return subprocess.run([CALC] + [str(a) for a in args], input=stdin, capture_output=True, text=True, timeout=120)


def batch(requests):
    r = run(["batch"], "\n".join(json.dumps(q) for q in requests) + "\n")
    assert r.returncode == 0, r.stderr
    return [json.loads(line) for line in r.stdout.splitlines()]


def flat(T):
    return [v for row in T for v in row]


def csv(values):
    return ",".join(repr(float(v)) for v in values)


def quat_of(T):
    """w, x, y, z of a rotation matrix (w >= 0), by Shepperd's method."""
    m = T
    tr = m[0][0] + m[1][1] + m[2][2]
    cands = [tr, m[0][0], m[1][1], m[2][2]]
    i = max(range(4), key=lambda k: cands[k])
    if i == 0:
        s = math.sqrt(1 + tr) * 2
        q = [s / 4, (m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s]
    elif i == 1:
        s = math.sqrt(1 + m[0][0] - m[1][1] - m[2][2]) * 2
        q = [(m[2][1] - m[1][2]) / s, s / 4, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s]
    elif i == 2:
        s = math.sqrt(1 + m[1][1] - m[0][0] - m[2][2]) * 2
        q = [(m[0][2] - m[2][0]) / s, (m[0][1] + m[1][0]) / s, s / 4, (m[1][2] + m[2][1]) / s]
    else:
        s = math.sqrt(1 + m[2][2] - m[0][0] - m[1][1]) * 2
        q = [(m[1][0] - m[0][1]) / s, (m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, s / 4]
    return [-v for v in q] if q[0] < 0 else q


def fk_all(qs):
    answers = batch([{"op": "fk", "model": "puma560", "q": q} for q in qs])
    return [a["pose"] for a in answers]


def max_diff(A, B):
    return max(abs(a - b) for ra, rb in zip(A, B) for a, b in zip(ra, rb))


def check_solutions(answers, targets):
    poses = fk_all([a["q"] for a in answers])
    for i, (a, T, P) in enumerate(zip(answers, targets, poses)):
        assert a["status"] == "converged", f"target {i}: {a}"
        assert max_diff(P, T) <= TOL, f"target {i}: FK(q) off by {max_diff(P, T)}"
        for j, (v, (lo, hi)) in enumerate(zip(a["q"], QLIM)):
            assert lo <= v <= hi, f"target {i}: q[{j}] = {v} outside [{lo}, {hi}]"
        assert a["position_error"] <= 1e-5 and a["orientation_error"] <= 1e-4


def test_vectors_batch_from_q_start():
    targets = [t["T_target"] for t in IK["targets"]]
    answers = batch([{"op": "ik", "model": "puma560", "target": flat(T), "q0": IK["q_start_rad"], "mask": "full"}
                     for T in targets])
    assert len(answers) == len(targets)
    check_solutions(answers, targets)


def test_command_line_both_target_forms_agree():
    for t in IK["targets"][:10]:
        T = t["T_target"]
        a = json.loads(run(["ik", "--model", "puma560", "--target", csv(flat(T)), "--q0", csv(IK["q_start_rad"])]).stdout)
        pose7 = [T[0][3], T[1][3], T[2][3]] + quat_of(T)
        b = json.loads(run(["ik", "--model", "puma560", "--target", csv(pose7), "--q0", csv(IK["q_start_rad"])]).stdout)
        check_solutions([a, b], [T, T])


def test_deg_reports_the_same_solution_in_degrees():
    T = IK["targets"][3]["T_target"]
    q0 = IK["q_start_rad"]
    rad = json.loads(run(["ik", "--model", "puma560", "--target", csv(flat(T)), "--q0", csv(q0)]).stdout)
    deg = json.loads(run(["ik", "--model", "puma560", "--deg", "--target", csv(flat(T)),
                          "--q0", csv([math.degrees(v) for v in q0])]).stdout)
    assert deg["status"] == "converged"
    # The same solve; only the unit of q differs (a float build rounds the
    # conversion to about 1e-7 relative).
    for r, d in zip(rad["q"], deg["q"]):
        assert abs(math.radians(d) - r) <= (1e-6 if FLOAT else 1e-9)


def test_position_mask_reaches_the_point():
    answers = batch([{"op": "ik", "model": "panda", "target": [0.4, 0.2, 0.5, 1, 0, 0, 0], "mask": "position"}])
    a = answers[0]
    assert a["status"] == "converged", a
    pose = batch([{"op": "fk", "model": "panda", "q": a["q"]}])[0]["pose"]
    for i, want in enumerate([0.4, 0.2, 0.5]):
        assert abs(pose[i][3] - want) <= TOL


def test_unreachable_target():
    a = json.loads(run(["ik", "--model", "puma560", "--target", "3,0,0,1,0,0,0"]).stdout)
    assert a["status"] == "unreachable" and a["q"] is None and a["position_error"] is None


def test_bad_input():
    T = flat(IK["targets"][0]["T_target"])
    not_rigid = list(T)
    not_rigid[0] = 2.0
    cases = [
        (["ik", "--model", "puma560", "--target", "1,2,3"], "16"),
        (["ik", "--model", "puma560", "--target", csv(not_rigid)], "rigid"),
        (["ik", "--model", "puma560", "--target", "0.5,0,0.5,0,0,0,0"], "zero"),
        (["ik", "--model", "puma560", "--target", csv(T), "--mask", "orientation"], "mask"),
        (["ik", "--model", "puma560", "--target", csv(T), "--q0", "0,0,0"], "q0"),
        (["ik", "--model", "puma560", "--target", "nan,0,0,1,0,0,0"], "target"),
        (["ik", "--model", "puma560"], "target"),
        (["ik", "--target", csv(T)], "model"),
    ]
    for args, word in cases:
        r = run(args)
        assert r.returncode == 2, f"{args}: exit {r.returncode}, stdout {r.stdout}"
        assert word in r.stderr, f"{args}: stderr {r.stderr!r} lacks {word!r}"
        assert r.stdout == ""


def test_a_miss_says_where_it_stopped():
    # rrr3's arm is 0.55 m from the shoulder at (0, 0, 0.4): a point 0.6 m
    # away is inside the reach bound but only the stretched, singular arm
    # comes close.
    a = json.loads(run(["ik", "--model", "rrr3", "--mask", "position", "--target", "0.6,0,0.4,1,0,0,0"]).stdout)
    assert a["status"] == "singular", a
    assert len(a["q"]) == 3 and 0.05 - 1e-6 <= a["position_error"] <= 0.051
