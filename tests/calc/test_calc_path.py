# SPDX-License-Identifier: BSD-3-Clause
"""Black-box tests of `kinctl-calc interp path`: every smoothing.json case
(tables 7.1 quartic and parabolic blends, 7.2 Lagrange, 7.3 cubic Hermite)
through the CLI's CSV rows, batch rows equal to CSV rows, joint paths from
the limits, Cartesian paths, and bad input.

Tolerances as in tests/unit/test_path.c: the file's 1e-9 absolute in double
(and 1e-10 relative for the large Lagrange values); in float 64 u (max|x| +
t_span max|x'|) with u = 2^-24 (each value is a few tens of roundings of
inputs rounded to float, with the tick time off by a few u t_span), and for
Lagrange 64 u times the first-order perturbation bound of rounded values and
nodes, sum_i |L_i^(m)(t)| (|y_i| + |p'(t_i)| |t_i|) + t_span |p^(m+1)(t)|.

Rows start at t = 0, the start of the motion: for blends that is the knot
time t_0 - t_acc, the first sample of the file (its t_s start there).

Environment: KINCTL_CALC, KINCTL_VECTORS, KINCTL_REAL (see test_calc.py).
"""
import json
import math
import os
import struct
import subprocess

import pytest

CALC = os.environ.get("KINCTL_CALC", "kinctl-calc")
VECTORS = os.environ.get("KINCTL_VECTORS", os.path.join(os.path.dirname(__file__), "..", "vectors"))
FLOAT = os.environ.get("KINCTL_REAL", "double") == "float"
U = 2.0 ** -24 if FLOAT else 2.0 ** -53



def rounded(x):
    """x as the build holds it: an input read into a float build is rounded."""
    return struct.unpack("f", struct.pack("f", x))[0] if FLOAT else x


def same(got, want):
    """Exactly equal in the build's precision (a float row prints 9 digits)."""
    return [rounded(g) for g in got] == [rounded(w) for w in want]


with open(os.path.join(VECTORS, "smoothing.json")) as f:
    SMOOTH = json.load(f)


def run(args, stdin=None):
    return subprocess.run([CALC] + [str(a) for a in args], input=stdin, capture_output=True, text=True, timeout=120)


def csv_rows(args):
    r = run(args)
    assert r.returncode == 0, f"{args}: exit {r.returncode}, stderr: {r.stderr}"
    lines = r.stdout.splitlines()
    header = lines[0].split(",")
    rows = [[float(x) for x in line.split(",")] for line in lines[1:]]
    assert all(len(row) == len(header) for row in rows)
    return header, rows


def bad(args, *words):
    r = run(args)
    assert r.returncode == 2, f"{args}: exit {r.returncode}, stdout {r.stdout[:200]}"
    assert r.stdout == ""
    for w in words:
        assert w in r.stderr, f"{args}: {w!r} not in {r.stderr!r}"
    return r.stderr


def nums(values):
    return ",".join(repr(float(v)) for v in values)


def points(values):
    return ";".join(repr(float(v)) for v in values)


def base_args(method, variant, dt=0.01):
    return ["interp", "path", "--space", "joint", "--method", method, "--points", points(variant["q_knots"]),
            "--times", nums(variant["t_knots_s"]), "--dt", dt]


def max_abs(xs):
    return max(abs(x) for x in xs)


def max_rate(ts, xs, skip):
    m = 0.0
    for k in range(len(xs) - 1):
        if k in skip or k + 1 in skip:
            continue
        m = max(m, abs(xs[k + 1] - xs[k]) / (ts[k + 1] - ts[k]))
    return m


def float_tols(series, ts, skip):
    span = ts[-1] - ts[0]
    q, qd, qdd = series
    return (64 * U * (max_abs(q) + span * max_abs(qd)), 64 * U * (max_abs(qd) + span * max_abs(qdd)),
            64 * U * (max_abs(qdd) + span * max_rate(ts, qdd, skip)))


def compare(rows, ts, series, tols, skip, label, rel=0.0):
    assert len(rows) == len(ts), f"{label}: {len(rows)} rows, {len(ts)} samples"
    for k, row in enumerate(rows):
        assert abs(row[0] - (ts[k] - ts[0])) <= 1e-12 + 4 * U * ts[-1], f"{label}: t of row {k}"
        for m in range(3):
            if m == 2 and k in skip:
                continue
            want = series[m][k]
            t = max(tols[m], rel * abs(want))
            assert abs(row[1 + m] - want) <= t, f"{label}: {['q', 'qd', 'qdd'][m]} at t = {ts[k]}: {row[1 + m]} vs {want}"


# ---- smoothing.json through the CLI ----

@pytest.mark.parametrize("shape", ["quartic", "parabolic"])
@pytest.mark.parametrize("index", range(6))
def test_blend_table(shape, index):
    v = SMOOTH["blend_tables_7_1"][index]
    header, rows = csv_rows(base_args("blend", v) + ["--tacc", v["t_acc_s"], "--blend", shape])
    assert header == ["t", "q1", "qd1", "qdd1"]
    s = v[shape]
    series = (s["q"], s["qdot"], s["qddot"])
    skip = set(s["qddot_ambiguous_indices"])
    tols = float_tols(series, v["t_s"], skip) if FLOAT else (1e-9, 1e-9, 1e-9)
    compare(rows, v["t_s"], series, tols, skip, f"7.1 variant {index + 1} {shape}")
    # The last row is the last knot, at rest.
    assert same([rows[-1][1], rows[-1][2]], [v["q_knots"][-1], 0.0])


def lagrange_float_tols(v):
    x, y = v["t_knots_s"], v["q_knots"]
    c = v["coefficients_ascending_powers_of_t"]
    n = len(x)

    def poly(coef, m, t):
        s = 0.0
        for i in range(len(coef) - 1, m - 1, -1):
            f = 1.0
            for r in range(m):
                f *= i - r
            s = s * t + f * coef[i]
        return s

    basis = []
    for i in range(n):
        coef, den = [1.0], 1.0
        for k in range(n):
            if k == i:
                continue
            coef = [(coef[m - 1] if m > 0 else 0.0) - x[k] * (coef[m] if m < len(coef) else 0.0)
                    for m in range(len(coef) + 1)]
            den *= x[i] - x[k]
        basis.append([b / den for b in coef])
    span = x[-1] - x[0]
    b = [0.0, 0.0, 0.0]
    for t in v["t_s"]:
        for m in range(3):
            s = span * abs(poly(c, m + 1, t))
            for i in range(n):
                s += abs(poly(basis[i], m, t)) * (abs(y[i]) + abs(poly(c, 1, x[i])) * abs(x[i]))
            b[m] = max(b[m], s)
    return tuple(64 * U * bm for bm in b)


@pytest.mark.parametrize("index", range(6))
def test_lagrange_table(index):
    v = SMOOTH["lagrange_tables_7_2"][index]
    _, rows = csv_rows(base_args("lagrange", v))
    series = (v["q"], v["qdot"], v["qddot"])
    if FLOAT:
        compare(rows, v["t_s"], series, lagrange_float_tols(v), set(), f"7.2 variant {index + 1}")
    else:
        compare(rows, v["t_s"], series, (1e-9, 1e-9, 1e-9), set(), f"7.2 variant {index + 1}", rel=1e-10)


@pytest.mark.parametrize("index", range(6))
def test_spline_table(index):
    v = SMOOTH["spline_tables_7_3"][index]
    _, rows = csv_rows(base_args("spline", v) + ["--velocities", points(v["v_knots"])])
    series = (v["q"], v["qdot"], v["qddot"])
    skip = set(v["qddot_ambiguous_indices"])
    tols = float_tols(series, v["t_s"], skip) if FLOAT else (1e-9, 1e-9, 1e-9)
    compare(rows, v["t_s"], series, tols, skip, f"7.3 variant {index + 1}")


def test_batch_rows_equal_csv():
    v = SMOOTH["spline_tables_7_3"][1]
    args = base_args("spline", v) + ["--velocities", points(v["v_knots"])]
    header, rows = csv_rows(args)
    req = {"op": "interp", "kind": "path", "space": "joint", "method": "spline", "points": [[q] for q in v["q_knots"]],
           "times": v["t_knots_s"], "velocities": [[x] for x in v["v_knots"]], "dt": 0.01, "id": 7}
    bad_req = dict(req, times=[0, 1, 1, 2, 3])
    r = run(["batch"], stdin=json.dumps(req) + "\n" + json.dumps(bad_req) + "\n")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    ans = json.loads(lines[0])
    assert ans["id"] == 7 and ans["columns"] == header
    assert len(ans["rows"]) == len(rows)
    for a, b in zip(ans["rows"], rows):
        assert a == pytest.approx(b, rel=0, abs=0)
    err = json.loads(lines[1])
    assert "times must increase strictly" in err["error"]


# ---- joint paths from the limits ----

@pytest.mark.parametrize("method,extra", [("blend", []), ("blend", ["--blend", "parabolic"]), ("lagrange", []),
                                          ("spline", []), ("spline", ["--ends", "natural"]), ("quintic", [])])
def test_limits_kept(method, extra):
    v, a = [1.0, 0.5], [2.0, 4.0]
    pts = "0,0;1,0.4;0.5,1;2,-0.3;2.5,0.2"
    header, rows = csv_rows(["interp", "path", "--space", "joint", "--method", method, "--points", pts,
                             "--v", nums(v), "--a", nums(a), "--dt", 0.002] + extra)
    assert header == ["t", "q1", "q2", "qd1", "qd2", "qdd1", "qdd2"]
    assert same(rows[0][1:3], [0, 0]) and same(rows[-1][1:3], [2.5, 0.2])
    slack = 1 + 1000 * U
    for row in rows:
        for j in range(2):
            assert abs(row[3 + j]) <= v[j] * slack, f"{method}: qd{j + 1} = {row[3 + j]} at t = {row[0]}"
            assert abs(row[5 + j]) <= a[j] * slack, f"{method}: qdd{j + 1} = {row[5 + j]} at t = {row[0]}"


def test_quintic_given_derivatives():
    _, rows = csv_rows(["interp", "path", "--space", "joint", "--method", "quintic", "--points", "0;1;3",
                        "--times", "0,1,2", "--velocities", "0;2;0", "--accelerations", "0;-1;0", "--dt", 0.5])
    assert same([r[0] for r in rows], [0, 0.5, 1, 1.5, 2])
    assert same(rows[2][1:], [1.0, 2.0, -1.0])  # the knot at t = 1: q, qd, qdd as given
    assert same(rows[-1][1:], [3.0, 0.0, 0.0])


# ---- Cartesian ----

def quat_norm(row):
    return math.sqrt(sum(x * x for x in row[4:8]))


@pytest.mark.parametrize("method", ["blend", "lagrange", "spline", "quintic"])
def test_cartesian(method):
    s2 = math.sqrt(0.5)
    pts = f"0.4,0,0.3,1,0,0,0;0.4,0.2,0.3,{s2},0,0,{s2};0.2,0.2,0.5,0,0,0,1;0.2,0,0.5,0,0,0,-1"
    extra = ["--tacc", 0.2] if method == "blend" else []
    header, rows = csv_rows(["interp", "path", "--space", "cartesian", "--method", method, "--points", pts,
                             "--times", "0,1,2,3", "--dt", 0.01] + extra)
    assert header == ["t", "x", "y", "z", "qw", "qx", "qy", "qz", "s", "sd", "sdd"]
    assert same(rows[0][1:8], [0.4, 0.0, 0.3, 1.0, 0.0, 0.0, 0.0])
    assert rows[0][8] == 0.0
    assert same(rows[-1][1:4], [0.2, 0.0, 0.5])
    # The last knot is (0,0,0,-1) = (0,0,0,1) turned no further: the rows keep
    # their sign continuous, so the path ends on (0,0,0,+1).
    assert abs(abs(rows[-1][7]) - 1) <= 16 * U
    for a, b in zip(rows, rows[1:]):
        assert abs(quat_norm(b) - 1) <= 64 * U
        assert sum(x * y for x, y in zip(a[4:8], b[4:8])) > 0, f"sign flip at t = {b[0]}"
        assert b[8] >= a[8] - 16 * U * b[8], f"s decreases at t = {b[0]}"
    # Interpolating methods pass the knots at their times.
    if method != "blend":
        for k, p in ((100, [0.4, 0.2, 0.3, s2, 0, 0, s2]), (200, [0.2, 0.2, 0.5, 0, 0, 0, 1])):
            for got, want in zip(rows[k][1:8], p):
                assert abs(got - want) <= (1e-5 if FLOAT else 1e-9), f"knot at row {k}: {rows[k]}"


def test_cartesian_turn_in_place_needs_angular_limits():
    pts = "0.3,0,0.4,1,0,0,0;0.3,0,0.4,0,1,0,0"
    bad(["interp", "path", "--space", "cartesian", "--method", "spline", "--points", pts, "--v", 1, "--a", 2,
         "--dt", 0.01], "same position", "--omega")
    _, rows = csv_rows(["interp", "path", "--space", "cartesian", "--method", "spline", "--points", pts, "--v", 1,
                        "--a", 2, "--omega", 1, "--epsilon", 2, "--dt", 0.01])
    assert all(r[8] == 0.0 for r in rows)
    assert same(rows[-1][4:8], [0.0, 1.0, 0.0, 0.0])
    # pi / 1 + 1 / 2 s at 0.01 s.
    assert len(rows) - 1 == math.ceil((math.pi + 0.5) / 0.01 - 1e-6)


def test_cartesian_quaternion_normalised_with_warning():
    r = run(["interp", "path", "--space", "cartesian", "--method", "spline", "--points",
             "0,0,0,2,0,0,0;1,0,0,2,0,0,0", "--times", "0,1", "--dt", 0.5])
    assert r.returncode == 0, r.stderr
    assert "normalised" in r.stderr
    assert r.stdout.splitlines()[1].split(",")[4] == "1"


# ---- bad input ----

J = ["interp", "path", "--space", "joint"]


@pytest.mark.parametrize("args,words", [
    (J + ["--method", "blend", "--times", "0,1", "--tacc", 0.1, "--dt", 0.01], ["--points"]),
    (J + ["--method", "spline", "--points", "1", "--times", "0", "--dt", 0.01], ["at least 2 points"]),
    (J + ["--method", "spline", "--points", "0;1;2", "--times", "0,1,1", "--dt", 0.01], ["increase strictly"]),
    (J + ["--method", "spline", "--points", "0;1;2", "--times", "0,2,1", "--dt", 0.01], ["increase strictly"]),
    (J + ["--method", "spline", "--points", "0;1;2", "--times", "0,1", "--dt", 0.01], ["one per point"]),
    (J + ["--method", "blend", "--points", "0;1;2", "--times", "0,1,2", "--dt", 0.01], ["--tacc"]),
    (J + ["--method", "blend", "--points", "0;1;2", "--times", "0,1,2", "--tacc", 0.6, "--dt", 0.01], ["overlap"]),
    (J + ["--method", "blend", "--points", "0;1;2", "--times", "0,1,2", "--tacc", -1, "--dt", 0.01], ["> 0"]),
    (J + ["--method", "blend", "--points", "0;1", "--times", "0,1", "--tacc", 0.1, "--velocities", "0;0",
          "--dt", 0.01], ["spline and quintic"]),
    (J + ["--method", "spline", "--points", "0;1", "--times", "0,1", "--accelerations", "0;0", "--dt", 0.01],
     ["quintic only"]),
    (J + ["--method", "spline", "--points", "0;1;2", "--times", "0,1,2", "--velocities", "0;0", "--dt", 0.01],
     ["one per knot"]),
    (J + ["--method", "spline", "--points", "0,1;1;2", "--times", "0,1,2", "--dt", 0.01], ["same count"]),
    (J + ["--method", "lagrange", "--points", points(range(9)), "--times", nums(range(9)), "--dt", 0.01],
     ["at most 8"]),
    (J + ["--method", "spline", "--points", points(range(33)), "--times", nums(range(33)), "--dt", 0.01],
     ["more than the 32"]),
    (J + ["--method", "spline", "--points", "0;nan", "--times", "0,1", "--dt", 0.01], ["finite"]),
    (J + ["--method", "spline", "--points", "0;1", "--times", "0,1", "--dt", 0], ["dt must be > 0"]),
    (J + ["--method", "spline", "--points", "0;1", "--times", "0,1", "--dt", 1e-7], ["rows"]),
    (J + ["--method", "spline", "--points", "0;1", "--dt", 0.01], ["--v and --a"]),
    (J + ["--method", "spline", "--points", "0;1", "--v", 0, "--a", 1, "--dt", 0.01], ["> 0"]),
    (J + ["--method", "spline", "--points", "0,0;1,1", "--v", "1,2,3", "--a", 1, "--dt", 0.01], ["one per"]),
    (J + ["--method", "spline", "--points", "0;0;1", "--v", 1, "--a", 1, "--dt", 0.01], ["without motion"]),
    (J + ["--method", "blend", "--points", "0;1;0", "--v", 1, "--a", 1, "--tacc", 0.1, "--dt", 0.01],
     ["too short"]),
    (J + ["--method", "spline", "--points", "0;1", "--times", "0,1", "--omega", 1, "--dt", 0.01], ["cartesian"]),
    (J + ["--method", "bezier", "--points", "0;1", "--times", "0,1", "--dt", 0.01], ["unknown method"]),
    (J + ["--method", "lagrange", "--blend", "parabolic", "--points", "0;1", "--times", "0,1", "--dt", 0.01],
     ["--blend"]),
    (J + ["--method", "spline", "--ends", "loose", "--points", "0;1", "--times", "0,1", "--dt", 0.01], ["unknown ends"]),
    (["interp", "path", "--space", "polar", "--method", "spline", "--points", "0;1", "--times", "0,1", "--dt", 0.01],
     ["unknown space"]),
    (["interp", "path", "--space", "cartesian", "--method", "spline", "--points", "0,0,0,1,0,0;1,0,0,1,0,0",
      "--times", "0,1", "--dt", 0.01], ["7 numbers"]),
    (["interp", "path", "--space", "cartesian", "--method", "spline", "--points", "0,0,0,0,0,0,0;1,0,0,1,0,0,0",
      "--times", "0,1", "--dt", 0.01], ["zero"]),
    (["interp", "path", "--space", "cartesian", "--method", "spline", "--points", "0,0,0,1,0,0,0;1,0,0,1,0,0,0",
      "--times", "0,1", "--omega", 1, "--dt", 0.01], ["both --omega and --epsilon"]),
])
def test_bad_input(args, words):
    bad(args, *words)
