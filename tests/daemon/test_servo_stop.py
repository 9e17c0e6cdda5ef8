# SPDX-License-Identifier: BSD-3-Clause
"""kinctld: a servo stream is jerk-limited, through LCM.

A twist stream moves puma560's tool from its nominal pose, its twist
shaped within the Cartesian bounds; STOP (or PAUSE) brings every joint to
rest from its (q, qd, qdd), as does the servo timeout
(test_goals.py, test_servo_stream_goes_stale_and_stops). The published qdd
changes by at most qddd_max dt per cycle (the jerk measured as in
test_jerk.py) from the stream's first setpoint to rest."""
import time

from kinctl_testing import (END, EVENTS, N, STATES, assert_smooth, go_nominal, max_jerk_ratio, servo_twist,
                            setpoints_since)

# Relative slack of the limit checks: the daemon's core is double, and a
# stop lasts under a second (kinctl/scurve.h: the rounding of a tick's time).
SLACK = 1e-6


def stream_then(d, goal_id, command):
    """Streams a twist of 0.1 m/s along +y for 0.4 s (its timeout long
    enough not to end it first), sends command, and returns every setpoint
    since the nominal pose and those of the stop (from the stream's last
    moving one to the first at rest), once the arm rests."""
    s0 = go_nominal(d)
    g = servo_twist(goal_id, [0.0, 0.1, 0.0, 0.0, 0.0, 0.0], 500000)
    for _ in range(40):
        d.bus.send("GOAL_SERVO", g)
        time.sleep(0.01)
    d.bus.send_command(command)
    want = STATES["IDLE"] if command == "STOP" else STATES["PAUSED"]
    d.bus.wait(lambda: any(s.state == want and all(v == 0.0 for v in s.qd[:N]) for s in d.bus.setpoints[-3:]), 5.0,
               "rest")
    sps = setpoints_since(d, s0.cycle)
    first = next(i for i, s in enumerate(sps) if s.state == STATES["STOPPING"])
    assert sps[first - 1].state == STATES["MOVING"] and sps[first - 1].goal_id == goal_id
    assert max(abs(v) for v in sps[first - 1].qd[:N]) > 0.05  # moving when it stops
    last = next(i for i, s in enumerate(sps) if i > first and s.state != STATES["STOPPING"])
    assert all(v == 0.0 for v in sps[last].qd[:N]) and all(v == 0.0 for v in sps[last].qdd[:N])
    return sps, sps[first - 1:last + 1]


def test_servo_stop_is_jerk_limited(kinctld):
    d = kinctld()
    sps, stop = stream_then(d, 30, "STOP")
    st = d.bus.wait_event(30, END)
    assert st.event == EVENTS["ABORTED"], st.reason
    assert_smooth(sps, SLACK)
    rj, ra = max_jerk_ratio(stop)
    assert rj <= 1.0 + SLACK and ra <= 1.0 + SLACK, (rj, ra)
    assert rj > 0.5, rj  # the stop does use the jerk it is allowed
    rj, ra = max_jerk_ratio(sps)  # the stream too, from its start
    assert rj <= 1.0 + SLACK and ra <= 1.0 + SLACK, (rj, ra)
    assert d.stop() == 0


def test_servo_pause_is_jerk_limited_and_resumes(kinctld):
    d = kinctld()
    sps, stop = stream_then(d, 31, "PAUSE")
    assert_smooth(sps, SLACK)
    rj, ra = max_jerk_ratio(stop)
    assert rj <= 1.0 + SLACK and ra <= 1.0 + SLACK, (rj, ra)
    # RESUME: the stream takes over again (the tool's timeout ends it).
    d.bus.send_command("RESUME")
    g = servo_twist(31, [0.0, -0.1, 0.0, 0.0, 0.0, 0.0], 50000)
    for _ in range(20):
        d.bus.send("GOAL_SERVO", g)
        time.sleep(0.01)
    st = d.bus.wait_event(31, END)
    assert st.event == EVENTS["ABORTED"] and st.reason.startswith("servo_timeout: "), st.reason
    d.bus.wait_idle()
    sps = setpoints_since(d, sps[0].cycle)
    assert_smooth(sps, SLACK)
    rj, ra = max_jerk_ratio(sps)  # the resumed stream and the timeout's stop too
    assert rj <= 1.0 + SLACK and ra <= 1.0 + SLACK, (rj, ra)
    assert d.stop() == 0
