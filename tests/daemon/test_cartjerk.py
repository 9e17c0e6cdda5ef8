# SPDX-License-Identifier: BSD-3-Clause
"""kinctld's jerk-limited lines, through LCM: a goal_line_t's jerk reaches
the controller, whose line then lasts the rest-to-rest optimum of a
jerk-limited law over its length (computed here independently, as
tests/calc/test_calc_interp.py does), longer than the trapezoid it would
have been; the setpoints stay within the joints' velocity and acceleration
limits every cycle, and the line ends on its target."""
import math

from kinctl import client as kc
from kinctl_testing import DT, assert_smooth, close, finished, go_nominal, setpoints_since

SLACK = 1e-6
# Cycles the tool may take after the line's last tick to settle within the
# IK tolerances (kinctl/ctrl.h): the online law's gain of 100/s shrinks the
# error a tick leaves (about 1e-5 m) by e^-5 in 50 cycles, under its 1e-7 m
# tolerance (seen: 21 cycles after the stiffer line). The durations compared
# differ by more: 1179 cycles for this goal's jerk, 1000 for the default.
SETTLE = 50


def rest_to_rest_time(D, V, A, J):
    """The fastest rest-to-rest time over D within V, A, J: reaching a speed v from rest and stopping again
    take ta(v) = v/A + A/J (v >= A^2/J) or 2 sqrt(v/J) each, over v ta(v) together; the line cruises at the
    largest v <= V with v ta(v) <= D (bisection)."""
    def ta(v):
        return v / A + A / J if v >= A * A / J else 2.0 * math.sqrt(v / J)
    v = V
    if v * ta(v) > D:
        lo, hi = 0.0, V
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if mid * ta(mid) > D else (mid, hi)
        v = lo
    return 2.0 * ta(v) + (D - v * ta(v)) / v


def line_cycles(d, goal_id, s0, to, **kw):
    msg = kc.make_goal_line(to, goal_id=goal_id, slerp=True, **kw)
    d.bus.send("GOAL_LINE", msg)
    s = finished(d, goal_id)
    assert close(s.position, to[:3], 1e-6)
    stream = [p for p in setpoints_since(d, s0.cycle) if p.goal_id == goal_id]
    assert_smooth(stream, SLACK)
    return len(stream)


def test_line_jerk_reaches_the_controller(kinctld):
    d = kinctld()
    s0 = go_nominal(d)
    here = list(s0.position)
    up = here[:2] + [here[2] + 0.1] + list(s0.orientation)
    V, A, J, L = 0.2, 0.5, 2.0, 0.1
    n_jerk = line_cycles(d, 30, s0, up, speed=V, accel=A, jerk=J)
    T = rest_to_rest_time(L, V, A, J)
    assert math.ceil(T / DT - 1e-9) <= n_jerk <= math.ceil(T / DT - 1e-9) + SETTLE, (n_jerk, T / DT)
    # Back down with the jerk limit ten times higher: closer to the trapezoid's L/V + V/A.
    s1 = d.bus.wait_idle()
    n_fast = line_cycles(d, 31, s1, here + list(s0.orientation), speed=V, accel=A, jerk=10 * J)
    T_fast = rest_to_rest_time(L, V, A, 10 * J)
    assert math.ceil(T_fast / DT - 1e-9) <= n_fast <= math.ceil(T_fast / DT - 1e-9) + SETTLE, (n_fast, T_fast / DT)
    assert T_fast < T and L / V + V / A < T_fast
    assert d.stop() == 0
