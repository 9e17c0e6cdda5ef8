# SPDX-License-Identifier: BSD-3-Clause
"""The Python API (kinctl.client) refuses bad arguments in its own terms:
each ValueError names the parameter as the API spells it, never a flag of
the command line."""
import math

import pytest

from kinctl import client as kc

DOWN = [0.7071068, 0.0, 0.7071068, 0.0]

CASES = [
    (lambda: kc.make_goal_joint([]), "q needs 1 to 16 joint values, got 0"),
    (lambda: kc.make_goal_joint([0.0, math.nan]), "q[1] = nan is not a finite number"),
    (lambda: kc.make_goal_joint([0.0], vel_scale=2.0), "vel_scale = 2.0 must be a fraction"),
    (lambda: kc.make_goal_joint([0.0], profile="scurve"), "profile = 'scurve' must be 'jerk', 'trapezoid' or None"),
    (lambda: kc.make_goal_line([0.5, 0.0, 0.5, 1.0, 1.0, 0.0, 0.0]), "to orientation = 1.0,1.0,0.0,0.0 is not a unit"),
    (lambda: kc.make_goal_line([0.5, 0.0, 0.5] + DOWN, angular_speed=-1.0), "angular_speed = -1.0 must be >= 0"),
    (lambda: kc.make_goal_line([0.5, 0.0, 0.5] + DOWN, jerk=-2.0), "jerk = -2.0 must be >= 0"),
    (lambda: kc.make_goal_arc([0.1, 0.2, 0.3], [0.5, 0.0, 0.5] + DOWN, angular_jerk=math.inf),
     "angular_jerk = inf"),
    (lambda: kc.make_goal_path([[0.0]], jerk=math.nan), "jerk = nan"),
    (lambda: kc.make_goal_line([0.5, 0.0]), "to needs 7 numbers, got 2"),
    (lambda: kc.make_goal_arc([0.1, 0.2], [0.5, 0.0, 0.5] + DOWN), "via needs 3 numbers, got 2"),
    (lambda: kc.make_goal_path([]), "points needs 1 to"),
    (lambda: kc.make_goal_path([[0.0]], space="polar"), "space = 'polar' must be 'joint' or 'cartesian'"),
    (lambda: kc.make_goal_path([[0.0]], method="bezier"), "method = 'bezier' must be"),
    (lambda: kc.make_goal_path([[0.0], [0.1]], times=[1.0, 0.5]), "times must be positive and increasing"),
    (lambda: kc.make_goal_path([[0.0], [0.1]], blend_time=-1.0), "blend_time = -1.0 must be >= 0"),
    (lambda: kc.make_servo_message(1), "a servo message needs either pose or twist"),
    (lambda: kc.make_servo_message(1, twist=[0.0] * 5), "twist needs 6 numbers, got 5"),
]


@pytest.mark.parametrize("call,expect", CASES, ids=[c[1][:30] for c in CASES])
def test_errors_in_the_apis_terms(call, expect):
    with pytest.raises(ValueError) as e:
        call()
    assert expect in str(e.value), str(e.value)
    assert "--" not in str(e.value), str(e.value)


def test_jerk_fields_reach_the_messages():
    g = kc.make_goal_line([0.5, 0.0, 0.5] + DOWN, jerk=3.0, angular_jerk=20.0)
    assert (g.jerk, g.angular_jerk) == (3.0, 20.0)
    g = kc.make_goal_arc([0.5, 0.1, 0.5], [0.5, 0.0, 0.6] + DOWN, jerk=4.0)
    assert (g.jerk, g.angular_jerk) == (4.0, 0.0)
    g = kc.make_goal_path([[0.5, 0.0, 0.5] + DOWN], space="cartesian", angular_jerk=7.0)
    assert (g.jerk, g.angular_jerk) == (0.0, 7.0)
