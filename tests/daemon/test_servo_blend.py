# SPDX-License-Identifier: BSD-3-Clause
"""kinctld: a servo stream replaced by a line takes over in the cycle it
arrives, without stopping, through LCM (kinctl/ctrl.h: the stream's
jerk-limited halt, joint by joint, superposed on the line).

A twist stream moves puma560's tool from its nominal pose; a line replaces
it. The line is accepted with no reason (not stop_first), the stream is
preempted, and the line's first setpoint follows the stream's last in the
next cycle with the arm still moving. Every published setpoint is smooth
(assert_smooth); through the takeover, while the setpoints are the halt's
(the line starts from rest where the halt ends, no sooner than the
takeover), the published qdd changes by at most qddd_max dt per cycle
from the stream's last setpoint on (the jerk measured as in test_jerk.py);
the line ends on its target."""
import time

from kinctl_testing import (EVENTS, N, STATES, assert_smooth, close, finished, go_nominal, goal_servo_t,
                            max_jerk_ratio, setpoints_since)

# Relative slack of the limit checks: the daemon's core is double.
SLACK = 1e-6
# Cycles of the takeover judged against the jerk limit: the halt's own
# (its first cycles, before the line adds its own motion: a line is
# bounded in Cartesian jerk, not in its joints'). The halt from 0.1 m/s
# lasts some 80 cycles and the line starts where the two together keep
# the Cartesian limits, no sooner than about half of it here.
TAKEOVER = 20


def test_servo_stream_replaced_by_line_without_stopping(kinctld):
    d = kinctld()
    s0 = go_nominal(d)
    g = goal_servo_t()
    g.goal_id = 40
    g.mode = goal_servo_t.REPLACE
    g.kind = goal_servo_t.TWIST
    g.twist = [0.0, 0.1, 0.0, 0.0, 0.0, 0.0]
    g.orientation = [1.0, 0.0, 0.0, 0.0]
    g.timeout_us = 500000
    for _ in range(40):
        d.bus.send("GOAL_SERVO", g)
        time.sleep(0.01)
    last = d.bus.last_setpoint()
    assert last.goal_id == 40 and last.state == STATES["MOVING"]
    target = [last.position[0] + 0.03, last.position[1] + 0.05, last.position[2] + 0.03]
    d.bus.send_goal_line(41, target, list(last.orientation), replace=True)
    accepted = d.bus.wait_event(41, ("ACCEPTED", "REJECTED"))
    assert accepted.event == EVENTS["ACCEPTED"] and accepted.code == 0 and accepted.reason == "", accepted.reason
    assert d.bus.wait_event(40, ("PREEMPTED", "ABORTED")).event == EVENTS["PREEMPTED"]
    s = finished(d, 41)
    assert close(s.position, target, 1e-6), s.position
    stream = setpoints_since(d, s0.cycle)
    assert_smooth(stream, SLACK)
    i = next(i for i, sp in enumerate(stream) if sp.goal_id == 41)
    assert stream[i - 1].goal_id == 40 and stream[i].cycle == stream[i - 1].cycle + 1
    assert stream[i].state == STATES["MOVING"]
    assert max(abs(v) for v in stream[i - 1].qd[:N]) > 0.05  # moving when it is replaced
    assert max(abs(v) for v in stream[i].qd[:N]) > 0.05  # and not stopped for the line
    rj, ra = max_jerk_ratio(stream[i - 1:i + TAKEOVER])
    assert rj <= 1.0 + SLACK and ra <= 1.0 + SLACK, (rj, ra)
    assert rj > 0.1, rj  # the halt does brake
    assert d.stop() == 0
