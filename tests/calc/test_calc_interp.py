# SPDX-License-Identifier: BSD-3-Clause
"""Black-box tests of `kinctl-calc interp`: its CSV rows against
tests/vectors (joint_trapezoid, cartesian_line, circle: every case), batch
rows equal to CSV rows, and bad input.

Tolerances as in tests/unit/test_interp.c: the files' 1e-9 in double; in
float 64 float ulps (7.6e-6) of the largest value of each quantity in a case
(at least 1): the float build rounds every input and evaluates each value in
a few tens of operations, each within half an ulp of that scale. Samples that
fall on a phase boundary (the files' *_ambiguous_indices; in float also those
within 8 ulps of one) are not compared for acceleration.

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
EPS = 1.1920929e-07 if FLOAT else 2.220446049250313e-16


def load(name):
    with open(os.path.join(VECTORS, name)) as f:
        return json.load(f)


JOINT = load("joint_trapezoid.json")
LINE = load("cartesian_line.json")
CIRCLE = load("circle.json")


def tol(scale):
    return 64 * EPS * max(scale, 1.0) if FLOAT else 1e-9


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


def nums(values):
    return ",".join(repr(float(v)) for v in values)


def flat(m):
    return [x for row in m for x in row]


def max_abs(values):
    if isinstance(values, list):
        return max((max_abs(v) for v in values), default=0.0)
    return abs(values)


def near(got, want, t, what):
    assert abs(got - want) <= t, f"{what}: {got} vs {want} (tol {t})"


def on_boundary(t, bounds):
    return FLOAT and any(abs(t - b) <= 8 * EPS * max(b, 1.0) for b in bounds)


def quat_to_matrix(w, x, y, z):
    return [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
            2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
            2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]


def f32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


def exact(got, want):
    """The build's own rounding of want: the CLI's rows hold exactly what was
    given (9 digits in float, which read back as the float value)."""
    return [f32(g) for g in got] == [f32(w) for w in want] if FLOAT else got == want


def pair_rows(rows, ts, T, dt=0.01):
    """Pairs (row, sample index, compare accelerations) of the CLI's rows and
    the file's samples: one row per tick from 0 to the end inclusive, at k dt;
    the last row is the first tick at or after T, the file's last sample is T
    itself. In float, T within rounding of a tick may end one tick later:
    that extra row lies within rounding of T and is compared to the last
    sample too (not its acceleration, which jumps there)."""
    n = len(ts)
    extra = len(rows) - n
    assert extra == 0 or (FLOAT and extra == 1 and on_boundary(rows[-2][0], [T])), (len(rows), n)
    for k, row in enumerate(rows):
        near(row[0], k * dt, 1e-12 if not FLOAT else 1e-6 * max(1.0, k * dt), f"t of row {k}")
    assert rows[-1][0] >= T - 1e-6 and (len(rows) == 1 or rows[-2][0] < T + (1e-6 if FLOAT else 0.0))
    pairs = [(rows[i], i, True) for i in range(n - 1)]
    if extra:
        pairs.append((rows[n - 1], n - 1, False))
    pairs.append((rows[-1], n - 1, True))
    return pairs


# ---- joint_trapezoid.json ----

JOINT_ARGS = [(c["case"], c) for c in JOINT["cases"]]


@pytest.mark.parametrize("name,case", JOINT_ARGS, ids=[c[0] for c in JOINT_ARGS])
def test_joint_vectors(name, case):
    header, rows = csv_rows(["interp", "joint", "--model", "planar2", "--deg", "--q0", nums(case["q_start_deg"]),
                             "--q1", nums(case["q_end_deg"]), "--vmax", case["v_deg_s"], "--amax", case["A_deg_s2"],
                             "--profile", "trapezoid", "--dt", "0.01"])
    assert header == ["t", "q1", "q2", "qd1", "qd2", "qdd1", "qdd2"]
    s = case["samples"]
    T = case["T_total_s"]
    bounds = [case["t_p_s"], case["t_p_s"] + case["t_pv_s"], T]
    amb = set(s["qddot_ambiguous_indices"])
    tq, tv, ta = tol(max_abs(s["q_deg"])), tol(max_abs(s["qdot_deg_s"])), tol(max_abs(s["qddot_deg_s2"]))
    for row, i, acc in pair_rows(rows, s["t_s"], T):
        t = s["t_s"][i]
        for j in range(2):
            near(row[1 + j], s["q_deg"][j][i], tq, f"q{j + 1} at {t}")
            near(row[3 + j], s["qdot_deg_s"][j][i], tv, f"qdot{j + 1} at {t}")
            if acc and i not in amb and not on_boundary(t, bounds):
                near(row[5 + j], s["qddot_deg_s2"][j][i], ta, f"qddot{j + 1} at {t}")
    # Ends exactly where asked, at rest.
    assert exact(rows[0][1:3], case["q_start_deg"])
    assert exact(rows[-1][1:3], case["q_end_deg"]) and rows[-1][3:] == [0.0] * 4


def batch(requests):
    r = run(["batch"], "".join(json.dumps(q) + "\n" for q in requests))
    assert r.returncode == 0, r.stderr
    return [json.loads(line) for line in r.stdout.splitlines()]


def test_joint_batch_gives_the_leading_joint_and_duration():
    # Equal limits (the seed's tables): the leading joint of (4.2) and the file's total time.
    answers = batch([{"op": "interp", "kind": "joint", "model": "planar2", "deg": True, "q0": c["q_start_deg"],
                      "q1": c["q_end_deg"], "vmax": [c["v_deg_s"]], "amax": [c["A_deg_s2"]], "dt": 100.0,
                      "profile": "trapezoid"}
                     for c in JOINT["cases"]])
    for c, a in zip(JOINT["cases"], answers):
        moving = any(x != y for x, y in zip(c["q_start_deg"], c["q_end_deg"]))
        assert a["lead"] == (c["leading_joint"] if moving else 0), c["case"]
        near(a["duration"], c["T_total_s"], tol(c["T_total_s"]), c["case"] + " duration")
    # Per-joint limits (puma560: joints 1-3 2 rad/s, 5 rad/s^2; 4-6 4 rad/s, 10 rad/s^2): joint 6 moves
    # farther (1.3 rad) but alone would take 2 sqrt(1.3 / 10) = 0.72 s, joint 1 (1.2 rad) 1.2 / 2 + 2 / 5 = 1 s.
    a, = batch([{"op": "interp", "kind": "joint", "model": "puma560", "q0": [0] * 6, "q1": [1.2, 0, 0, 0, 0, 1.3],
                 "dt": 0.01, "profile": "trapezoid"}])
    assert a["lead"] == 1
    near(a["duration"], 1.0, 1e-12 if not FLOAT else 1e-6, "duration")
    # CSV has no room for them: unchanged.
    header, _ = csv_rows(["interp", "joint", "--model", "planar2", "--q0", "0,0", "--q1", "1,1", "--dt", "0.1",
                          "--profile", "trapezoid"])
    assert header == ["t", "q1", "q2", "qd1", "qd2", "qdd1", "qdd2"]


def test_joint_radians_equal_degrees():
    c = JOINT["cases"][2]
    _, deg = csv_rows(["interp", "joint", "--model", "planar2", "--deg", "--q0", nums(c["q_start_deg"]),
                       "--q1", nums(c["q_end_deg"]), "--vmax", c["v_deg_s"], "--amax", c["A_deg_s2"], "--dt", "0.002"])
    r = math.radians
    _, rad = csv_rows(["interp", "joint", "--model", "planar2", "--q0", nums(map(r, c["q_start_deg"])),
                       "--q1", nums(map(r, c["q_end_deg"])), "--vmax", r(c["v_deg_s"]), "--amax", r(c["A_deg_s2"]),
                       "--dt", "0.002"])
    assert len(deg) == len(rad)
    for a, b in zip(deg, rad):
        for x, y in zip(a[1:], b[1:]):
            near(math.radians(x), y, 1e-9 if not FLOAT else 1e-4, "deg vs rad")


def test_joint_model_limits_and_per_joint():
    # planar2's limits are 80 deg/s and 800 deg/s^2 for both joints.
    _, model = csv_rows(["interp", "joint", "--model", "planar2", "--deg", "--q0", "0,0", "--q1", "90,-30", "--dt", "0.01"])
    _, given = csv_rows(["interp", "joint", "--model", "planar2", "--deg", "--q0", "0,0", "--q1", "90,-30",
                         "--vmax", "80,80", "--amax", "800", "--dt", "0.01"])
    assert model == given
    # Per-joint limits: joint 2 slow. Every joint within its own limits,
    # both at the same fraction of their moves.
    _, rows = csv_rows(["interp", "joint", "--model", "planar2", "--deg", "--q0", "0,0", "--q1", "90,-30",
                        "--vmax", "80,10", "--amax", "800,50", "--profile", "trapezoid", "--dt", "0.01"])
    for row in rows:
        assert abs(row[3]) <= 80 * (1 + 1e-6) and abs(row[4]) <= 10 * (1 + 1e-6)
        assert abs(row[5]) <= 800 * (1 + 1e-6) and abs(row[6]) <= 50 * (1 + 1e-6)
        near(row[1] / 90.0, row[2] / -30.0, 1e-9 if not FLOAT else 1e-5, "same fraction")
    assert max(abs(row[4]) for row in rows) >= 10 * (1 - 1e-6)  # joint 2 leads
    # Stretched to 3 s: the last row is the first tick at or after 3 s.
    _, rows = csv_rows(["interp", "joint", "--model", "planar2", "--deg", "--q0", "0,0", "--q1", "90,-30",
                        "--duration", "3", "--dt", "0.01"])
    near(rows[-1][0], 3.0, 1e-9 if not FLOAT else 1e-5, "stretched end")


# ---- jerk-limited joint moves (the default; --profile jerk) ----

PANDA_QD = [2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61]
PANDA_QDD = [15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0]
PANDA_QDDD = [7500.0, 3750.0, 5000.0, 6250.0, 7500.0, 10000.0, 10000.0]


def rest_to_rest_time(D, V, A, J):
    """The fastest rest-to-rest time over D, independent of the calculator's closed form: reaching a speed v
    from rest and stopping take ta(v) = v/A + A/J (v >= A^2/J) or 2 sqrt(v/J) each, over v ta(v) together;
    the move cruises at the largest v <= V with v ta(v) <= D (bisection)."""
    if D == 0.0:
        return 0.0

    def ta(v):
        return v / A + A / J if v >= A * A / J else 2.0 * math.sqrt(v / J)

    v = V
    if v * ta(v) > D:
        lo, hi = 0.0, V
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if mid * ta(mid) > D else (mid, hi)
        v = lo
    return 2.0 * ta(v) + (D - v * ta(v)) / v


def check_jerk_rows(header, rows, n, q0, q1, vmax, amax, jmax, dt):
    """Every row within each joint's limits; jerk as the change of qdd per row over dt, with the slack of
    tests/unit/test_scurve.c (rounding of t = k dt and of the sums: 8 eps (A + J T)); qddd within J; the
    first row q0 at rest, the last q1 at rest, on one row for every joint."""
    assert header == ["t"] + [f"{s}{i + 1}" for s in ("q", "qd", "qdd", "qddd") for i in range(n)]
    T = rows[-1][0]
    for i in range(n):
        assert rows[0][1 + i] == q0[i] and rows[0][1 + n + i] == 0.0 and rows[0][1 + 2 * n + i] == 0.0
        assert rows[-1][1 + i] == q1[i] and rows[-1][1 + n + i] == 0.0 and rows[-1][1 + 2 * n + i] == 0.0
        V, A, J = vmax[i], amax[i], jmax[i]
        slack = 8 * EPS * (A + J * T) + 16 * EPS * J * dt
        for prev, row in zip(rows, rows[1:]):
            assert abs(row[1 + n + i]) <= V * (1 + 16 * EPS) + 4 * EPS * A * T
            assert abs(row[1 + 2 * n + i]) <= A * (1 + 16 * EPS) + 4 * EPS * J * T
            assert abs(row[1 + 2 * n + i] - prev[1 + 2 * n + i]) <= J * dt + slack, (i, row[0])
            assert abs(row[1 + 3 * n + i]) <= J * (1 + 16 * EPS)
    # The joints do not all arrive before the last row: someone still moves on the row before it.
    assert any(rows[-2][1 + n + i] != 0.0 or rows[-2][1 + 2 * n + i] != 0.0 for i in range(n))


def test_joint_jerk_random_moves():
    # Seeded random panda moves (7 joints, the model's limits including its jerk limits) and puma560 moves with
    # given limits (6 joints): limits, jerk, exact ends on one row, and the duration is the slowest joint's
    # independent optimum rounded up to the tick.
    import random
    rng = random.Random(1906)
    for case in range(24):
        panda = case % 2 == 0
        n = 7 if panda else 6
        q0 = [round(rng.uniform(-1.5, 1.5), 6) for _ in range(n)]
        q1 = [round(rng.uniform(-1.5, 1.5), 6) for _ in range(n)]
        dt = rng.choice([0.001, 0.002, 0.004])
        if panda:
            vmax, amax, jmax, extra = PANDA_QD, PANDA_QDD, PANDA_QDDD, []
        else:
            vmax = [round(rng.uniform(0.5, 3.0), 3) for _ in range(n)]
            amax = [round(rng.uniform(2.0, 20.0), 3) for _ in range(n)]
            jmax = [round(rng.uniform(20.0, 500.0), 3) for _ in range(n)]
            extra = ["--vmax", nums(vmax), "--amax", nums(amax), "--jmax", nums(jmax)]
        r = run(["interp", "joint", "--model", "panda" if panda else "puma560", "--q0", nums(q0), "--q1", nums(q1),
                 "--dt", dt] + extra + (["--profile", "jerk"] if case % 4 < 2 else []))
        assert r.returncode == 0, r.stderr
        lines = r.stdout.splitlines()
        header = lines[0].split(",")
        rows = [[float(x) for x in line.split(",")] for line in lines[1:]]
        check_jerk_rows(header, rows, n, q0, q1, vmax, amax, jmax, dt)
        T = max(rest_to_rest_time(abs(b - a), V, A, J) for a, b, V, A, J in zip(q0, q1, vmax, amax, jmax))
        ticks = math.ceil(T / dt - 1e-9)
        assert len(rows) - 1 in (ticks, ticks + 1) and (len(rows) - 2) * dt < T * (1 + 1e-6) and \
            (len(rows) - 1) * dt >= T * (1 - 1e-6), (case, len(rows) - 1, T / dt)


PUMA_QD = [2.0, 2.0, 2.0, 4.0, 4.0, 4.0]
PUMA_QDD = [5.0, 5.0, 5.0, 10.0, 10.0, 10.0]
PUMA_QDDD = [50.0, 50.0, 50.0, 100.0, 100.0, 100.0]  # the built-in model's: ten times qdd


def test_joint_jerk_moving_start():
    # A replacement as kinctld makes it: a move planned from rest is cut at a random row, and a move to
    # another target starts from that row's q, qd and qdd (--qd0, --qdd0). Its first row is that state,
    # every row is within the limits and the jerk, the jerk across the cut too, and it ends exactly on its
    # target at rest with every joint arriving on the last row. Towards the first target again, it lasts
    # exactly what the first move had left: the rest of an optimal move is optimal.
    import random
    rng = random.Random(1919)
    for case in range(16):
        panda = case % 2 == 0
        n = 7 if panda else 6
        V, A, J = (PANDA_QD, PANDA_QDD, PANDA_QDDD) if panda else (PUMA_QD, PUMA_QDD, PUMA_QDDD)
        model = ["--model", "panda" if panda else "puma560"]
        q0 = [round(rng.uniform(-0.06, 0.06) + (-1.5 if panda and i == 3 else 0.0), 6) for i in range(n)]
        qa = [round(rng.uniform(-1.5, 1.5) - (1.5 if panda and i == 3 else 0.0), 6) for i in range(n)]
        qb = [round(rng.uniform(-1.5, 1.5) - (1.5 if panda and i == 3 else 0.0), 6) for i in range(n)]
        dt = 0.001
        _, first = csv_rows(["interp", "joint"] + model + ["--q0", nums(q0), "--q1", nums(qa), "--dt", dt])
        k = rng.randrange(1, len(first) - 2)
        cut = first[k]
        q, qd, qdd = cut[1:1 + n], cut[1 + n:1 + 2 * n], cut[1 + 2 * n:1 + 3 * n]
        for target in (qb, qa):
            _, rows = csv_rows(["interp", "joint"] + model + ["--q0", nums(q), "--qd0", nums(qd), "--qdd0", nums(qdd),
                                                              "--q1", nums(target), "--dt", dt])
            T = rows[-1][0]
            assert rows[0][1:1 + n] == q
            for i in range(n):
                near(rows[0][1 + n + i], qd[i], 1e-12 if not FLOAT else 1e-6, "qd0")
                near(rows[0][1 + 2 * n + i], qdd[i], 1e-12 if not FLOAT else 1e-6, "qdd0")
                slack = 8 * EPS * (A[i] + J[i] * T) + 16 * EPS * J[i] * dt
                # Across the cut: the old move's row k-1, then the new move's rows.
                prev_qdd = first[k - 1][1 + 2 * n + i]
                for row in rows:
                    assert abs(row[1 + n + i]) <= V[i] * (1 + 16 * EPS) + 4 * EPS * A[i] * T, (case, i, row[0])
                    assert abs(row[1 + 2 * n + i]) <= A[i] * (1 + 16 * EPS) + 4 * EPS * J[i] * T, (case, i, row[0])
                    assert abs(row[1 + 2 * n + i] - prev_qdd) <= J[i] * dt + slack, (case, i, row[0])
                    prev_qdd = row[1 + 2 * n + i]
                assert rows[-1][1 + i] == target[i] and rows[-1][1 + n + i] == 0.0 and rows[-1][1 + 2 * n + i] == 0.0
            assert any(rows[-2][1 + n + i] != 0.0 or rows[-2][1 + 2 * n + i] != 0.0 for i in range(n))
        # Towards qa again: the rest of the first move, to the tick.
        assert abs((len(rows) - 1) - (len(first) - 1 - k)) <= 1, (case, len(rows) - 1, len(first) - 1 - k)
    # Not with the trapezoid, which starts at rest.
    r = run(["interp", "joint", "--model", "planar2", "--q0", "0,0", "--q1", "1,1", "--qd0", "0.1,0",
             "--profile", "trapezoid", "--dt", "0.01"])
    assert r.returncode != 0 and "qd0 and qdd0 need the jerk-limited profile" in r.stderr


def test_joint_jerk_batch_duration_and_model_default():
    # Batch gives the duration: the slowest joint's optimum (puma560's jerk limits from the model).
    q1 = [0.4, -0.9, 0.7, 1.5, -1.1, 2.0]
    a, = batch([{"op": "interp", "kind": "joint", "model": "panda", "q0": [0] * 7, "q1": q1 + [0.3],
                 "profile": "jerk", "dt": 0.001}])
    T = max(rest_to_rest_time(abs(q), V, A, J) for q, V, A, J in zip(q1 + [0.3], PANDA_QD, PANDA_QDD, PANDA_QDDD))
    near(a["duration"], T, 1e-9 if not FLOAT else 1e-5, "duration")
    assert a["columns"][-1] == "qddd7"
    # The model's jerk limits are the default: the same rows as given explicitly (and one value for all).
    args = ["interp", "joint", "--model", "panda", "--q0", "0,0,0,0,0,0,0", "--q1", nums(q1 + [0.3]),
            "--profile", "jerk", "--dt", "0.002"]
    _, model = csv_rows(args)
    _, given = csv_rows(args + ["--jmax", nums(PANDA_QDDD)])
    assert model == given
    _, slow = csv_rows(args + ["--jmax", "100"])
    assert len(slow) > len(model)
    check_jerk_rows(_, slow, 7, [0.0] * 7, q1 + [0.3], PANDA_QD, PANDA_QDD, [100.0] * 7, 0.002)
    # Degrees: --jmax in deg/s^3, rows in degrees, the same motion.
    _, deg = csv_rows(["interp", "joint", "--model", "planar2", "--deg", "--q0", "0,0", "--q1", "90,-30",
                       "--vmax", "80", "--amax", "800", "--jmax", "6000", "--profile", "jerk", "--dt", "0.01"])
    _, rad = csv_rows(["interp", "joint", "--model", "planar2", "--q0", "0,0", "--q1",
                       nums([math.radians(90), math.radians(-30)]), "--vmax", math.radians(80), "--amax",
                       math.radians(800), "--jmax", math.radians(6000), "--profile", "jerk", "--dt", "0.01"])
    assert len(deg) == len(rad)
    for a_, b_ in zip(deg, rad):
        for x, y in zip(a_[1:], b_[1:]):
            near(math.radians(x), y, 1e-9 * max(1.0, abs(y)) if not FLOAT else 1e-4 * max(1.0, abs(y)), "deg vs rad")


def test_joint_jerk_stretched_and_trapezoid_default():
    # --duration stretches every joint to end on the same row at the first tick at or after it.
    _, rows = csv_rows(["interp", "joint", "--model", "puma560", "--q0", "0,0,0,0,0,0", "--q1", "1,0.5,0,0,0,-1",
                        "--profile", "jerk", "--jmax", "50", "--duration", "3", "--dt", "0.01"])
    near(rows[-1][0], 3.0, 1e-9 if not FLOAT else 1e-5, "stretched end")
    # Jerk-limited is the default (as the controller's), and --profile jerk is it; --profile trapezoid
    # gives seed 001's trapezoid, without the jerk columns.
    args = ["interp", "joint", "--model", "planar2", "--q0", "0,0", "--q1", "1,1", "--dt", "0.01"]
    h1, r1 = csv_rows(args)
    h2, r2 = csv_rows(args + ["--profile", "jerk"])
    h3, r3 = csv_rows(args + ["--profile", "trapezoid"])
    assert h1 == h2 == ["t", "q1", "q2", "qd1", "qd2", "qdd1", "qdd2", "qddd1", "qddd2"] and r1 == r2
    assert h3 == ["t", "q1", "q2", "qd1", "qd2", "qdd1", "qdd2"] and len(r3) < len(r1)


# ---- cartesian_line.json ----

LINE_ARGS = [(c["case"], c) for c in LINE["cases"]]


@pytest.mark.parametrize("name,case", LINE_ARGS, ids=[c[0] for c in LINE_ARGS])
def test_line_vectors(name, case):
    header, rows = csv_rows(["interp", "line", "--from", nums(flat(case["P1_corrected"])),
                             "--to", nums(flat(case["P2_corrected"])), "--v", case["v"], "--a", case["A_used"],
                             "--profile", "trapezoid", "--dt", "0.01"])
    assert header == ["t", "x", "y", "z", "qw", "qx", "qy", "qz", "s", "sd", "sdd"]
    s, tm = case["samples"], case["timing"]
    bounds = [tm["t_p"], tm["t_p"] + tm["t_pv"], tm["T_total"]]
    amb = set(s["qddot_ambiguous_indices"])
    tp, ts_, tsd, tsdd = tol(max_abs(s["p"])), tol(max_abs(s["S"])), tol(max_abs(s["Sdot"])), tol(max_abs(s["Sddot"]))
    for row, i, acc in pair_rows(rows, s["t_s"], tm["T_total"]):
        t = s["t_s"][i]
        for k in range(3):
            near(row[1 + k], s["p"][i][k], tp, f"p[{k}] at {t}")
        for got, want in zip(quat_to_matrix(*row[4:8]), s["R_rowmajor"][i]):
            near(got, want, tol(1.0), f"R at {t}")
        near(row[8], s["S"][i], ts_, f"S at {t}")
        near(row[9], s["Sdot"][i], tsd, f"Sdot at {t}")
        if acc and i not in amb and not on_boundary(t, bounds):
            near(row[10], s["Sddot"][i], tsdd, f"Sddot at {t}")


def test_line_slerp_and_pure_rotation():
    # Same ends by either method; a pure rotation needs angular limits.
    args = ["interp", "line", "--from", "0.4,0,0.5,1,0,0,0", "--to", "0.4,0.3,0.4,0,1,0,0", "--v", "0.5", "--a", "2",
            "--dt", "0.005"]
    _, two = csv_rows(args)
    _, sl = csv_rows(args + ["--orientation", "slerp"])
    assert two[-1][1:4] == sl[-1][1:4] and exact(sl[-1][1:4], [0.4, 0.3, 0.4])
    for a, b in zip(quat_to_matrix(*two[-1][4:8]), quat_to_matrix(*sl[-1][4:8])):
        near(a, b, 1e-9 if not FLOAT else 1e-5, "same end orientation")
    r = run(["interp", "line", "--from", "0,0,0,1,0,0,0", "--to", "0,0,0,0,0,0,1", "--v", "1", "--a", "1", "--dt", "0.01"])
    assert r.returncode == 2 and "give --omega and --epsilon" in r.stderr and r.stdout == ""
    _, rows = csv_rows(["interp", "line", "--from", "0,0,0,1,0,0,0", "--to", "0,0,0,0,0,0,1", "--v", "1", "--a", "1",
                        "--omega", "1", "--epsilon", "2", "--dt", "0.01"])
    assert all(row[1:4] == [0.0, 0.0, 0.0] for row in rows)
    near(rows[-1][8], math.pi, 1e-9 if not FLOAT else 1e-5, "s is the angle")
    assert max(row[9] for row in rows) <= 1.0 * (1 + 1e-6)
    # The quaternions keep the sign the start was given with.
    _, rows = csv_rows(["interp", "line", "--from", "0,0,0,-1,0,0,0", "--to", "1,0,0,-1,0,0,0", "--v", "1", "--a", "1",
                        "--dt", "0.1"])
    assert all(row[4] == -1.0 for row in rows)


def check_cart_jerk_rows(rows, V, A, J, dt, end):
    """A jerk-limited line or arc's rows: sd within V, sdd within A, sdd changing by at most J dt per row
    (slack as check_jerk_rows'), at rest on the first and last rows, the last exactly at the end point."""
    T = rows[-1][0]
    assert rows[0][9] == 0.0 and rows[0][10] == 0.0 and rows[-1][9] == 0.0 and rows[-1][10] == 0.0
    assert exact(rows[-1][1:4], end)
    for prev, row in zip(rows, rows[1:]):
        assert abs(row[9]) <= V * (1 + 16 * EPS) + 4 * EPS * A * T, row[0]
        assert abs(row[10]) <= A * (1 + 16 * EPS) + 4 * EPS * J * T, row[0]
        assert abs(row[10] - prev[10]) <= J * dt + 8 * EPS * (A + J * T) + 16 * EPS * J * dt, row[0]


def test_line_and_arc_jerk_random():
    # Seeded random lines (translation only: the path's own limits bind) and arcs in a plane, jerk-limited by
    # default with --jmax or its default 10/s times --a: limits and jerk per row, exact ends, and the duration
    # is the independent rest-to-rest optimum of the path length rounded up to the tick.
    import random
    rng = random.Random(1919)
    for case in range(16):
        dt = rng.choice([0.001, 0.002, 0.005])
        V, A = round(rng.uniform(0.1, 1.0), 4), round(rng.uniform(0.5, 5.0), 4)
        J = round(rng.uniform(2.0, 100.0), 4) if case % 2 else 10.0 * A
        jerk = ["--jmax", J] if case % 2 else []
        if case % 4 < 2:
            p0 = [round(rng.uniform(-1, 1), 6) for _ in range(3)]
            p1 = [round(rng.uniform(-1, 1), 6) for _ in range(3)]
            D = math.dist(p0, p1)
            _, rows = csv_rows(["interp", "line", "--from", nums(p0 + [1, 0, 0, 0]), "--to", nums(p1 + [1, 0, 0, 0]),
                                "--v", V, "--a", A, "--dt", dt] + jerk)
            end = p1
        else:
            R, alpha = rng.uniform(0.1, 1.0), rng.uniform(0.5, 5.5)
            pts = [[R * math.cos(a), R * math.sin(a), 0.3] for a in (0.0, alpha / 2, alpha)]
            D = R * alpha
            _, rows = csv_rows(["interp", "arc", "--from", nums(pts[0] + [1, 0, 0, 0]), "--via", nums(pts[1]),
                                "--to", nums(pts[2]), "--v", V, "--a", A, "--dt", dt] + jerk)
            end = pts[2]
        check_cart_jerk_rows(rows, V, A, J, dt, end)
        T = rest_to_rest_time(D, V, A, J)
        assert (len(rows) - 2) * dt < T * (1 + 1e-6) and (len(rows) - 1) * dt >= T * (1 - 1e-6), \
            (case, len(rows) - 1, T / dt)
        near(rows[-1][8], D, 1e-9 if not FLOAT else 1e-5, "s ends at the path length")


def test_line_trapezoid_and_jerk_flags():
    # --profile trapezoid is the trapezoid (acceleration jumps to A in one row) and refuses jerk limits.
    base = ["interp", "line", "--from", "0,0,0,1,0,0,0", "--to", "1,0,0,1,0,0,0", "--v", "1", "--a", "2", "--dt", "0.01"]
    _, trap = csv_rows(base + ["--profile", "trapezoid"])
    assert trap[1][10] == 2.0
    _, jerk = csv_rows(base + ["--jmax", "50"])
    near(jerk[1][10], 50 * 0.01, 1e-12 if not FLOAT else 1e-6, "acceleration ramps at the jerk limit")
    for extra in (["--jmax", "5"], ["--angular-jmax", "5"]):
        r = run(base + ["--profile", "trapezoid"] + extra)
        assert r.returncode == 2 and "do not apply to --profile trapezoid" in r.stderr


# ---- circle.json ----

CIRCLE_ARGS = [(c["case"], c) for c in CIRCLE["cases"]]


@pytest.mark.parametrize("name,case", CIRCLE_ARGS, ids=[c[0] for c in CIRCLE_ARGS])
def test_circle_vectors(name, case):
    header, rows = csv_rows(["interp", "arc", "--from", nums(flat(case["T1_corrected"])),
                             "--via", nums(case["T2_position"]), "--to", nums(case["T3_position"]),
                             "--v", case["v"], "--a", case["A_used"], "--profile", "trapezoid", "--dt", "0.01"])
    assert header == ["t", "x", "y", "z", "qw", "qx", "qy", "qz", "s", "sd", "sdd"]
    s, tm, R = case["samples"], case["timing"], case["radius"]
    bounds = [tm["t_p"], tm["t_p"] + tm["t_pv"], tm["T_total"]]
    amb = set(s["qddot_ambiguous_indices"])
    tp, ta, tad, tadd = tol(max_abs(s["p"])), tol(2 * math.pi), tol(max_abs(s["alphadot"])), tol(max_abs(s["alphaddot"]))
    for row, i, acc in pair_rows(rows, s["t_s"], tm["T_total"]):
        t = s["t_s"][i]
        for k in range(3):
            near(row[1 + k], s["p"][i][k], tp, f"p[{k}] at {t}")
        for got, want in zip(quat_to_matrix(*row[4:8]), s["R_rowmajor"][i]):
            near(got, want, tol(1.0), f"R at {t}")
        near(row[8] / R, s["alpha"][i], ta, f"alpha at {t}")
        near(row[9] / R, s["alphadot"][i], tad, f"alphadot at {t}")
        if acc and i not in amb and not on_boundary(t, bounds):
            near(row[10] / R, s["alphaddot"][i], tadd, f"alphaddot at {t}")
    assert exact(rows[-1][1:4], case["T3_position"])  # exactly the end point


# ---- batch ----

def test_batch_rows_equal_csv():
    c = JOINT["cases"][0]
    _, rows = csv_rows(["interp", "joint", "--model", "planar2", "--deg", "--q0", nums(c["q_start_deg"]),
                        "--q1", nums(c["q_end_deg"]), "--vmax", c["v_deg_s"], "--amax", c["A_deg_s2"],
                        "--profile", "trapezoid", "--dt", "0.01"])
    a = CIRCLE["cases"][10]
    _, arc = csv_rows(["interp", "arc", "--from", nums(flat(a["T1_corrected"])), "--via", nums(a["T2_position"]),
                       "--to", nums(a["T3_position"]), "--v", a["v"], "--a", a["A_used"], "--dt", "0.05"])
    reqs = [
        {"op": "interp", "kind": "joint", "model": "planar2", "deg": True, "q0": c["q_start_deg"],
         "q1": c["q_end_deg"], "vmax": [c["v_deg_s"]], "amax": [c["A_deg_s2"]], "dt": 0.01, "id": "j",
         "profile": "trapezoid"},
        {"op": "interp", "kind": "arc", "from": flat(a["T1_corrected"]), "via": a["T2_position"],
         "to": a["T3_position"], "v": a["v"], "a": a["A_used"], "dt": 0.05},
        {"op": "interp", "kind": "line", "from": [0, 0, 0, 1, 0, 0, 0], "to": [1, 0, 0, 1, 0, 0, 0], "v": 1, "a": 1,
         "dt": 0.01, "q0": [1]},
        {"op": "interp", "kind": "spiral"},
        {"op": "interp", "from": [0, 0, 0, 1, 0, 0, 0]},
        {"op": "interp", "kind": "arc", "from": [0, 0, 0, 1, 0, 0, 0], "via": [1, 0, 0], "to": [2, 0, 0], "v": 1,
         "a": 1, "dt": 0.01},
    ]
    r = run(["batch"], "\n".join(json.dumps(q) for q in reqs) + "\n")
    assert r.returncode == 0, r.stderr
    ans = [json.loads(line) for line in r.stdout.splitlines()]
    assert len(ans) == len(reqs)
    assert ans[0]["columns"] == ["t", "q1", "q2", "qd1", "qd2", "qdd1", "qdd2"] and ans[0]["id"] == "j"
    assert ans[0]["rows"] == rows
    assert ans[1]["columns"][8] == "s" and ans[1]["rows"] == arc
    assert "unknown key \"q0\" for interp line" in ans[2]["error"]
    assert "unknown interp kind \"spiral\"" in ans[3]["error"]
    assert "missing kind" in ans[4]["error"]
    assert "collinear" in ans[5]["error"]


# ---- bad input ----

J = ["interp", "joint", "--model", "planar2", "--q0", "0,0", "--q1", "1,1"]
L = ["interp", "line", "--from", "0,0,0,1,0,0,0", "--to", "1,0,0,1,0,0,0"]
A = ["interp", "arc", "--from", "0,0,0,1,0,0,0", "--via", "1,1,0", "--to", "2,0,0"]

BAD = [
    (J, "missing dt"),
    (J + ["--dt", "0"], "dt must be > 0"),
    (J + ["--dt", "-0.001"], "dt must be > 0"),
    (J + ["--dt", "nan"], "not a finite number"),
    (J + ["--dt", "0.001", "--vmax", "0"], "vmax must be > 0"),
    (J + ["--dt", "0.001", "--amax", "-5"], "amax must be > 0"),
    (J + ["--dt", "0.001", "--vmax", "1,2,3"], "vmax has 3 values"),
    (J + ["--dt", "0.001", "--amax", "1,inf"], "not a finite number"),
    (J + ["--dt", "0.001", "--duration", "0.1"], "shorter than the limits allow"),
    (J + ["--dt", "0.001", "--duration", "-1"], "duration must be >= 0"),
    (J + ["--dt", "1e-9"], "use a larger --dt"),
    (["interp", "joint", "--model", "planar2", "--q0", "0,0,0", "--q1", "1,1", "--dt", "0.01"], "q0 has 3 values"),
    (["interp", "joint", "--model", "planar2", "--q0", "0,nan", "--q1", "1,1", "--dt", "0.01"], "not a finite number"),
    (["interp", "joint", "--q0", "0", "--q1", "1", "--dt", "0.01"], "give a model"),
    (L + ["--v", "1", "--dt", "0.01"], "missing a"),
    (L + ["--v", "0", "--a", "1", "--dt", "0.01"], "v must be > 0"),
    (L + ["--v", "1", "--a", "1", "--omega", "-1", "--dt", "0.01"], "omega must be > 0"),
    (L + ["--v", "1", "--a", "1", "--orientation", "euler", "--dt", "0.01"], "unknown orientation method \"euler\""),
    (["interp", "line", "--from", "0,0,0,0,0,0,0", "--to", "1,0,0,1,0,0,0", "--v", "1", "--a", "1", "--dt", "0.01"],
     "quaternion qw,qx,qy,qz is zero"),
    (["interp", "line", "--from", "0,0,0,1,0,0", "--to", "1,0,0,1,0,0,0", "--v", "1", "--a", "1", "--dt", "0.01"],
     "from has 6 numbers"),
    (["interp", "line", "--from", nums([2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]), "--to", "1,0,0,1,0,0,0",
      "--v", "1", "--a", "1", "--dt", "0.01"], "not a rigid transform"),
    (L + ["--v", "1e-9", "--a", "1", "--dt", "0.001"], "ticks"),
    (A + ["--v", "1", "--dt", "0.01"], "missing a"),
    (["interp", "arc", "--from", "0,0,0,1,0,0,0", "--via", "1,0,0", "--to", "2,0,0", "--v", "1", "--a", "1",
      "--dt", "0.01"], "collinear"),
    (["interp", "arc", "--from", "0,0,0,1,0,0,0", "--via", "1,1,0", "--to", "0,0,0", "--v", "1", "--a", "1",
      "--dt", "0.01"], "coincide"),
    (["interp", "arc", "--from", "0,0,0,1,0,0,0", "--via", "1,1", "--to", "2,0,0", "--v", "1", "--a", "1",
      "--dt", "0.01"], "via has 2 numbers"),
    (A + ["--v", "1", "--a", "1", "--dt", "0.01", "--q0", "1"], "unknown option \"--q0\""),
    (J + ["--dt", "0.01", "--profile", "scurve"], "profile must be trapezoid or jerk"),
    (J + ["--dt", "0.01", "--profile", "trapezoid", "--jmax", "10"], "jmax does not apply to --profile trapezoid"),
    (J + ["--dt", "0.01", "--profile", "jerk", "--jmax", "0"], "jmax must be > 0"),
    # limits whose squares and cubes under- or overflow (kinctl/desc.h): a
    # jerk of 1e-250 once gave one row already at q1 (exit 0), limits of
    # 1e240 rows with q at 1e231
    (J + ["--dt", "0.001", "--profile", "jerk", "--jmax", "1e-250"], "jmax = 1e-250 is outside 1e-09 .. 1e+09"),
    (J + ["--dt", "0.001", "--vmax", "1e240", "--amax", "1e240", "--jmax", "1e240"],
     "vmax = 1e+240 is outside 1e-09 .. 1e+09"),
    (J + ["--dt", "0.001", "--deg", "--amax", "1e11"], "amax = 1.74533e+09 is outside"),
    (L + ["--v", "1", "--a", "1e240", "--dt", "0.01"], "a = 1e+240 is outside 1e-09 .. 1e+09"),
    (L + ["--v", "1", "--a", "1", "--jmax", "1e-12", "--dt", "0.01"], "jmax = 1e-12 is outside"),
    (J + ["--dt", "0.01", "--profile", "jerk", "--jmax", "1,2,3"], "jmax has 3 values"),
    (J + ["--dt", "0.01", "--profile", "jerk", "--duration", "0.1"], "shorter than the limits allow"),
    (["interp", "spiral"], "unknown kind \"spiral\""),
    (["interp"], "usage: kinctl-calc interp KIND"),
]


@pytest.mark.parametrize("args,message", BAD, ids=[" ".join(a[1:]) for a, _ in BAD])
def test_bad_input(args, message):
    r = run(args)
    assert r.returncode == 2
    assert message in r.stderr, r.stderr
    assert r.stdout == ""


def test_path_plugs_in():
    # interp path belongs to interp_path.c; whether or not it is built in,
    # an incomplete request is bad input with a message and no rows.
    r = run(["interp", "path", "--dt", "0.01"])
    assert r.returncode == 2 and r.stdout == "" and r.stderr != ""


def test_warnings_on_stderr():
    r = run(["interp", "joint", "--model", "planar2", "--deg", "--q0", "0,0", "--q1", "200,0", "--vmax", "100",
             "--dt", "0.01"])
    assert r.returncode == 0
    assert "outside joint 1's limits" in r.stderr and "exceeds the model's limit" in r.stderr
    assert r.stdout.startswith("t,q1,q2,")


PUMA_Q1_MAX = 2.792526803190927  # models/puma560.cfg, joint 1's upper limit


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_moving_start_carried_beyond_a_joint_limit_is_warned_about(sign):
    # Joint 1 at 2.5 rad, 2 rad/s towards its limit: at 5 rad/s^2 and 50
    # rad/s^3 it turns beyond the limit on the way to 2.79 rad. The rows
    # are computed anyway; the warning names the joint's extreme over them.
    args = ["interp", "joint", "--model", "puma560", "--q0", nums([2.5 * sign] + [0.0] * 5),
            "--q1", nums([2.79 * sign] + [0.0] * 5), "--qd0", nums([2.0 * sign] + [0.0] * 5), "--dt", "0.004"]
    r = run(args)
    assert r.returncode == 0
    rows = [[float(x) for x in line.split(",")] for line in r.stdout.splitlines()[1:]]
    far = max((row[1] for row in rows), key=lambda q: q * sign)
    assert far * sign > PUMA_Q1_MAX
    assert f"joint 1 reaches {far:.9g} rad on the way from this start, beyond its limits" in r.stderr, r.stderr
    assert r.stderr.count("warning") == 1
    # From 0.5 rad/s it turns before the limit: no warning.
    slow = args[:-4] + ["--qd0", nums([0.5 * sign] + [0.0] * 5), "--dt", "0.004"]
    r = run(slow)
    assert r.returncode == 0 and r.stderr == ""
    assert max(float(line.split(",")[1]) * sign for line in r.stdout.splitlines()[1:]) < PUMA_Q1_MAX


def test_moving_start_beyond_the_rate_limits_is_warned_about():
    # puma560 joint 1: vmax 2 rad/s, amax 5 rad/s^2, jmax 50 rad/s^3.
    base = ["interp", "joint", "--model", "puma560", "--q0", nums([0.0] * 6), "--q1", nums([1.0] + [0.0] * 5)]
    # A start beyond vmax and amax: the rows start there.
    r = run(base + ["--qd0", nums([3.0] + [0.0] * 5), "--qdd0", nums([-7.0] + [0.0] * 5), "--dt", "0.004"])
    assert r.returncode == 0
    assert "joint 1's speed reaches 3 rad/s from this start, beyond vmax 2" in r.stderr, r.stderr
    assert "joint 1's acceleration reaches 7 rad/s^2 from this start, beyond amax 5" in r.stderr, r.stderr
    # 1.9 rad/s rising at 4.9 rad/s^2: the acceleration comes down to 0 at
    # the jerk limit in 4.9 / 50 s (49 ticks of 2 ms), the speed rising by
    # 4.9^2 / (2 50) to 2.1401 rad/s on the way.
    r = run(base + ["--qd0", nums([1.9] + [0.0] * 5), "--qdd0", nums([4.9] + [0.0] * 5), "--dt", "0.002"])
    assert r.returncode == 0 and r.stderr.count("warning") == 1, r.stderr
    peak = float(r.stderr.split("speed reaches ")[1].split()[0])
    assert peak == pytest.approx(1.9 + 4.9 ** 2 / 100.0, rel=1e-8)
    # At the limits exactly (2 rad/s braking at 5 rad/s^2): nothing to say.
    r = run(base + ["--qd0", nums([2.0] + [0.0] * 5), "--qdd0", nums([-5.0] + [0.0] * 5), "--dt", "0.004"])
    assert r.returncode == 0 and r.stderr == ""


@pytest.mark.parametrize("kind", ["joint", "line", "arc", "path"])
def test_help(kind):
    r = run(["interp", kind, "--help"])
    assert r.returncode == 0 and r.stdout.startswith("usage: kinctl-calc interp " + kind)
    if kind == "joint":
        assert "--jmax 3000" in r.stdout and "--profile trapezoid --vmax" in r.stdout and "--jmax J|J1,J2,.." in r.stdout
    r = run(["interp", "--help"])
    assert r.returncode == 0 and f"\n  {kind} " in r.stdout
    r = run(["--help"])
    assert "\n  interp " in r.stdout
