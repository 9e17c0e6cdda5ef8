# SPDX-License-Identifier: BSD-3-Clause
"""kinctld: a servo stream replaced by a line (or by a joint path) takes
over in the cycle it arrives, without stopping, through LCM
(kinctl/ctrl.h: the stream's jerk-limited halt, joint by joint,
superposed on the line, or on the path in joint space).

A twist stream moves puma560's tool from its nominal pose; a line replaces
it. The line is accepted with no reason (not stop_first), the stream is
preempted, and the line's first setpoint follows the stream's last in the
next cycle with the arm still moving. Every published setpoint is smooth
(assert_smooth); through the takeover, while the setpoints are the halt's
(the line starts from rest where the halt ends, no sooner than the
takeover), the published qdd changes by at most qddd_max dt per cycle
from the stream's last setpoint on (the jerk measured as in test_jerk.py);
the line ends on its target. The joint path likewise, ending on its
last knot."""
import time

from kinctl_testing import (EVENTS, N, STATES, assert_smooth, close, finished, go_nominal, goal_path_t, max_jerk_ratio,
                            servo_twist, setpoints_since)

# Relative slack of the limit checks: the daemon's core is double.
SLACK = 1e-6
# Cycles of the takeover judged against the jerk limit: the halt's own
# (its first cycles, before the line adds its own motion: a line is
# bounded in Cartesian jerk, not in its joints'). The halt from 0.1 m/s
# lasts some 80 cycles and the line starts where the two together keep
# the Cartesian limits, no sooner than about half of it here.
TAKEOVER = 20


# The stream's timeout (us): long enough not to end it before the goal
# replacing it is taken, its dry run included (the daemon caps it at
# controller.servo_timeout_ms, 100 ms by default: raised to it here). A
# stream going stale is an input of a cycle the dry run cannot foresee:
# a replacing goal judged past it is refused as late.
TIMEOUT_US = 500000


def started(kinctld, tmp_path):
    """kinctld on puma560 whose streams may ask for TIMEOUT_US."""
    cfg = tmp_path / "servo.cfg"
    cfg.write_text(f"controller = {{ servo_timeout_ms = {TIMEOUT_US / 1000.0}; }};\n")
    return kinctld("--config", str(cfg))


def stream(d, goal_id):
    """Streams a twist of 0.1 m/s along +y for 0.4 s from the nominal pose;
    returns the nominal setpoint and the stream's latest."""
    s0 = go_nominal(d)
    g = servo_twist(goal_id, [0.0, 0.1, 0.0, 0.0, 0.0, 0.0], TIMEOUT_US)
    for _ in range(40):
        d.bus.send("GOAL_SERVO", g)
        time.sleep(0.01)
    last = d.bus.last_setpoint()
    assert last.goal_id == goal_id and last.state == STATES["MOVING"]
    return s0, last


def assert_taken_over(d, s0, old, new):
    """new accepted with no reason, old preempted; the setpoints smooth,
    new's first following old's last in the next cycle, moving; the
    takeover's jerk within the limits. Returns the setpoints."""
    accepted = d.bus.wait_event(new, ("ACCEPTED", "REJECTED"))
    assert accepted.event == EVENTS["ACCEPTED"] and accepted.code == 0 and accepted.reason == "", accepted.reason
    assert d.bus.wait_event(old, ("PREEMPTED", "ABORTED")).event == EVENTS["PREEMPTED"]
    finished(d, new)
    sps = setpoints_since(d, s0.cycle)
    assert_smooth(sps, SLACK)
    i = next(i for i, sp in enumerate(sps) if sp.goal_id == new)
    assert sps[i - 1].goal_id == old and sps[i].cycle == sps[i - 1].cycle + 1
    assert sps[i].state == STATES["MOVING"]
    assert max(abs(v) for v in sps[i - 1].qd[:N]) > 0.05  # moving when it is replaced
    assert max(abs(v) for v in sps[i].qd[:N]) > 0.05  # and not stopped for the new goal
    rj, ra = max_jerk_ratio(sps[i - 1:i + TAKEOVER])
    assert rj <= 1.0 + SLACK and ra <= 1.0 + SLACK, (rj, ra)
    assert rj > 0.1, rj  # the halt does brake
    return sps


def test_servo_stream_replaced_by_line_without_stopping(kinctld, tmp_path):
    d = started(kinctld, tmp_path)
    s0, last = stream(d, 40)
    target = [last.position[0] + 0.03, last.position[1] + 0.05, last.position[2] + 0.03]
    d.bus.send_goal_line(41, target, list(last.orientation), replace=True)
    sps = assert_taken_over(d, s0, 40, 41)
    assert close(sps[-1].position, target, 1e-6), sps[-1].position
    assert d.stop() == 0


def test_servo_stream_replaced_by_joint_path_without_stopping(kinctld, tmp_path):
    d = started(kinctld, tmp_path)
    s0, last = stream(d, 42)
    pts = [[q + 0.1 for q in last.q[:N]], [q + 0.2 for q in last.q[:N]]]
    g = goal_path_t()
    g.goal_id = 43
    g.mode = goal_path_t.REPLACE
    g.space = goal_path_t.JOINT
    g.method = goal_path_t.QUINTIC
    g.n_points, g.dim = len(pts), N
    g.points = [r + [0.0] * (16 - N) for r in pts] + [[0.0] * 16] * (32 - len(pts))
    d.bus.send("GOAL_PATH", g)
    sps = assert_taken_over(d, s0, 42, 43)
    assert close(sps[-1].q, pts[-1], 1e-9), sps[-1].q[:N]
    assert d.stop() == 0
