# SPDX-License-Identifier: BSD-3-Clause
"""kinctld: a servo stream replacing a joint move takes over in the cycle
it arrives, without stopping, through LCM (kinctl/ctrl.h: on an arm of
six joints or more the stream's target starts where the IK step would
have tracked one with the joints' motion, so their acceleration goes on
through the takeover).

puma560 moves from its nominal pose by a joint move slowed to 5 % of its
limits (the tool then stays within a stream's default Cartesian speed and
acceleration, which a joint move at full speed does not: that one stops
first); a twist stream replaces it while every joint still moves. The
stream is accepted with no reason (not stop_first), the joint move is
preempted, and the stream's first setpoint follows the move's last in
the next cycle with the arm still moving. Every published setpoint is
smooth (assert_smooth); from the move's last setpoint to the stream's
first, qdd changes by at most qddd_max dt (the joints' acceleration goes
on: a step of it at the takeover is what stopping first avoided). The
stream then ends by its timeout, aborted, the arm at rest. The same for
a pose stream replacing a line's stop on its path, and for a twist
stream replacing the Panda's joint move: on its seven joints the IK step
does not carry the joint move's self-motion, which comes to the step's
within the joints' jerk limits (Arm.check_limits on every setpoint)."""
import time

from kinctl import client as kc
from kinctl_arms import HOMES, Arm
from kinctl_testing import (EVENTS, N, QN, STATES, assert_smooth, finished, go_nominal, max_jerk_ratio, servo_twist,
                            setpoints_since)

# Relative slack of the limit checks: the daemon's core is double.
SLACK = 1e-6
# The joint move's share of the joints' limits, and how far each joint
# goes (rad): about 1.5 s of motion, the stream sent 0.5 s in.
SCALE = 0.05
TRAVEL = 0.3
# The stream: a twist of 0.05 m/s along +z, a message every 10 ms for
# 0.6 s (its takeover may be scheduled some hundred ms after its first
# message in a slow build), stale after 100 ms (the daemon's default cap).
TWIST = [0.0, 0.0, 0.05, 0.0, 0.0, 0.0]
TIMEOUT_US = 100000


def stream_takes_over(d, s0, g, arm=None):
    """Sends servo message g (goal 3) every 10 ms for 0.6 s, replacing goal
    2: accepted with no reason, goal 2 preempted, the stream ending by its
    timeout, aborted, the arm at rest; every setpoint since s0 smooth
    (the PUMA 560's), or within arm's limits (an Arm: Arm.check_limits).
    Returns the setpoints and the index of the stream's first."""
    for _ in range(60):
        d.bus.send("GOAL_SERVO", g)
        time.sleep(0.01)
    accepted = d.bus.wait_event(3, ("ACCEPTED", "REJECTED"))
    assert accepted.event == EVENTS["ACCEPTED"] and accepted.code == 0 and accepted.reason == "", accepted.reason
    assert d.bus.wait_event(2, ("PREEMPTED", "ABORTED", "COMPLETED")).event == EVENTS["PREEMPTED"]
    end = d.bus.wait_event(3, ("ABORTED", "COMPLETED", "FAULT"))
    assert end.event == EVENTS["ABORTED"], end.reason
    s = d.bus.wait_idle()
    sps = setpoints_since(d, s0.cycle)
    if arm is None:
        assert_smooth(sps, SLACK)
    else:
        arm.check_limits(sps)
    i = next(i for i, sp in enumerate(sps) if sp.goal_id == 3)
    assert all(v == 0.0 for v in s.qd[:arm.n if arm else N])
    return sps, i


def test_joint_move_replaced_by_twist_stream_without_stopping(kinctld):
    d = kinctld()
    s0 = go_nominal(d)
    d.bus.send_goal_joint(2, [q + TRAVEL for q in QN], vel_scale=SCALE, acc_scale=SCALE)
    assert d.bus.wait_event(2, ("STARTED",)).event == EVENTS["STARTED"]
    time.sleep(0.5)
    sps, i = stream_takes_over(d, s0, servo_twist(3, TWIST, TIMEOUT_US))
    assert sps[i - 1].goal_id == 2 and sps[i].cycle == sps[i - 1].cycle + 1
    assert sps[i].state == STATES["MOVING"]
    assert min(abs(v) for v in sps[i - 1].qd[:N]) > 0.01  # every joint moving when it is replaced
    assert max(abs(v) for v in sps[i].qd[:N]) > 0.01  # and not stopped for the stream
    rj, _ = max_jerk_ratio(sps[i - 1:i + 1])
    assert rj <= 1.0 + SLACK, rj
    assert d.stop() == 0


def test_stopping_line_replaced_by_pose_stream_without_stopping(kinctld):
    """A line stopping on its path for a STOP, replaced by a pose stream
    while it still moves: the stream goes on from the stop's target (its
    pose, twist and rate), accepted with no reason, the line preempted,
    the stream's first setpoint the next cycle's with the arm moving, and
    the joints' qdd changing by at most qddd_max dt through it."""
    d = kinctld()
    s0 = go_nominal(d)
    p = list(s0.position)
    d.bus.send_goal_line(2, [p[0], p[1] + 0.15, p[2]], list(s0.orientation))
    assert d.bus.wait_event(2, ("STARTED",)).event == EVENTS["STARTED"]
    time.sleep(0.5)
    d.bus.send_command("STOP")
    d.bus.wait(lambda: d.bus.setpoints[-1].state == STATES["STOPPING"], 2.0, "the stop")
    g = kc.make_servo_message(3, pose=[p[0], p[1] + 0.1, p[2]] + list(s0.orientation), replace=True,
                              timeout_s=TIMEOUT_US / 1e6)
    sps, i = stream_takes_over(d, s0, g)
    assert sps[i - 1].goal_id == 2 and sps[i - 1].state == STATES["STOPPING"]
    assert sps[i].cycle == sps[i - 1].cycle + 1 and sps[i].state == STATES["MOVING"]
    assert max(abs(v) for v in sps[i].qd[:N]) > 0.01  # not stopped for the stream
    rj, _ = max_jerk_ratio(sps[i - 1:i + 1])
    assert rj <= 1.0 + SLACK, rj
    assert d.stop() == 0


def test_panda_joint_move_replaced_by_twist_stream_without_stopping(kinctld):
    arm = Arm("panda")
    d = kinctld("--model", "panda")
    d.bus.send_goal_joint(1, HOMES["panda"])
    s0 = finished(d, 1)
    d.bus.send_goal_joint(2, [q + TRAVEL for q in HOMES["panda"]], vel_scale=SCALE, acc_scale=SCALE)
    assert d.bus.wait_event(2, ("STARTED",)).event == EVENTS["STARTED"]
    time.sleep(0.5)
    sps, i = stream_takes_over(d, s0, servo_twist(3, TWIST, TIMEOUT_US), arm)
    assert sps[i - 1].goal_id == 2 and sps[i].cycle == sps[i - 1].cycle + 1
    assert sps[i].state == STATES["MOVING"]
    assert min(abs(v) for v in sps[i - 1].qd[:arm.n]) > 0.01  # every joint moving when it is replaced
    assert max(abs(v) for v in sps[i].qd[:arm.n]) > 0.01  # and not stopped for the stream
    assert d.stop() == 0
