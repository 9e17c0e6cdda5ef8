# SPDX-License-Identifier: BSD-3-Clause
"""kinctld given random joint goals over LCM, each replacing the one before
at a random moment (issue 19): every published setpoint, across every
takeover, within puma560's velocity, acceleration and jerk limits, q and qd
continuous (each follows from the cycle before within what the jerk limit
allows over one cycle), the last goal ending exactly on its target; and
each replacing goal's move from the state it took over lasts Ruckig's
time-synchronised duration from that state (Python ruckig package), to the
tick.

Slack: the daemon's core is double; the limits and the jerk get 1e-6 of
themselves as test_jerk.py, the continuity checks 1e-12 rad (rounding of
positions of a few rad) and 1e-9 rad/s."""
import random
import time

from ruckig import InputParameter, Result, Ruckig, Synchronization, Trajectory

from kinctl_testing import (DT, EVENTS, N, QD_MAX, QDD_MAX, QDDD_MAX, close, finished, go_nominal,
                            setpoints_since)

SLACK = 1e-6
# puma560's position limits (models/puma560.cfg), less a margin that a
# replacing goal's overshoot from full speed (about vmax^2 / (2 amax) plus
# the jerk phases, 0.6 rad) keeps clear of.
Q_LIMITS = [(-2.792526803190927, 2.792526803190927), (-0.7853981633974483, 3.9269908169872414),
            (-3.9269908169872414, 0.7853981633974483), (-1.9198621771937625, 2.9670597283903604),
            (-1.7453292519943295, 1.7453292519943295), (-4.642575810304916, 4.642575810304916)]
MARGIN = 0.9


def random_target(rng):
    return [rng.uniform(lo + MARGIN, hi - MARGIN) for lo, hi in Q_LIMITS]


def ruckig_ticks(q, qd, qdd, target):
    """Ruckig's time-synchronised duration from (q, qd, qdd) to rest at
    target within puma560's limits, in cycles (the first at or after it)."""
    inp = InputParameter(N)
    inp.current_position, inp.current_velocity, inp.current_acceleration = list(q), list(qd), list(qdd)
    inp.target_position, inp.target_velocity, inp.target_acceleration = list(target), [0.0] * N, [0.0] * N
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = QD_MAX, QDD_MAX, QDDD_MAX
    inp.synchronization = Synchronization.Time
    traj = Trajectory(N)
    assert Ruckig(N).calculate(inp, traj) == Result.Working
    return traj.duration / DT


def check_stream(stream):
    for a, b in zip(stream, stream[1:]):
        assert b.cycle == a.cycle + 1, (a.cycle, b.cycle)
        for j in range(N):
            where = (b.cycle, b.goal_id, j)
            assert abs(b.qd[j]) <= QD_MAX[j] * (1 + SLACK), where
            assert abs(b.qdd[j]) <= QDD_MAX[j] * (1 + SLACK), where
            assert abs(b.qdd[j] - a.qdd[j]) <= QDDD_MAX[j] * DT * (1 + SLACK), where
            assert abs(b.qd[j] - a.qd[j] - a.qdd[j] * DT) <= QDDD_MAX[j] * DT ** 2 / 2 * (1 + SLACK) + 1e-9, where
            assert abs(b.q[j] - a.q[j] - a.qd[j] * DT - a.qdd[j] * DT ** 2 / 2) <= \
                QDDD_MAX[j] * DT ** 3 / 6 * (1 + SLACK) + 1e-12, where


def test_random_goals_replaced_at_random_moments(kinctld):
    rng = random.Random(1907)
    d = kinctld()
    s0 = go_nominal(d)
    first = 100
    targets = {first: random_target(rng)}
    d.bus.send_goal_joint(first, targets[first])
    d.bus.wait(lambda: any(s.goal_id == first for s in d.bus.setpoints[-3:]), 5.0, "motion")
    last = first
    for gid in range(first + 1, first + 13):
        # From a few cycles into a move to past its end (most moves take 1-2
        # s); the last goal early, to take over a moving arm and end.
        time.sleep(rng.uniform(0.005, 0.1) if gid == first + 12 else
                   rng.choice([rng.uniform(0.005, 0.05), rng.uniform(0.05, 0.8)]))
        targets[gid] = random_target(rng)
        d.bus.send_goal_joint(gid, targets[gid], replace=True)
        ev = d.bus.wait_event(last, ("PREEMPTED", "COMPLETED", "ABORTED", "FAULT", "REJECTED"))
        assert ev.event in (EVENTS["PREEMPTED"], EVENTS["COMPLETED"]), (last, ev.reason)
        last = gid
    s = finished(d, last)
    assert close(s.q, targets[last], 0.0)  # exactly on the target
    stream = setpoints_since(d, s0.cycle)
    check_stream(stream)
    # Each goal that ended, from the setpoint before its first (its tick 0)
    # to its end: Ruckig's duration from that state, to the tick.
    taken = 0
    for i in range(1, len(stream)):
        a, b = stream[i - 1], stream[i]
        if b.goal_id == a.goal_id or b.goal_id not in targets:
            continue
        target = targets[b.goal_id]
        # Its end: the first setpoint of no goal, exactly on its target at
        # rest (a replaced goal's next setpoint is the next goal's).
        end = next(s for s in stream[i:] if s.goal_id != b.goal_id)
        if end.goal_id != 0:
            continue
        assert close(end.q, target, 0.0) and not any(end.qd[:N]) and not any(end.qdd[:N]), b.goal_id
        taken += any(a.qd[:N])
        want = ruckig_ticks(a.q[:N], a.qd[:N], a.qdd[:N], target)
        assert want - 1e-6 * want <= end.cycle - a.cycle < want + 1 + 1e-6 * want, (b.goal_id, end.cycle - a.cycle,
                                                                                      want)
    assert taken >= 1  # some goal ended that took over a moving arm
    assert d.stop() == 0
