# SPDX-License-Identifier: BSD-3-Clause
"""Random jerk-limited joint moves and replacements through `kinctl-calc
interp joint` (issue 19), checked row by row and against Ruckig.

Every built-in arm, with random per-joint limits (--vmax, --amax, --jmax)
and with the model's own (panda, puma560), random starts q0, targets q1 and
start states (--qd0, --qdd0), random tick periods. Each move's rows are
checked on every tick:
  limits      |qd| <= vmax, |qdd| <= amax, |qddd| <= jmax; from a start
              beyond what the limits can hold (its speed with its
              acceleration ramped out, |qd0 + qdd0 |qdd0| / (2 jmax)|, above
              vmax) the bounds the start itself sets instead;
  jerk        |change of qdd over one tick| <= jmax dt;
  continuity  q and qd follow from the row before within what the jerk
              allows over one tick: |q' - q - qd dt - qdd dt^2/2| <=
              jmax dt^3 / 6 and |qd' - qd - qdd dt| <= jmax dt^2 / 2;
  ends        the first row is the start state, the last row exactly q1 at
              rest, every joint arriving on that row.
Slack of the limits, as tests/unit/test_scurve.c and test_calc_interp.py
state it: the rounding of t = k dt and of the phase sums, 8 eps (A + J T)
for the acceleration and its change, 4 eps A T beyond V; the continuity
checks 16 eps of the positions' and speeds' scale.

Replacements as kinctld makes them: a move is cut at a random row and the
next one starts from that row's q, qd and qdd; the stitched rows pass the
same checks across every cut.

Durations: the calculator's (its rows span the first tick at or after its
duration T) against the Python ruckig package (Berscheid & Kroeger 2021)
on the same input: synchronised by time from moving starts, by phase and by
time from rest. Within the starts the limits can hold Ruckig's is the
optimum, so the two agree within one tick and 1e-6 of the duration (1e-4
in the float build); from a start beyond them kinctl may brake
differently, and only its limits are checked.

Environment: KINCTL_CALC, KINCTL_REAL (see test_calc.py).
"""
import math
import random

from ruckig import InputParameter, Result, Ruckig, Synchronization, Trajectory

from test_calc_interp import (EPS, FLOAT, PANDA_QD, PANDA_QDD, PANDA_QDDD, PUMA_QD, PUMA_QDD, PUMA_QDDD, csv_rows,
                              nums)

# The built-in arms and their joint counts (kinctl-calc interp joint --help).
ARMS = {"planar2": 2, "rrr3": 3, "puma560": 6, "rb211": 6, "rm01": 6, "panda": 7}
# The model's own limits where the test passes none.
MODEL_LIMITS = {"panda": (PANDA_QD, PANDA_QDD, PANDA_QDDD), "puma560": (PUMA_QD, PUMA_QDD, PUMA_QDDD)}
# Durations against Ruckig's: relative, beside one tick.
DURATION_TOL = 1e-4 if FLOAT else 1e-6
# The same for moves whose every joint's optimum Ruckig computes the same
# way (starts the limits hold, small jerk limits).
DURATION_TOL_TIGHT = 1e-4 if FLOAT else 1e-9


def random_limits(rng, n):
    return ([round(rng.uniform(0.3, 3.0), 3) for _ in range(n)],
            [round(rng.uniform(1.0, 30.0), 3) for _ in range(n)],
            [round(rng.uniform(10.0, 5000.0), 3) for _ in range(n)])


def held(v, a, V, A, J):
    """Whether the limits can hold a start (v, a): |a| <= A and the speed
    reached by ramping a out at J, v + a |a| / (2J), within V."""
    return abs(a) <= A and abs(v) <= V and abs(v + a * abs(a) / (2.0 * J)) <= V


def random_state(rng, V, A, J, inside=True):
    """A start state (qd0, qdd0) the limits hold, or (inside False) one
    anywhere within them whose speed with its acceleration ramped out may
    exceed V."""
    while True:
        v, a = rng.uniform(-V, V), rng.uniform(-A, A)
        if not inside or held(v, a, V, A, J):
            return v, a


class Move:
    """A move's rows split into columns: t, q, qd, qdd, qddd (lists per row)."""

    def __init__(self, header, rows, n):
        assert header == ["t"] + [f"{s}{i + 1}" for s in ("q", "qd", "qdd", "qddd") for i in range(n)]
        self.rows = rows
        self.n = n

    def state(self, k):
        r, n = self.rows[k], self.n
        return r[1:1 + n], r[1 + n:1 + 2 * n], r[1 + 2 * n:1 + 3 * n]


def plan(arm, q0, q1, dt, limits=None, qd0=None, qdd0=None):
    args = ["interp", "joint", "--model", arm, "--q0", nums(q0), "--q1", nums(q1), "--dt", dt]
    if limits is not None:
        args += ["--vmax", nums(limits[0]), "--amax", nums(limits[1]), "--jmax", nums(limits[2])]
    if qd0 is not None:
        args += ["--qd0", nums(qd0), "--qdd0", nums(qdd0)]
    header, rows = csv_rows(args)
    return Move(header, rows, len(q0))


def check_rows(rows, n, q_end, limits, dt, bounds=None):
    """Every row of a stream (one move, or moves stitched at their cuts)
    within the limits (or per joint the (speed, acceleration) bounds a
    start sets), the jerk and continuity; the last row exactly q_end at
    rest, some joint still moving on the row before it."""
    V, A, J = limits
    T = rows[-1][0] - rows[0][0]
    for i in range(n):
        vb, ab = bounds[i] if bounds else (V[i], A[i])
        scale_q = max(abs(r[1 + i]) for r in rows) + vb * T
        slack_a = 8 * EPS * (ab + J[i] * T) + 16 * EPS * J[i] * dt
        slack_q, slack_v = 16 * EPS * scale_q, 16 * EPS * (vb + ab * T)
        for prev, row in zip(rows, rows[1:]):
            q, qd, qdd = row[1 + i], row[1 + n + i], row[1 + 2 * n + i]
            p_q, p_qd, p_qdd = prev[1 + i], prev[1 + n + i], prev[1 + 2 * n + i]
            where = (i, row[0])
            assert abs(qd) <= vb * (1 + 16 * EPS) + 4 * EPS * ab * T, where
            assert abs(qdd) <= ab * (1 + 16 * EPS) + 4 * EPS * J[i] * T, where
            assert abs(row[1 + 3 * n + i]) <= J[i] * (1 + 16 * EPS), where
            assert abs(qdd - p_qdd) <= J[i] * dt + slack_a, where
            assert abs(qd - p_qd - p_qdd * dt) <= J[i] * dt * dt / 2 * (1 + 1e-9) + slack_v, where
            assert abs(q - p_q - p_qd * dt - p_qdd * dt * dt / 2) <= J[i] * dt ** 3 / 6 * (1 + 1e-9) + slack_q, where
        assert rows[-1][1 + i] == q_end[i] and rows[-1][1 + n + i] == 0.0 and rows[-1][1 + 2 * n + i] == 0.0
    assert any(rows[-2][1 + n + i] != 0.0 or rows[-2][1 + 2 * n + i] != 0.0 for i in range(n))


def ruckig_duration(q0, qd0, qdd0, q1, limits, sync):
    n = len(q0)
    inp = InputParameter(n)
    inp.current_position, inp.current_velocity, inp.current_acceleration = list(q0), list(qd0), list(qdd0)
    inp.target_position, inp.target_velocity, inp.target_acceleration = list(q1), [0.0] * n, [0.0] * n
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = list(limits[0]), list(limits[1]), list(limits[2])
    inp.synchronization = sync
    traj = Trajectory(n)
    assert Ruckig(n).calculate(inp, traj) == Result.Working
    return traj.duration


def assert_duration(move, dt, want, what, tol=DURATION_TOL):
    """The move's rows end on the first tick at or after a duration equal to
    Ruckig's `want` (within tol of it)."""
    ticks = len(move.rows) - 1
    lo, hi = want * (1 - tol), want * (1 + tol)
    assert (ticks - 1) * dt < hi and ticks * dt >= lo * (1 - 1e-12), (what, ticks, want / dt)


def arm_limits(rng, arm, n):
    if arm in MODEL_LIMITS and rng.random() < 0.5:
        return None, MODEL_LIMITS[arm]
    lim = random_limits(rng, n)
    return lim, lim


def random_q(rng, arm, n):
    # panda's joint 4 lies in [-3.07, -0.07] rad; the other arms' span 0.
    return [round(rng.uniform(-1.5, 1.5) - (1.5 if arm == "panda" and i == 3 else 0.0), 6) for i in range(n)]


def test_random_moves_within_limits_and_as_fast_as_ruckig():
    rng = random.Random(2019)
    for case in range(36):
        arm = list(ARMS)[case % len(ARMS)]
        n = ARMS[arm]
        given, lim = arm_limits(rng, arm, n)
        dt = rng.choice([0.001, 0.002, 0.004])
        q0, q1 = random_q(rng, arm, n), random_q(rng, arm, n)
        moving = case % 3 != 0
        if moving:
            states = [random_state(rng, lim[0][i], lim[1][i], lim[2][i]) for i in range(n)]
            qd0, qdd0 = [s[0] for s in states], [s[1] for s in states]
            move = plan(arm, q0, q1, dt, given, qd0, qdd0)
        else:
            qd0, qdd0 = [0.0] * n, [0.0] * n
            move = plan(arm, q0, q1, dt, given)
        q, qd, qdd = move.state(0)
        assert q == q0, case
        for i in range(n):
            assert abs(qd[i] - qd0[i]) <= 1e-12 + 8 * EPS * abs(qd0[i])
            assert abs(qdd[i] - qdd0[i]) <= 1e-12 + 8 * EPS * abs(qdd0[i])
        check_rows(move.rows, n, q1, lim, dt)
        what = (case, arm, "moving" if moving else "rest")
        assert_duration(move, dt, ruckig_duration(q0, qd0, qdd0, q1, lim, Synchronization.Time), what)
        if not moving:
            assert_duration(move, dt, ruckig_duration(q0, qd0, qdd0, q1, lim, Synchronization.Phase), what)


def test_starts_beyond_what_the_limits_hold():
    # Speed and acceleration within the limits, but the speed with the
    # acceleration ramped out may pass vmax: no plan can stay within vmax,
    # and kinctl's passes it only by what the start forces.
    rng = random.Random(1919)
    for case in range(12):
        arm = list(ARMS)[case % len(ARMS)]
        n = ARMS[arm]
        given, lim = arm_limits(rng, arm, n)
        dt = rng.choice([0.001, 0.002])
        q0, q1 = random_q(rng, arm, n), random_q(rng, arm, n)
        states = [random_state(rng, lim[0][i], lim[1][i], lim[2][i], inside=False) for i in range(n)]
        qd0, qdd0 = [s[0] for s in states], [s[1] for s in states]
        move = plan(arm, q0, q1, dt, given, qd0, qdd0)
        bounds = [(max(lim[0][i], abs(qd0[i] + qdd0[i] * abs(qdd0[i]) / (2 * lim[2][i]))), lim[1][i])
                  for i in range(n)]
        check_rows(move.rows, n, q1, lim, dt, bounds)


def test_random_replacements_continuous_and_as_fast_as_ruckig():
    # A move from rest replaced at random rows, three times, each by a move
    # to a new random target from the row's state; the stitched stream is
    # within the limits and continuous across the cuts, and every move from
    # its cut lasts Ruckig's time-synchronised duration.
    rng = random.Random(1920)
    for case in range(12):
        arm = list(ARMS)[(case * 5) % len(ARMS)]
        n = ARMS[arm]
        given, lim = arm_limits(rng, arm, n)
        dt = rng.choice([0.001, 0.002])
        q0 = random_q(rng, arm, n)
        move = plan(arm, q0, random_q(rng, arm, n), dt, given)
        stream = []
        for cut in range(3):
            k = rng.randrange(1, len(move.rows) - 1)
            stream += move.rows[:k]
            q, qd, qdd = move.state(k)
            target = random_q(rng, arm, n)
            move = plan(arm, q, target, dt, given, qd, qdd)
            assert move.state(0)[0] == q
            assert_duration(move, dt, ruckig_duration(q, qd, qdd, target, lim, Synchronization.Time), (case, cut))
            # The new move's times continue the stream's.
            t0 = stream[-1][0] + dt
            move.rows = [[r[0] + t0] + r[1:] for r in move.rows]
        stream += move.rows
        check_rows(stream, n, target, lim, dt)
        ts = [r[0] for r in stream]
        assert all(abs(b - a - dt) <= 1e-9 for a, b in zip(ts, ts[1:])), case


def test_small_jerk_moving_starts_as_fast_as_ruckig():
    # rb211's vmax and amax (1.5 rad/s, 6 rad/s^2) with jmax of 1-3 rad/s^3
    # on every built-in arm, from moving starts the limits hold: a joint's
    # stretch to the slowest joint's optimum may need a cruise below the
    # speed its acceleration carries it to, which passes the target, or lie
    # between its optimum and its slowest cruise (kinctl/scurve.h,
    # kc_scurve_plan_duration_from). Every duration from the optimum on is
    # reached, so each move lasts Ruckig's time-synchronised duration within
    # 1e-9 of it and one tick, within the limits (while such stretches were
    # blocked, 2 of these 120 moves lasted 2 % and 6 % longer).
    rng = random.Random(1)
    for case in range(120):
        arm = list(ARMS)[case % len(ARMS)]
        n = ARMS[arm]
        lim = ([1.5] * n, [6.0] * n, [round(rng.uniform(1.0, 3.0), 3) for _ in range(n)])
        dt = rng.choice([0.002, 0.004])
        q0, q1 = random_q(rng, arm, n), random_q(rng, arm, n)
        states = [random_state(rng, lim[0][i], lim[1][i], lim[2][i]) for i in range(n)]
        qd0, qdd0 = [s[0] for s in states], [s[1] for s in states]
        move = plan(arm, q0, q1, dt, lim, qd0, qdd0)
        check_rows(move.rows, n, q1, lim, dt)
        assert_duration(move, dt, ruckig_duration(q0, qd0, qdd0, q1, lim, Synchronization.Time), (case, arm),
                        DURATION_TOL_TIGHT)
