# SPDX-License-Identifier: BSD-3-Clause
"""kinctld keeps a redundant arm's joints within their limits on Cartesian
goals: random lines and arcs of the panda from a pose away from mid-range
(tests/unit/test_ctrl_null_jerk.c's cases, end to end), at the default
Cartesian limits and at random fast ones. The IK step's null-space motion
moves the joints beside the tool's law; the dry run judges it at the
cycle's period and slows a goal whose joints would exceed their jerk
limits (kinctl/check.h). Every cycle of every goal taken stays within
qd_max and qdd_max and changes qdd by at most qddd_max dt, and the goal
ends on its target."""
import random

from kinctl import client as kc
from kinctl_arms import HOMES, Arm
from kinctl_testing import END, EVENTS, close, fast_cart_limits, finished, random_offset, setpoints_since

CASES = 16


def random_goal(rng, c, home, goal_id):
    """A line or (odd c) an arc of 5 to 30 cm from home's position in its
    orientation: at the default limits for c % 4 < 2, else at speed, accel
    and jerk drawn up to fast ones."""
    to = random_offset(rng, home.position, 0.05, 0.3) + list(home.orientation)
    limits = fast_cart_limits(rng) if c % 4 >= 2 else {}
    if c % 2:
        via = [0.5 * (p + t) + rng.uniform(-0.05, 0.05) for p, t in zip(home.position, to)]
        return to, kc.make_goal_arc(via, to, goal_id=goal_id, **limits)
    return to, kc.make_goal_line(to, goal_id=goal_id, slerp=True, **limits)


def test_panda_lines_and_arcs_within_joint_limits(kinctld):
    a = Arm("panda")
    d = kinctld("--model", "panda")
    rng = random.Random(0x4E11)
    taken = 0
    for c in range(CASES):
        d.bus.send_goal_joint(100 + 2 * c, HOMES["panda"])
        home = finished(d, 100 + 2 * c)
        goal_id = 101 + 2 * c
        to, msg = random_goal(rng, c, home, goal_id)
        d.bus.send("GOAL_ARC" if c % 2 else "GOAL_LINE", msg)
        st = d.bus.wait_event(goal_id, END)
        if st.event == EVENTS["REJECTED"]:  # out of reach, or a singularity on the way: the dry run says so
            continue
        s = finished(d, goal_id)
        assert close(s.position, to[:3], 1e-6), (goal_id, s.position, to)
        stream = [p for p in setpoints_since(d, home.cycle) if p.goal_id == goal_id]
        assert len(stream) > 100
        a.check_limits(stream)
        taken += 1
    assert taken >= CASES // 2
    assert d.stop() == 0
