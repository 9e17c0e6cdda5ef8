# SPDX-License-Identifier: BSD-3-Clause
"""kinctld: every goal kind, preemption, commands and stalls, through LCM.

The arm first goes to puma560's nominal pose QN (elbow bent, wrist not
singular); Cartesian goals are then built around its tool pose."""
import math
import os
import signal
import time

import pytest

from kinctl_testing import (END, EVENT_NAMES, EVENTS, N, QN, QN_ORIENTATION, QN_POSITION, STATES, assert_smooth, close,
                            finished, go_nominal, goal_arc_t, goal_path_t, goal_servo_t, max_jerk_ratio, servo_twist,
                            setpoints_since)


def same_rotation(qa, qb, tol):
    dot = abs(sum(x * y for x, y in zip(qa, qb)))
    return 1.0 - dot <= tol



def test_line_completes(kinctld):
    d = kinctld()
    s0 = go_nominal(d)
    p, o = list(s0.position), list(s0.orientation)
    target = [p[0], p[1] + 0.1, p[2] - 0.05]
    d.bus.send_goal_line(2, target, o)
    s = finished(d, 2)
    assert close(s.position, target, 1e-6), s.position
    assert same_rotation(s.orientation, o, 1e-9)
    assert_smooth(setpoints_since(d, s0.cycle))
    assert d.stop() == 0


def test_arc_completes(kinctld):
    d = kinctld()
    s0 = go_nominal(d)
    p, o = list(s0.position), list(s0.orientation)
    g = goal_arc_t()
    g.goal_id = 3
    g.via = [p[0], p[1] + 0.05, p[2] + 0.05]
    g.position = [p[0], p[1] + 0.1, p[2]]
    g.orientation = o
    d.bus.send("GOAL_ARC", g)
    s = finished(d, 3)
    assert close(s.position, g.position, 1e-6), s.position
    assert_smooth(setpoints_since(d, s0.cycle))
    assert d.stop() == 0


@pytest.mark.parametrize("method", ["BLEND", "SPLINE", "QUINTIC", "LAGRANGE"])
def test_joint_path_completes(kinctld, method):
    d = kinctld()
    s0 = go_nominal(d)
    pts = [[0.2, 0.9, -3.0, 0.1, 0.7, 0.1], [0.4, 0.7, -2.9, 0.0, 0.9, 0.2], [0.1, 0.6, -3.1, -0.1, 0.8, 0.0]]
    g = goal_path_t()
    g.goal_id = 4
    g.space = goal_path_t.JOINT
    g.method = getattr(goal_path_t, method)
    g.n_points, g.dim = len(pts), N
    g.points = [r + [0.0] * (16 - N) for r in pts] + [[0.0] * 16] * (32 - len(pts))
    if method == "LAGRANGE":
        # One polynomial through every knot overshoots when timed from the
        # limits: give it slow knot times.
        g.has_times = 1
        g.times = [2.0, 4.0, 6.0] + [0.0] * 29
    d.bus.send("GOAL_PATH", g)
    s = finished(d, 4)
    assert close(s.q, pts[-1], 1e-9), s.q[:N]
    assert_smooth(setpoints_since(d, s0.cycle))
    assert d.stop() == 0


def test_cartesian_path_completes(kinctld):
    d = kinctld()
    s0 = go_nominal(d)
    p, o = list(s0.position), list(s0.orientation)
    knots = [[p[0], p[1] + 0.05, p[2]], [p[0], p[1] + 0.05, p[2] + 0.05], [p[0], p[1], p[2] + 0.05]]
    g = goal_path_t()
    g.goal_id = 5
    g.space = goal_path_t.CARTESIAN
    g.method = goal_path_t.SPLINE
    g.n_points, g.dim = len(knots), goal_path_t.CARTESIAN_DIM
    g.points = [k + o + [0.0] * 9 for k in knots] + [[0.0] * 16] * (32 - len(knots))
    d.bus.send("GOAL_PATH", g)
    s = finished(d, 5)
    assert close(s.position, knots[-1], 1e-6), s.position
    assert_smooth(setpoints_since(d, s0.cycle))
    assert d.stop() == 0


def test_servo_stream_goes_stale_and_stops(kinctld):
    d = kinctld()
    s0 = go_nominal(d)
    g = servo_twist(6, [0.0, 0.05, 0.0, 0.0, 0.0, 0.0], 50000)
    for _ in range(30):
        d.bus.send("GOAL_SERVO", g)
        time.sleep(0.01)
    # Then silence: the daemon's own clock says stale after 50 ms.
    st = d.bus.wait_event(6, END)
    assert st.event == EVENTS["ABORTED"] and st.reason.startswith("servo_timeout: "), st.reason
    assert st.code < 0
    s = d.bus.wait_idle()
    assert s.position[1] > s0.position[1] + 0.005  # it did move along +y
    assert all(v == 0.0 for v in s.qd[:N])
    sps = setpoints_since(d, s0.cycle)
    assert_smooth(sps)
    # The stream's twist shaped and the timeout's stop jerk-limited: every
    # joint's qdd changes by at most qddd_max dt a cycle (slack as
    # test_servo_stop.py's).
    rj, ra = max_jerk_ratio(sps)
    assert rj <= 1.0 + 1e-6 and ra <= 1.0 + 1e-6, (rj, ra)
    assert d.stop() == 0


def test_pose_stream_is_shaped(kinctld):
    """A pose stream whose pose jumps by 2.2 cm and turns by 0.1 rad: the
    shaped pose reaches it within the joints' jerk limits, the tool at rest
    on it before the stream goes quiet, then the timeout's stop."""
    d = kinctld()
    s0 = go_nominal(d)
    g = servo_twist(7, [0.0] * 6, 50000)
    g.kind = goal_servo_t.POSE
    g.position = [QN_POSITION[0], QN_POSITION[1] + 0.02, QN_POSITION[2] + 0.01]
    w, x, y, z = QN_ORIENTATION
    c, s = math.cos(0.05), math.sin(0.05)  # 0.1 rad about the base's z
    g.orientation = [c * w - s * z, c * x - s * y, c * y + s * x, c * z + s * w]
    for _ in range(150):  # 1.5 s: the shaped approach takes about 0.7 s
        d.bus.send("GOAL_SERVO", g)
        time.sleep(0.01)
    arrived = d.bus.last_setpoint()
    assert close(arrived.position, g.position, 1e-6), arrived.position
    assert same_rotation(arrived.orientation, g.orientation, 1e-10), arrived.orientation
    st = d.bus.wait_event(7, END)
    assert st.event == EVENTS["ABORTED"] and st.reason.startswith("servo_timeout: "), st.reason
    s = d.bus.wait_idle()
    assert close(s.position, g.position, 1e-6)
    sps = setpoints_since(d, s0.cycle)
    assert_smooth(sps)
    rj, ra = max_jerk_ratio(sps)
    assert rj <= 1.0 + 1e-6 and ra <= 1.0 + 1e-6, (rj, ra)
    assert d.stop() == 0


def test_servo_stream_waits_for_the_goal_sent_before_it(kinctld):
    """A servo stream sent right after a replacing goal does not overtake
    that goal's dry run (a replacing goal is judged for a cycle 10 ms or
    more ahead): the goal is taken first, then the stream replaces it; the
    stream's goal is answered once and runs. Before, its first message
    reached the controller first, the goal then took its place (PREEMPTED)
    and a later message made it a new goal (ACCEPTED again)."""
    d = kinctld()
    go_nominal(d)
    d.bus.send_goal_joint(20, [0.5, 0.5, -2.5, 0.5, 0.5, 0.5], vel_scale=0.3)
    d.bus.wait(lambda: any(s.goal_id == 20 for s in d.bus.setpoints[-3:]), 5.0, "motion")
    d.bus.send_goal_joint(21, QN, replace=True, vel_scale=0.3)
    g = servo_twist(22, [0.0, 0.02, 0.0, 0.0, 0.0, 0.0], 100000)
    for _ in range(40):
        d.bus.send("GOAL_SERVO", g)
        time.sleep(0.005)
    d.bus.wait(lambda: any(s.goal_id == 22 for s in d.bus.setpoints[-3:]), 5.0, "the stream running")
    names = [EVENT_NAMES[s.event] for s in d.bus.events(22)]
    assert names[:1] == ["ACCEPTED"] and names.count("ACCEPTED") == 1 and "PREEMPTED" not in names, names
    assert EVENT_NAMES[d.bus.events(21)[0].event] == "ACCEPTED"
    assert d.bus.wait_event(21, END + ("PREEMPTED",)).event == EVENTS["PREEMPTED"]
    assert d.stop() == 0


def test_replace_mid_motion_is_smooth(kinctld):
    d = kinctld()
    s0 = go_nominal(d)
    far = [1.5, 0.5, -2.5, 1.0, 0.5, 1.0]
    d.bus.send_goal_joint(10, far, vel_scale=0.5)
    d.bus.wait(lambda: any(s.goal_id == 10 for s in d.bus.setpoints[-3:]), 5.0, "motion")
    d.bus.wait_setpoints(300)
    d.bus.send_goal_joint(11, QN, replace=True)
    assert d.bus.wait_event(10, END + ("PREEMPTED",)).event == EVENTS["PREEMPTED"]
    s = finished(d, 11)
    assert close(s.q, QN, 1e-9)
    stream = setpoints_since(d, s0.cycle)
    assert_smooth(stream)
    # The new goal takes over from the moving state: the setpoint that
    # first carries goal 11 follows one of goal 10 and is still moving.
    i = next(i for i, p in enumerate(stream) if p.goal_id == 11)
    assert stream[i - 1].goal_id == 10 and stream[i].cycle == stream[i - 1].cycle + 1
    assert max(abs(v) for v in stream[i].qd[:N]) > 0.1
    assert d.stop() == 0


def test_pause_resume(kinctld):
    d = kinctld()
    s0 = go_nominal(d)
    target = [1.0, 0.5, -2.5, 0.5, 0.5, 0.5]
    d.bus.send_goal_joint(20, target, vel_scale=0.5)
    d.bus.wait(lambda: any(s.goal_id == 20 for s in d.bus.setpoints[-3:]), 5.0, "motion")
    d.bus.wait_setpoints(200)
    d.bus.send_command("PAUSE")
    paused = d.bus.wait(lambda: [s for s in d.bus.setpoints[-3:] if s.state == STATES["PAUSED"]
                                 and all(v == 0.0 for v in s.qd[:N])], 5.0, "paused at rest")[-1]
    d.bus.wait_setpoints(100)
    assert close(d.bus.last_setpoint().q, paused.q, 0.0)  # holds
    d.bus.send_command("RESUME")
    s = finished(d, 20)
    assert close(s.q, target, 1e-9)
    assert_smooth(setpoints_since(d, s0.cycle))
    assert d.stop() == 0


def test_estop_latches_until_reset(kinctld):
    d = kinctld()
    go_nominal(d)
    d.bus.send_goal_joint(30, [1.0, 0.5, -2.5, 0.5, 0.5, 0.5], vel_scale=0.5)
    d.bus.wait(lambda: any(s.goal_id == 30 for s in d.bus.setpoints[-3:]), 5.0, "motion")
    d.bus.wait_setpoints(200)
    d.bus.send_command("ESTOP")
    ab = d.bus.wait_event(30, END)
    assert ab.event == EVENTS["ABORTED"] and (ab.code, ab.reason) == (0, "stopped: an ESTOP command ended it"), \
        (ab.event, ab.code, ab.reason)
    d.bus.wait(lambda: [s for s in d.bus.setpoints[-3:] if s.state == STATES["ESTOP"]
                        and all(v == 0.0 for v in s.qd[:N])], 5.0, "e-stopped at rest")
    d.bus.send_goal_joint(31, QN)
    rej = d.bus.wait_event(31, END + ("ACCEPTED",))
    assert rej.event == EVENTS["REJECTED"] and rej.reason.startswith("state: "), rej.reason
    d.bus.send_command("RESET")
    d.bus.wait_idle()
    d.bus.send_goal_joint(32, QN)
    s = finished(d, 32)
    assert close(s.q, QN, 1e-9)
    assert d.stop() == 0


def test_queued_cartesian_goal_checked_from_where_it_starts(kinctld):
    """A line queued behind a joint move is dry-run from the move's end (the
    I/O thread's shadow), not from where the arm is when it arrives."""
    d = kinctld()
    d.bus.send_goal_joint(40, QN)
    p, o = QN_POSITION, QN_ORIENTATION
    target = [p[0], p[1] + 0.1, p[2]]
    d.bus.send_goal_line(41, target, o)
    s = finished(d, 41)
    assert close(s.position, target, 1e-6)
    assert d.bus.wait_event(40, END).event == EVENTS["COMPLETED"]
    assert d.stop() == 0


def test_stall_neither_bursts_nor_jumps(kinctld):
    """SIGSTOP freezes the daemon for 150 ms: the missed cycles are counted
    and skipped; the setpoints carry on with consecutive counters and one
    cycle's motion per setpoint."""
    d = kinctld()
    s0 = go_nominal(d)
    d.bus.send_goal_joint(50, [1.0, 0.5, -2.5, 0.5, 0.5, 0.5], vel_scale=0.5)
    d.bus.wait(lambda: any(s.goal_id == 50 for s in d.bus.setpoints[-3:]), 5.0, "motion")
    d.bus.wait_setpoints(200)
    os.kill(d.proc.pid, signal.SIGSTOP)
    time.sleep(0.15)
    os.kill(d.proc.pid, signal.SIGCONT)
    finished(d, 50)
    d.bus.wait(lambda: [s for s in d.bus.stats if s.overruns >= 100], 5.0, "stats with the overruns")
    with d.bus.lock:
        assert max(s.latency_max_ns for s in d.bus.stats) >= 100_000_000
    assert_smooth(setpoints_since(d, s0.cycle))
    assert d.stop() == 0


def test_overrun_policy_stops_the_arm(kinctld, tmp_path):
    cfg = tmp_path / "k.cfg"
    # A 0.5 s freeze misses 500 cycles, twice the policy's 250: far above
    # what a loaded machine's stalls cost a sanitizer build (tens of ms), so
    # only the freeze can trip it.
    cfg.write_text('controller = { overrun = { missed_cycles = 250; action = "stop"; }; };\n')
    d = kinctld("--config", str(cfg))
    s0 = go_nominal(d)
    d.bus.send_goal_joint(60, [1.0, 0.5, -2.5, 0.5, 0.5, 0.5], vel_scale=0.5)
    d.bus.wait(lambda: any(s.goal_id == 60 for s in d.bus.setpoints[-3:]), 5.0, "motion")
    d.bus.wait_setpoints(200)
    os.kill(d.proc.pid, signal.SIGSTOP)
    time.sleep(0.5)
    os.kill(d.proc.pid, signal.SIGCONT)
    ab = d.bus.wait_event(60, END)
    note = d.bus.wait(lambda: [s for s in d.bus.statuses if s.reason.startswith("overrun: ")], 2.0, "overrun status")
    assert "STOP sent" in note[0].reason
    assert ab.event == EVENTS["ABORTED"] and ab.code < 0 and ab.reason == note[0].reason, (ab.event, ab.code, ab.reason)
    d.bus.wait_idle()
    assert_smooth(setpoints_since(d, s0.cycle))
    assert d.stop() == 0
    assert "overrun: " in d.stderr
