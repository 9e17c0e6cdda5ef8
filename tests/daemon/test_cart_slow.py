# SPDX-License-Identifier: BSD-3-Clause
"""kinctld keeps a Cartesian goal's joints within their jerk limits: fast
random lines from puma560's nominal pose, whose joints' jerk the dry run
finds beyond qddd_max (the Jacobian amplifies the tool's: unit.check_slow
shows such lines exceed it at 1 ms as asked), are slowed before they reach
the controller (kinctl/check.h, kc_goal_slow) and logged; every cycle of
each line then changes every joint's qdd by at most qddd_max dt, within
the velocity and acceleration limits, and the line ends on its target.

And a Cartesian path of two knots with parabolic blends, whose acceleration
steps where a blend meets a line: the joints' jerk goes as the square of
the share of speed, times a factor of where the step falls on the ticks,
so a slower share may be judged over a faster one (unit.check_slow), as
the search meets on this one (judged at 0.497 of its speed with the jerk
at 1.17 of the limits). The search goes on from such a share: the path is
slowed below it, completes within qddd_max and ends on its last knot."""
import random
import re

from kinctl import client as kc
from kinctl_testing import (END, EVENTS, assert_smooth, close, finished, go_nominal, max_jerk_ratio,
                            random_offset, setpoints_since)

SLACK = 1e-6
LINES = 4


def test_fast_lines_are_slowed_within_joint_jerk(kinctld):
    d = kinctld()
    rng = random.Random(0x5103)
    ids = []
    s0 = go_nominal(d)
    for goal_id in range(40, 60):
        if len(ids) == LINES:
            break
        to = random_offset(rng, s0.position, 0.05, 0.15) + list(s0.orientation)
        d.bus.send("GOAL_LINE", kc.make_goal_line(to, goal_id=goal_id, slerp=True, speed=rng.uniform(0.3, 0.5),
                                                  accel=rng.uniform(2.0, 3.0), jerk=rng.uniform(30.0, 60.0)))
        st = d.bus.wait_event(goal_id, END)
        if st.event == EVENTS["REJECTED"]:  # out of the arm's reach from here: drawn again
            assert st.reason.startswith("unreachable: "), st.reason
            continue
        s = finished(d, goal_id)
        assert close(s.position, to[:3], 1e-6), (s.position, to)
        stream = [p for p in setpoints_since(d, s0.cycle) if p.goal_id == goal_id]
        assert_smooth(stream, SLACK)
        rj, ra = max_jerk_ratio(stream)
        assert rj <= 1.0 + SLACK and ra <= 1.0 + SLACK, (goal_id, rj, ra)
        ids.append(goal_id)
        s0 = go_nominal(d, 100 + goal_id)
    assert len(ids) == LINES
    assert d.stop() == 0
    slowed = {int(m.group(1)): float(m.group(2))
              for m in re.finditer(r"goal (\d+) slowed to ([0-9.e+-]+) of its speed", d.stderr)}
    # Every one of these lines needed it, and was slowed, not stopped.
    assert set(slowed) == set(ids), d.stderr
    assert all(0.2 < s < 1.0 for s in slowed.values()), slowed


def test_parabolic_path_is_slowed_within_joint_jerk(kinctld):
    d = kinctld()
    rng = random.Random(4)
    s0 = go_nominal(d)
    knot = random_offset(rng, s0.position, 0.03, 0.15)
    points = [knot + list(s0.orientation), random_offset(rng, knot, 0.03, 0.15) + list(s0.orientation)]
    d.bus.send("GOAL_PATH", kc.make_goal_path(points, space="cartesian", method="blend", shape="parabolic",
                                              goal_id=200))
    s = finished(d, 200)
    assert close(s.position, points[-1][:3], 1e-6), (s.position, points[-1])
    stream = [p for p in setpoints_since(d, s0.cycle) if p.goal_id == 200]
    assert_smooth(stream, SLACK)
    rj, ra = max_jerk_ratio(stream)
    assert rj <= 1.0 + SLACK and ra <= 1.0 + SLACK, (rj, ra)
    assert d.stop() == 0
    slowed = re.search(r"goal 200 slowed to ([0-9.e+-]+) of its speed", d.stderr)
    assert slowed and 0.2 < float(slowed.group(1)) < 0.497, d.stderr
