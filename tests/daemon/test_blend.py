# SPDX-License-Identifier: BSD-3-Clause
"""kinctld: a line replaced mid-motion by another line takes over in the
cycle it arrives, without stopping (kinctl/ctrl.h: the old line's stop on
its path superposed on the new line), through LCM. No logged setpoint
jumps: consecutive cycles, each joint's q and qd changing within its
limits times dt, the tool's position within the Cartesian speed times dt;
the tool keeps moving through the takeover and ends on the new target. So
does a line replacing a jerk-limited joint move (the move's stop in joint
space superposed). A replacement that must stop first (a line replacing a
trapezoid joint move) is accepted with the reason stop_first. On the
Panda (7 joints: the full task leaves a null space) a line replacing a
joint move takes over the same way, the move's stop fed to the IK step
in that null space too, every setpoint within the arm's limits, its
jerk included (kinctl_arms.Arm.check_limits). Joint and Cartesian paths
that kinctld runs on its jerk-limited ramps take over a joint move and a
line the same way."""
import math

import pytest

from kinctl import client as kc
from kinctl_arms import HOMES, Arm
from kinctl_testing import (DT, END, EVENTS, QN, assert_smooth, close, finished, go_nominal, goal_joint_t,
                            setpoints_since)

# The controller's default Cartesian speed (m/s), and the slack of the tool
# speed measured on the published poses: the online IK law adds gain *
# error (gain 100/s, errors of the order of its tolerance) to the target's
# own speed.
SPEED = 0.25
TOOL_SLACK = 0.01



def tool_speed(a, b):
    return math.dist(a.position, b.position) / ((b.cycle - a.cycle) * DT)


def test_line_replaced_by_line_without_stopping(kinctld):
    d = kinctld()
    s0 = go_nominal(d)
    p, o = list(s0.position), list(s0.orientation)
    first = [p[0], p[1] + 0.15, p[2]]
    second = [p[0] + 0.04, p[1] + 0.2, p[2] - 0.03]
    d.bus.send_goal_line(2, first, o)
    d.bus.wait(lambda: any(s.goal_id == 2 for s in d.bus.setpoints[-3:]), 5.0, "motion")
    d.bus.wait_setpoints(350)
    d.bus.send_goal_line(3, second, o, replace=True)
    assert d.bus.wait_event(2, ("PREEMPTED",) + END).event == EVENTS["PREEMPTED"]
    accepted = d.bus.wait_event(3, ("ACCEPTED", "REJECTED"))
    assert accepted.event == EVENTS["ACCEPTED"] and accepted.code == 0 and accepted.reason == "", accepted.reason
    s = finished(d, 3)
    assert close(s.position, second, 1e-6), s.position
    stream = setpoints_since(d, s0.cycle)
    assert_smooth(stream)
    worst = max(tool_speed(a, b) for a, b in zip(stream, stream[1:]))
    assert worst <= SPEED * (1 + TOOL_SLACK), worst
    # The takeover: the first setpoint of goal 3 follows one of goal 2 in
    # the next cycle, and the tool does not come to rest between the two
    # lines (stopping first, it would: the new line starts from rest).
    i = next(i for i, sp in enumerate(stream) if sp.goal_id == 3)
    assert stream[i - 1].goal_id == 2 and stream[i].cycle == stream[i - 1].cycle + 1
    moving = stream[i - 1:]
    end = next(k for k, sp in enumerate(moving) if tool_speed(sp, moving[k + 1]) < 0.01)
    slowest = min(tool_speed(a, b) for a, b in zip(moving[:end], moving[1:end + 1]))
    assert tool_speed(stream[i - 1], stream[i]) > 0.05
    # Where the speed first drops below 1 cm/s, the tool is at the end.
    assert math.dist(moving[end].position, second) < 1e-3, (end, moving[end].position, slowest)
    assert d.stop() == 0


def replace_joint_move_by_line(d, profile):
    """A joint move (2) of the given profile from QN, at a fifth of the
    joints' speed (still moving when a replacing goal's judgement in a slow
    build takes over some hundred ms later: scheduled takeover), replaced
    200 cycles in by a line (3) 5 cm up from QN's tool point; its ACCEPTED
    status, the line's target and the first cycle's setpoint."""
    s0 = go_nominal(d)
    p, o = list(s0.position), list(s0.orientation)
    d.bus.send_goal_joint(2, [q + 0.3 for q in QN], profile=profile, vel_scale=0.2)
    d.bus.wait(lambda: any(s.goal_id == 2 for s in d.bus.setpoints[-3:]), 5.0, "motion")
    d.bus.wait_setpoints(200)
    target = [p[0], p[1] + 0.05, p[2]]
    d.bus.send_goal_line(3, target, o, replace=True)
    accepted = d.bus.wait_event(3, ("ACCEPTED", "REJECTED"))
    assert accepted.event == EVENTS["ACCEPTED"] and accepted.code == 0, accepted.reason
    return accepted, target, s0


def test_line_replacing_a_joint_move_without_stopping(kinctld):
    d = kinctld()
    accepted, target, s0 = replace_joint_move_by_line(d, goal_joint_t.PROFILE_CONFIG)
    assert accepted.reason == "", accepted.reason
    assert d.bus.wait_event(2, ("PREEMPTED",) + END).event == EVENTS["PREEMPTED"]
    s = finished(d, 3)
    assert close(s.position, target, 1e-6), s.position
    stream = setpoints_since(d, s0.cycle)
    assert_smooth(stream)
    # The line's first setpoint follows the joint move's in the next
    # cycle, the tool still moving (stopping first, it would be at rest).
    i = next(i for i, sp in enumerate(stream) if sp.goal_id == 3)
    assert stream[i - 1].goal_id == 2 and stream[i].cycle == stream[i - 1].cycle + 1
    assert tool_speed(stream[i - 1], stream[i]) > 0.05
    assert d.stop() == 0


def test_line_replacing_a_trapezoid_joint_move_stops_first(kinctld):
    d = kinctld()
    accepted, target, s0 = replace_joint_move_by_line(d, goal_joint_t.PROFILE_TRAPEZOID)
    assert accepted.reason.startswith("stop_first: "), accepted.reason
    s = finished(d, 3)
    assert close(s.position, target, 1e-6), s.position
    assert_smooth(setpoints_since(d, s0.cycle))
    assert d.stop() == 0


def taken_over(d, a, s0):
    """Goal 3, sent to replace goal 2: accepted with no reason, goal 2
    preempted, goal 3 finished, every setpoint since s0 within arm a's
    limits (Arm.check_limits), goal 3's first the cycle after goal 2's
    last. Returns goal 3's last setpoint and its first."""
    accepted = d.bus.wait_event(3, ("ACCEPTED", "REJECTED"))
    assert accepted.event == EVENTS["ACCEPTED"] and accepted.code == 0 and accepted.reason == "", accepted.reason
    assert d.bus.wait_event(2, ("PREEMPTED",) + END).event == EVENTS["PREEMPTED"]
    s = finished(d, 3)
    stream = setpoints_since(d, s0.cycle)
    a.check_limits(stream)
    i = next(i for i, sp in enumerate(stream) if sp.goal_id == 3)
    assert stream[i - 1].goal_id == 2 and stream[i].cycle == stream[i - 1].cycle + 1
    return s, stream[i]


def test_panda_line_replacing_a_joint_move_without_stopping(kinctld):
    a = Arm("panda")
    d = kinctld("--model", "panda")
    d.bus.send_goal_joint(1, HOMES["panda"])
    s0 = finished(d, 1)
    d.bus.send_goal_joint(2, [q + 0.2 for q in HOMES["panda"]], vel_scale=0.2)
    d.bus.wait(lambda: any(s.goal_id == 2 for s in d.bus.setpoints[-3:]), 5.0, "motion")
    d.bus.wait_setpoints(200)
    target = [s0.position[0], s0.position[1], s0.position[2] + 0.05]
    d.bus.send_goal_line(3, target, list(s0.orientation), replace=True)
    s, first = taken_over(d, a, s0)
    assert close(s.position, target, 1e-6), s.position
    assert max(abs(v) for v in first.qd[:a.n]) > 0.05  # not stopped for the line
    assert d.stop() == 0


# Paths kinctld runs on its jerk-limited ramps of tau' (Lagrange's does not
# start at rest; a cubic spline's acceleration steps at its ends): a joint
# path replacing a puma560 joint move, a Cartesian path replacing a line,
# each takes over in the cycle it arrives, superposed on the stop of the
# motion it replaces like any other path.
RAMPED = [("joint", "lagrange", "clamped"), ("joint", "spline", "natural"), ("joint", "spline", "clamped"),
          ("cartesian", "spline", "clamped"), ("cartesian", "lagrange", "clamped"),
          ("cartesian", "spline", "natural")]


@pytest.mark.parametrize("space,method,ends", RAMPED)
def test_ramped_path_taking_over_without_stopping(kinctld, space, method, ends):
    a = Arm("puma560")
    d = kinctld()
    d.bus.send_goal_joint(1, HOMES["puma560"])
    s0 = finished(d, 1)
    p = list(s0.position)
    if space == "joint":
        d.bus.send_goal_joint(2, [q + 0.2 for q in HOMES["puma560"]], vel_scale=0.2)
    else:
        d.bus.send_goal_line(2, [p[0], p[1] + 0.15, p[2]], list(s0.orientation))
    d.bus.wait(lambda: any(s.goal_id == 2 for s in d.bus.setpoints[-3:]), 5.0, "motion")
    here = d.bus.wait_setpoints(200)[-1]
    if space == "joint":
        points = [[q - 0.1 for q in here.q[:a.n]], [q - 0.2 for q in here.q[:a.n]]]
        target = points[-1]
    else:
        p = list(here.position)
        points = [[p[0], p[1], p[2] + 0.03] + list(here.orientation),
                  [p[0] + 0.03, p[1], p[2] + 0.05] + list(here.orientation)]
        target = points[-1][:3]
    d.bus.send("GOAL_PATH", kc.make_goal_path(points, space=space, method=method, ends=ends, goal_id=3,
                                               replace=True))
    s, first = taken_over(d, a, s0)
    if space == "joint":
        assert close(s.q[:a.n], target, 1e-9), s.q
    else:
        assert close(s.position, target, 1e-6), s.position
    assert max(abs(v) for v in first.qd[:a.n]) > 0.01  # not stopped for the path
    assert d.stop() == 0
