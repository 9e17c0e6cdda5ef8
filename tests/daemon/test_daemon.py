# SPDX-License-Identifier: BSD-3-Clause
"""kinctld against real LCM: setpoints, a goal's life, rejections, hostile
datagrams, shutdown, configuration. Fixtures and helpers: tests/pylib/kinctl_testing.py."""
import math
import os
import random
import signal
import struct
import time

import pytest

from kinctl_testing import (EVENTS, MODELS, STATES, command_t, goal_joint_t, goal_line_t, quat_norm, run_kinctld,
                            setpoint_t, unique_url)

PUMA_N = 6
TARGET = [0.3, -0.2, 0.4, 0.1, 0.2, -0.3]


def assert_consecutive(setpoints):
    cycles = [s.cycle for s in setpoints]
    gaps = [(a, b) for a, b in zip(cycles, cycles[1:]) if b != a + 1]
    assert not gaps, f"{len(gaps)} gaps in the cycle counter, first {gaps[:5]}"


def assert_period_steps(setpoints, period_us):
    """utime is the tick's deadline: consecutive setpoints are a whole number
    of periods apart (more than one where the machine stalled the cycle and
    deadlines were skipped; never a fraction: no drift)."""
    for a, b in zip(setpoints, setpoints[1:]):
        step = b.utime - a.utime
        k = round(step / period_us)
        assert k >= 1 and abs(step - k * period_us) <= 1, (a.cycle, step)


# ---- the setpoint stream ---------------------------------------------------

def test_setpoints_every_cycle(kinctld):
    d = kinctld()
    sps = d.bus.wait_setpoints(1000)
    assert_consecutive(sps)
    for s in sps:
        assert s.n == PUMA_N
        assert s.state == STATES["IDLE"] and s.goal_id == 0
        assert s.q[:PUMA_N] == (0.0,) * PUMA_N and s.qd[:PUMA_N] == (0.0,) * PUMA_N
        assert abs(quat_norm(s.orientation) - 1.0) < 1e-12
    assert_period_steps(sps, 1000)
    assert d.stop() == 0


def test_period_and_model_flags(kinctld):
    d = kinctld("--model", "panda", "--period-us", "2000")
    sps = d.bus.wait_setpoints(200)
    assert_consecutive(sps)
    assert sps[-1].n == 7
    assert_period_steps(sps, 2000)
    assert d.stop() == 0


def test_prefix(kinctld):
    d = kinctld(prefix="ARM2_")
    d.bus.send_goal_joint(5, TARGET)
    assert d.bus.wait_event(5, ["COMPLETED"]).event_goal_id == 5
    assert d.stop() == 0


def test_lcm_default_url_honoured(kinctld):
    url = unique_url()
    d = kinctld(url=url, url_flag=False, env={"LCM_DEFAULT_URL": url})
    assert d.bus.wait_setpoints(50)
    assert d.stop() == 0
    assert "LCM_DEFAULT_URL" in d.stderr


def test_stats(kinctld):
    d = kinctld()
    st = d.bus.wait_stats(lambda s: s.cycles > 500, timeout=5.0)
    assert st.period_ns == 1_000_000
    assert 0 <= st.latency_p50_ns <= st.latency_p99_ns <= st.latency_p999_ns <= st.latency_max_ns
    assert 0 < st.compute_p50_ns <= st.compute_p99_ns <= st.compute_max_ns
    assert st.msgs_out >= st.cycles - 10
    assert st.msgs_invalid == 0 and st.rejections == 0 and st.msgs_dropped == 0
    assert d.stop() == 0


# ---- goals -----------------------------------------------------------------

def test_joint_goal_completes(kinctld):
    d = kinctld()
    d.bus.send_goal_joint(42, TARGET)
    done = d.bus.wait_event(42, ["COMPLETED", "REJECTED", "ABORTED", "FAULT"])
    assert done.event == EVENTS["COMPLETED"], done.reason
    kinds = [s.event for s in d.bus.events(42)]
    assert kinds.index(EVENTS["ACCEPTED"]) < kinds.index(EVENTS["COMPLETED"])
    final = d.bus.wait_idle()
    for j in range(PUMA_N):
        assert abs(final.q[j] - TARGET[j]) <= 1e-9
        assert final.qd[j] == 0.0
    with d.bus.lock:
        sps = list(d.bus.setpoints)
    moving = [s for s in sps if s.goal_id == 42]
    assert moving and all(s.state == STATES["MOVING"] for s in moving)
    assert_consecutive(sps)
    # The status carries the measured state (the simulated plant: = commanded).
    st = d.bus.wait(lambda: [s for s in d.bus.statuses if s.event == 0 and s.state == STATES["IDLE"]
                              and s.cycle > final.cycle], 2.0, "a periodic status")[0]
    assert all(abs(st.q_measured[j] - TARGET[j]) <= 1e-9 for j in range(PUMA_N))
    assert d.stop() == 0


def test_queued_goals_run_in_order(kinctld):
    d = kinctld()
    second = [-0.2, 0.1, -0.3, 0.0, -0.1, 0.2]
    d.bus.send_goal_joint(1, TARGET)
    d.bus.send_goal_joint(2, second)
    d.bus.wait_event(2, ["COMPLETED"])
    c1 = d.bus.wait_event(1, ["COMPLETED"])
    c2 = d.bus.wait_event(2, ["COMPLETED"])
    assert c1.cycle < c2.cycle
    final = d.bus.wait_idle()
    assert all(abs(final.q[j] - second[j]) <= 1e-9 for j in range(PUMA_N))
    assert d.stop() == 0


@pytest.mark.parametrize("case, token", [
    ("joint_count", "joint_count"),
    ("nan", "bad_goal"),
    ("inf", "bad_goal"),
    ("outside_limits", "joint_limit"),
    ("scale_above_one", "bad_goal"),
    ("goal_id_zero", None),
])
def test_bad_goal_rejected(kinctld, case, token):
    d = kinctld()
    gid = 77
    if case == "joint_count":
        d.bus.send_goal_joint(gid, TARGET[:5])
    elif case == "nan":
        d.bus.send_goal_joint(gid, [0.1, float("nan"), 0, 0, 0, 0])
    elif case == "inf":
        d.bus.send_goal_joint(gid, [0.1, 0, 0, 0, float("inf"), 0])
    elif case == "outside_limits":
        d.bus.send_goal_joint(gid, [0.1, 0, 10.0, 0, 0, 0])
    elif case == "scale_above_one":
        d.bus.send_goal_joint(gid, TARGET, vel_scale=1.5)
    elif case == "goal_id_zero":
        gid = 0
        d.bus.send_goal_joint(0, TARGET)
    if token is None:
        # No id to answer: counted as invalid, no status about it.
        st = d.bus.wait_stats(lambda s: s.msgs_invalid == 1, timeout=5.0)
        assert st.rejections == 0
        assert not d.bus.events(0)
    else:
        rej = d.bus.wait_event(gid, ["REJECTED", "ACCEPTED"])
        assert rej.event == EVENTS["REJECTED"], "accepted a bad goal"
        assert rej.reason.startswith(token + ": "), rej.reason
        assert rej.code < 0
        if case == "outside_limits":
            assert "q[2]" in rej.reason and "joint 3" in rej.reason
        if case == "nan":
            assert "not finite" in rej.reason
        st = d.bus.wait_stats(lambda s: s.rejections >= 1, timeout=5.0)
        assert st.rejections == 1
    # The arm never moved, and the stream carried on.
    sps = d.bus.wait_setpoints(100)
    assert_consecutive(sps)
    assert all(s.state == STATES["IDLE"] and s.q[:PUMA_N] == (0.0,) * PUMA_N for s in sps)
    assert d.stop() == 0


def test_unreachable_line_rejected(kinctld):
    d = kinctld()
    g = goal_line_t()
    g.goal_id = 9
    g.position = [5.0, 0.0, 0.5]  # metres outside a 1 m arm
    g.orientation = [1.0, 0.0, 0.0, 0.0]
    d.bus.send("GOAL_LINE", g)
    rej = d.bus.wait_event(9, ["REJECTED", "ACCEPTED"], timeout=20.0)
    assert rej.event == EVENTS["REJECTED"]
    assert rej.code < 0 and rej.reason.split(":")[0] in ("unreachable", "plan", "tracking"), rej.reason
    assert d.stop() == 0


def test_non_unit_quaternion_rejected(kinctld):
    d = kinctld()
    g = goal_line_t()
    g.goal_id = 10
    g.position = [0.4, 0.1, 0.3]
    g.orientation = [1.0, 1.0, 0.0, 0.0]
    d.bus.send("GOAL_LINE", g)
    rej = d.bus.wait_event(10, ["REJECTED", "ACCEPTED"])
    assert rej.event == EVENTS["REJECTED"] and rej.reason.startswith("bad_goal: "), rej.reason
    assert "unit quaternion" in rej.reason
    assert d.stop() == 0


# ---- hostile datagrams -----------------------------------------------------

def test_bad_datagrams_counted_and_ignored(kinctld):
    d = kinctld()
    rnd = random.Random(5)
    g = goal_joint_t()
    g.goal_id = 31
    g.n = PUMA_N
    g.q = TARGET + [0.0] * 10
    valid = g.encode()
    hostile = [
        ("GOAL_JOINT", b""),                                       # empty
        ("GOAL_JOINT", b"\x01\x02\x03"),                           # shorter than a fingerprint
        ("GOAL_JOINT", bytes(rnd.randrange(256) for _ in range(200))),  # garbage
        ("GOAL_JOINT", valid[:-9]),                                # truncated (goal_id readable)
        ("GOAL_JOINT", valid + b"\x00" * 16),                      # oversized
        ("GOAL_JOINT", setpoint_t().encode()),                     # another type's fingerprint
        ("COMMAND", valid),                                        # a goal on the command channel
        ("GOAL_LINE", bytes(4096)),                                # zeros
        ("COMMAND", b"\xff" * 17),
    ]
    # A hostile count: n = -1 in an otherwise valid goal_joint_t.
    off = 8 + 8 + 8 + 1
    hostile.append(("GOAL_JOINT", valid[:off] + struct.pack(">i", -1) + valid[off + 4:]))
    # Big garbage, which LCM sends fragmented: the receiver's kernel filter
    # drops every fragment (daemon/lcm_rx.h), so it is never even read.
    unread = [("GOAL_PATH", bytes(rnd.randrange(256) for _ in range(70000)))]
    before = d.bus.wait_setpoints(10)
    for suffix, data in unread + hostile:
        d.bus.send_raw(suffix, data)
        time.sleep(0.005)
    st = d.bus.wait_stats(lambda s: s.msgs_invalid >= len(hostile), timeout=5.0)
    assert st.msgs_invalid == len(hostile)
    assert st.msgs_in == len(hostile)
    assert st.msgs_dropped == 0
    # The truncated goal names its goal_id: it is answered.
    rej = d.bus.wait_event(31, ["REJECTED"])
    assert rej.reason.startswith("bad_goal: truncated"), rej.reason
    after = d.bus.wait_setpoints(200)
    with d.bus.lock:
        sps = [s for s in d.bus.setpoints if s.cycle >= before[0].cycle]
    assert_consecutive(sps)
    assert all(s.state == STATES["IDLE"] and s.goal_id == 0 for s in after)
    # Still serving: a valid goal after all that completes.
    d.bus.send_goal_joint(32, TARGET)
    assert d.bus.wait_event(32, ["COMPLETED", "REJECTED"]).event == EVENTS["COMPLETED"]
    assert d.stop() == 0
    # Counted by reason (the summary on stderr at exit).
    assert "truncated 3" in d.stderr and "oversized 1" in d.stderr and "bad count 1" in d.stderr


# ---- commands and shutdown -------------------------------------------------

def test_stop_command_mid_motion(kinctld):
    d = kinctld()
    d.bus.send_goal_joint(50, [2.0, 0.5, -1.0, 1.0, 1.0, 2.0], vel_scale=0.3)
    d.bus.wait(lambda: any(s.goal_id == 50 for s in d.bus.setpoints[-5:]), 5.0, "motion")
    d.bus.wait_setpoints(200)
    d.bus.send_command("STOP")
    ab = d.bus.wait_event(50, ["ABORTED", "COMPLETED"])
    assert ab.event == EVENTS["ABORTED"]
    assert (ab.code, ab.reason) == (0, "stopped: a STOP command ended it"), (ab.code, ab.reason)
    final = d.bus.wait_idle()
    assert all(v == 0.0 for v in final.qd[:PUMA_N])
    assert d.stop() == 0


def test_sigterm_final_status_and_exit_0(kinctld):
    d = kinctld()
    d.bus.wait_setpoints(100)
    assert d.stop(signal.SIGTERM) == 0
    last = d.bus.wait(lambda: [s for s in d.bus.statuses if s.reason.startswith("shutdown: ")], 2.0,
                      "the final status")[-1]
    assert last.state == STATES["IDLE"] and "at rest" in last.reason


def test_sigint_mid_motion_stops_the_arm(kinctld):
    d = kinctld()
    d.bus.send_goal_joint(60, [2.0, 0.5, -1.0, 1.0, 1.0, 2.0], vel_scale=0.3)
    d.bus.wait(lambda: any(s.goal_id == 60 and s.state == STATES["MOVING"] for s in d.bus.setpoints[-5:]), 5.0,
               "motion")
    assert d.stop(signal.SIGINT) == 0
    ab = d.bus.wait_event(60, ["ABORTED"])
    assert ab.code < 0 and ab.reason == "shutdown: kinctld exiting: the arm stopped", (ab.code, ab.reason)
    final = d.bus.wait(lambda: [s for s in d.bus.statuses if s.reason.startswith("shutdown: ")], 2.0,
                       "the final status")[-1]
    assert final.state == STATES["IDLE"] and "at rest" in final.reason
    assert all(v == 0.0 for v in final.qd_measured[:PUMA_N])
    with d.bus.lock:
        sps = list(d.bus.setpoints)
    assert_consecutive(sps)
    assert sps[-1].state == STATES["IDLE"]


# ---- configuration ---------------------------------------------------------

def write(tmp_path, text, name="k.cfg"):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def test_help():
    r = run_kinctld("--help")
    assert r.returncode == 0
    assert "Example" in r.stdout and "--config" in r.stdout and "--no-rt" in r.stdout


def test_check_defaults():
    r = run_kinctld("--check", env={"LCM_DEFAULT_URL": ""})
    assert r.returncode == 0, r.stderr
    assert "robot puma560 (6 joints, built-in)" in r.stdout
    assert "period 1000 us" in r.stdout and "udpm://239.255.76.67:7667?ttl=0 (default)" in r.stdout


def test_check_model_file_and_controller_section(tmp_path):
    # The robot from a model file (included beside the file), the controller here.
    write(tmp_path, open(os.path.join(MODELS, "panda.cfg")).read(), "panda.cfg")
    cfg = write(tmp_path, '@include "panda.cfg"\n'
                'controller = { period_us = 500; prefix = "LAB."; queue_size = 100;\n'
                '  overrun = { missed_cycles = 20; action = "estop"; };\n'
                '  rt = { enable = false; }; plant = { lag_s = 0.01; };\n'
                '  cartesian = { speed = 0.1; jerk = 2.0; angular_jerk = 30.0; };\n'
                '  angles = "deg"; home = [0.0, 0.0, 0.0, -90.0, 0.0, 90.0, 0.0]; };\n')
    r = run_kinctld("--config", cfg, "--check")
    assert r.returncode == 0, r.stderr
    assert "robot panda (7 joints" in r.stdout and "period 500 us" in r.stdout
    assert "channels LAB.*" in r.stdout and "overrun policy estop" in r.stdout and "rt off" in r.stdout
    # Flags win over the file.
    r = run_kinctld("--config", cfg, "--check", "--period-us", "250", "--prefix", "X_", "--rt",
                    "--lcm-url", "udpm://239.255.77.1:7001?ttl=0")
    assert r.returncode == 0, r.stderr
    assert "period 250 us" in r.stdout and "channels X_*" in r.stdout and "rt on" in r.stdout
    assert "udpm://239.255.77.1:7001?ttl=0 (command line)" in r.stdout


@pytest.mark.parametrize("text, args, expect", [
    (None, ["--config", "/nonexistent/k.cfg"], "/nonexistent/k.cfg: cannot open"),
    ("controller = { period_us = 1000 ", [], "k.cfg:1: "),
    ("controller = {\n  perod_us = 1000;\n};\n", [], 'k.cfg:2: unknown key "perod_us" in controller'),
    ("controller = {\n  period_us = 10;\n};\n", [], "k.cfg:2: controller.period_us = 10 is outside 100 .. 100000"),
    ("controller = {\n  period_us = \"fast\";\n};\n", [], "k.cfg:2: controller.period_us must be a number"),
    ("controller = {\n  check_budget_ms = 0.5;\n};\n", [],
     "k.cfg:2: controller.check_budget_ms = 0.5 is outside 1 .. 600000"),
    ("controller = {\n  vel_scale = 0.0;\n};\n", [], "k.cfg:2: controller.vel_scale must be > 0"),
    ("controller = {\n  cartesian = { jerk = 0.0; };\n};\n", [], "k.cfg:2: controller.cartesian.jerk = 0 is outside"),
    ("controller = {\n  cartesian = { angular_jerk = -3.0; };\n};\n", [],
     "k.cfg:2: controller.cartesian.angular_jerk = -3 is outside"),
    ("controller = {\n  home = [0.0, 0.0];\n};\n", [], "k.cfg:2: controller.home has 2 values"),
    ("controller = {\n  home = [9.0, 0.0, 0.0, 0.0, 0.0, 0.0];\n};\n", [], "controller.home[0] is outside"),
    ("controller = {\n  prefix = \"A B\";\n};\n", [], "k.cfg:2: controller.prefix \"A B\" may hold only"),
    ("controller = {\n  overrun = { action = \"halt\"; };\n};\n", [], 'controller.overrun.action must be "stop"'),
    ("controller = {\n  lcm_url = \"nowhere\";\n};\n", [], "is not an LCM URL"),
    ("robots = {};\n", [], 'k.cfg:1: unknown key "robots" in the top level'),
    ("robot = { name = \"x\"; angles = \"rad\"; };\n", [], "robot has no chain"),
    (None, ["--period-us", "abc"], '--period-us "abc"'),
    (None, ["--period-us", "50"], '--period-us "50"'),
    (None, ["--model", "r2d2"], 'no such built-in model'),
    (None, ["--prefix", "a;b"], '--prefix "a;b" may hold only'),
    (None, ["--lcm-url", "239.255.76.67"], "is not an LCM URL"),
    (None, ["--bogus"], 'unknown option "--bogus"'),
    (None, ["--config"], "--config needs a value"),
    (None, ["stray"], 'unexpected argument "stray"'),
])
def test_bad_config_exit_2(tmp_path, text, args, expect):
    argv = list(args)
    if text is not None:
        argv = ["--config", write(tmp_path, text)] + argv
    extra = ["--no-rt"] + ([] if "--lcm-url" in args else ["--lcm-url", "udpm://239.255.77.250:7999?ttl=0"])
    r = run_kinctld(*(extra + argv))
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert expect in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr  # one clear line
    assert r.stdout == ""


def test_bad_config_moves_nothing(kinctld, tmp_path):
    """A bad file: exit 2 before any setpoint goes out."""
    url = unique_url()
    from kinctl_testing import Bus
    bus = Bus(url)
    try:
        r = run_kinctld("--config", write(tmp_path, "controller = { period_us = 1; };\n"), "--lcm-url", url,
                        "--no-rt")
        assert r.returncode == 2
        time.sleep(0.3)
        assert not bus.setpoints and not bus.statuses
    finally:
        bus.close()


def test_rt_flag_runs_or_warns(kinctld):
    """--rt: SCHED_FIFO, mlockall and affinity when permitted, else warnings;
    either way the daemon runs. (Skipped under sanitizers: mlockall of
    ASan's shadow memory is not what this tests.)"""
    if os.environ.get("KINCTLD_SANITIZED") == "1":
        pytest.skip("mlockall under AddressSanitizer")
    d = kinctld(rt=True)
    sps = d.bus.wait_setpoints(300)
    assert_consecutive(sps)
    assert d.stop() == 0
    assert "running (cycle" in d.stderr
    assert math.isfinite(sps[-1].q[0])
