# SPDX-License-Identifier: BSD-3-Clause
"""kinctld's jerk-limited joint moves, through LCM: a joint goal replaced
mid-motion by another keeps every setpoint within puma560's velocity,
acceleration and jerk limits (the jerk measured as the change of the
published qdd over one cycle, over dt), the replacing goal takes over in
the cycle it arrives from the moving state with q, qd and qdd continuous,
and ends exactly on its target; goal_joint_t.profile = PROFILE_TRAPEZOID
still gets seed 001's trapezoid."""
from kinctl_testing import (DT, EVENTS, N, QDD_MAX, QDDD_MAX, QN, assert_smooth, close, finished, go_nominal,
                            goal_joint_t, max_jerk_ratio, setpoints_since)

# Relative slack of the limit checks: the daemon's core is double, and a
# tick's time rounds by about 2e-16 of a few seconds (kinctl/scurve.h).
SLACK = 1e-6


def test_replace_mid_motion_is_jerk_limited(kinctld):
    d = kinctld()
    s0 = go_nominal(d)
    far = [1.5, 0.5, -2.5, 1.0, 0.5, 1.0]
    back = [-0.5, 1.0, -2.8, -0.5, 1.0, -0.5]
    d.bus.send_goal_joint(10, far)
    d.bus.wait(lambda: any(s.goal_id == 10 for s in d.bus.setpoints[-3:]), 5.0, "motion")
    d.bus.wait_setpoints(400)
    d.bus.send_goal_joint(11, back, replace=True)
    assert d.bus.wait_event(10, ("PREEMPTED", "COMPLETED", "ABORTED", "FAULT")).event == EVENTS["PREEMPTED"]
    s = finished(d, 11)
    assert close(s.q, back, 0.0)  # exactly on the target
    stream = setpoints_since(d, s0.cycle)
    assert_smooth(stream, SLACK)
    rj, ra = max_jerk_ratio(stream)
    assert rj <= 1.0 + SLACK and ra <= 1.0 + SLACK, (rj, ra)
    assert rj > 0.99  # the jerk limit is what binds
    # The takeover: the first setpoint of goal 11 follows one of goal 10 in
    # the next cycle, the arm still moving and accelerating; q continues by
    # qd dt, qd by qdd dt, qdd by at most the jerk limit times dt.
    i = next(i for i, p in enumerate(stream) if p.goal_id == 11)
    a, b = stream[i - 1], stream[i]
    assert a.goal_id == 10 and b.cycle == a.cycle + 1
    assert max(abs(v) for v in b.qd[:N]) > 0.1
    assert max(abs(v) for v in a.qdd[:N]) > 0.01
    for j in range(N):
        assert abs(b.q[j] - a.q[j] - a.qd[j] * DT) <= QDD_MAX[j] * DT * DT, j
        assert abs(b.qd[j] - a.qd[j]) <= QDD_MAX[j] * DT * (1 + SLACK), j
        assert abs(b.qdd[j] - a.qdd[j]) <= QDDD_MAX[j] * DT * (1 + SLACK), j
    assert d.stop() == 0


def test_trapezoid_on_request(kinctld):
    d = kinctld()
    s0 = go_nominal(d)
    target = [1.0, 0.5, -2.5, 0.5, 0.5, 0.5]
    d.bus.send_goal_joint(20, target, profile=goal_joint_t.PROFILE_TRAPEZOID)
    s = finished(d, 20)
    assert close(s.q, target, 0.0)
    stream = [p for p in setpoints_since(d, s0.cycle) if p.goal_id == 20]
    assert_smooth(stream, SLACK)
    # The trapezoid's acceleration jumps from 0 to the leading joint's
    # limit in one cycle: its jerk is A / dt, far beyond the limit.
    rj, ra = max_jerk_ratio(stream)
    assert rj > 10.0
    assert d.stop() == 0
