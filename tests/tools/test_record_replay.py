# SPDX-License-Identifier: BSD-3-Clause
"""kinctl record / play / replay against a real kinctld over real LCM."""
import math
import os
import re
import signal
import subprocess
import sys
import time

import lcm
import pytest

from kinctl.local import unique_url
from kinctl_testing import EVENTS, SLOW, finished, run_kinctl, start_kinctld
from kinctl_msgs import goal_joint_t, goal_path_t, setpoint_t

QN = "0,45,-180,0,45,0"
DOWN = "0.7071068,0,0.7071068,0"


def start_record(d, path, *extra):
    env = dict(os.environ)
    env.pop("LCM_DEFAULT_URL", None)
    p = subprocess.Popen([sys.executable, "-m", "kinctl", "--lcm-url", d.url, "record", path] + list(extra),
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    line = p.stdout.readline()
    assert line.startswith("recording "), line + p.stderr.read()
    return p


def stop_record(p):
    p.send_signal(signal.SIGTERM)
    out, err = p.communicate(timeout=30 * SLOW)
    assert p.returncode == 0, err
    assert "none missing" in out, out
    return out


def events(path):
    log = lcm.EventLog(path, "r")
    try:
        return [(e.timestamp, e.channel, e.data) for e in log]
    finally:
        log.close()


def write_log(path, evs):
    log = lcm.EventLog(path, "w", overwrite=True)
    for t, ch, data in evs:
        log.write_event(t, ch, data)
    log.close()


def ok(r):
    assert r.returncode == 0, r.stdout + r.stderr
    return r


@pytest.fixture(scope="module")
def session(multicast, tmp_path_factory):
    """One recorded run of every goal kind, a stop and a servo stream (the
    daemon's setpoints and its inputs): the log and the daemon's URL."""
    path = str(tmp_path_factory.mktemp("rec") / "run.lcmlog")
    d = start_kinctld()
    logger = None
    try:
        # LCM's own lcm-logger beside kinctl record: the two logs must agree
        logger = subprocess.Popen([os.path.join(os.path.dirname(sys.executable), "lcm-logger"),
                                   "--lcm-url=" + d.url, "-c", "KINCTL_.*", "-f", path + ".lcm-logger"],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        rec = start_record(d, path)
        ok(run_kinctl(d, "--deg", "goal", "joint", "--q", QN, "--wait"))
        ok(run_kinctl(d, "goal", "line", "--to", "0.45,0.15,0.38," + DOWN, "--speed", "0.2", "--wait"))
        ok(run_kinctl(d, "goal", "arc", "--via", "0.45,0.2,0.43", "--to", "0.45,0.15,0.48," + DOWN, "--wait"))
        ok(run_kinctl(d, "goal", "path", "--space", "joint", "--method", "spline", "--id", "7001",
                      "--points", "0.2,0.9,-3,0.1,0.7,0.1;0.4,0.7,-2.9,0,0.9,0.2", "--wait"))
        # rejected by the daemon's checks before the cycle: never replayed
        r = run_kinctl(d, "goal", "joint", "--q", "0,10,0,0,0,0")
        assert r.returncode == 1 and "joint_limit" in r.stderr
        ok(run_kinctl(d, "goal", "joint", "--q", "1.0,0.5,-2.5,0.5,0.5,0.5", "--id", "7002"))
        time.sleep(0.3)
        ok(run_kinctl(d, "stop", "--wait"))
        ok(run_kinctl(d, "goal", "servo", "--twist", "0,0.05,0,0,0,0", "--duration", "0.4", "--replace", "--wait"))
        out = stop_record(rec)
    finally:
        if logger is not None:
            logger.send_signal(signal.SIGINT)
            logger.communicate(timeout=30)
        assert d.stop() == 0, d.stderr
    return path, out


def test_log_is_lcm_logger_compatible(session, multicast, tmp_path):
    """LCM's own tools and ours agree. lcm-logger, recording the same run,
    caught the same messages in the same order of each sender (it may lose
    some: seen here, 40 setpoints while the clients started, when kinctl
    record lost none). Across senders the two may differ: two datagrams
    looped back from two processes at once are handed to the two
    receivers' sockets by two CPUs, each socket in turn (seen once, two
    neighbours 9,000 messages in). Our log
    played by lcm-logplayer and recorded again by kinctl record comes back
    identical."""
    path, _ = session
    ours = [(ch, d) for _, ch, d in events(path)]
    theirs = [(ch, d) for _, ch, d in events(path + ".lcm-logger")]
    pos = {m: i for i, m in enumerate(ours)}
    assert sum(m in pos for m in theirs) > len(ours) // 2

    def sender(ch):  # the clients' channels, or kinctld's own
        return ch.startswith("KINCTL_GOAL_") or ch == "KINCTL_COMMAND"

    for client in (False, True):
        in_ours = [pos[m] for m in theirs if m in pos and sender(m[0]) == client]
        assert len(in_ours) > 10
        assert in_ours == sorted(in_ours)  # the same order

    url = unique_url(subnet=79)
    env = dict(os.environ)
    env.pop("LCM_DEFAULT_URL", None)
    again = str(tmp_path / "again.lcmlog")
    rec = subprocess.Popen([sys.executable, "-m", "kinctl", "--lcm-url", url, "record", again],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    assert rec.stdout.readline().startswith("recording ")
    r = subprocess.run([os.path.join(os.path.dirname(sys.executable), "lcm-logplayer"), "--lcm-url=" + url,
                        "--speed=4", path], capture_output=True, text=True, timeout=120 * SLOW)
    assert r.returncode == 0, r.stderr
    time.sleep(0.5)
    stop_record(rec)
    assert [(ch, d) for _, ch, d in events(again)] == ours


def test_record_writes_every_channel_with_every_setpoint(session):
    path, out = session
    evs = events(path)
    channels = {ch for _, ch, _ in evs}
    assert {"KINCTL_SETPOINT", "KINCTL_STATUS", "KINCTL_GOAL_JOINT", "KINCTL_GOAL_LINE", "KINCTL_GOAL_ARC",
            "KINCTL_GOAL_PATH", "KINCTL_GOAL_SERVO", "KINCTL_COMMAND"} <= channels
    sps = [setpoint_t.decode(data) for _, ch, data in evs if ch == "KINCTL_SETPOINT"]
    cycles = [s.cycle for s in sps]
    assert cycles == list(range(cycles[0], cycles[0] + len(cycles)))
    # the inputs on the wire: every goal sent, the stop, the servo stream's staleness
    taken = {s.input_goal_id for s in sps if s.input_goal_id}
    assert {7001, 7002} <= taken
    assert [s.input_command for s in sps if s.input_command] == [1]
    assert any(s.input_servo_stale for s in sps)
    rejected = goal_joint_t.decode(next(d for _, ch, d in evs if ch == "KINCTL_GOAL_JOINT"
                                        and goal_joint_t.decode(d).q[1] == 10.0))
    assert rejected.goal_id not in taken
    assert f"{len(evs)} events" in out


def test_replay_is_bit_exact(session, kinctl):
    path, _ = session
    r = kinctl(None, "replay", path)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "BIT-EXACT" in r.stdout
    n = sum(1 for _, ch, _ in events(path) if ch == "KINCTL_SETPOINT")
    # every setpoint after the first one at rest (the log starts idle)
    assert f"BIT-EXACT: {n - 1} setpoints" in r.stdout, r.stdout


@pytest.mark.parametrize("channel, cls, gid", [("KINCTL_GOAL_PATH", goal_path_t, 7001),
                                               ("KINCTL_GOAL_JOINT", goal_joint_t, 7002)])
def test_replay_reports_an_altered_goal_at_its_cycle(session, kinctl, tmp_path, channel, cls, gid):
    path, _ = session
    evs = events(path)
    altered = []
    for t, ch, data in evs:
        if ch == channel and cls.decode(data).goal_id == gid:
            m = cls.decode(data)
            if cls is goal_path_t:
                m.points = [list(p) for p in m.points]
                m.points[1][0] += 1e-9
            else:
                m.q = list(m.q)
                m.q[0] += 1e-9
            data = m.encode()
        altered.append((t, ch, data))
    assert altered != evs
    bad = str(tmp_path / "altered.lcmlog")
    write_log(bad, altered)
    # the cycle that took the goal, from the log itself
    took = [setpoint_t.decode(d).cycle for _, ch, d in evs
            if ch == "KINCTL_SETPOINT" and setpoint_t.decode(d).input_goal_id == gid]
    assert len(took) == 1
    r = kinctl(None, "replay", bad)
    assert r.returncode == 1, r.stdout + r.stderr
    assert f"DIFFERS at cycle {took[0]}:" in r.stdout, r.stdout


def test_replay_reports_a_lost_setpoint(session, kinctl, tmp_path):
    path, _ = session
    evs = events(path)
    sp = [i for i, (_, ch, _) in enumerate(evs) if ch == "KINCTL_SETPOINT"]
    lost = setpoint_t.decode(evs[sp[500]][2]).cycle
    write_log(str(tmp_path / "gap.lcmlog"), evs[:sp[500]] + evs[sp[500] + 1:])
    r = kinctl(None, "replay", str(tmp_path / "gap.lcmlog"))
    assert r.returncode == 1
    assert f"no setpoint for cycles {lost} .. {lost}" in r.stdout, r.stdout
    assert f"bit-exact through cycle {lost - 1}" in r.stdout


def test_play_round_trip(session, multicast, tmp_path):
    """Played into a bus of its own at 4x and recorded again: the same
    events in the same order, spaced a quarter as far apart at least."""
    path, _ = session
    url = unique_url(subnet=79)
    env = dict(os.environ)
    env.pop("LCM_DEFAULT_URL", None)
    again = str(tmp_path / "again.lcmlog")

    rec = subprocess.Popen([sys.executable, "-m", "kinctl", "--lcm-url", url, "record", again],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    assert rec.stdout.readline().startswith("recording ")
    evs = events(path)
    span = (evs[-1][0] - evs[0][0]) / 1e6
    t0 = time.monotonic()
    r = subprocess.run([sys.executable, "-m", "kinctl", "--lcm-url", url, "play", path, "--speed", "4"],
                       capture_output=True, text=True, env=env, timeout=120 * SLOW)
    took = time.monotonic() - t0
    assert r.returncode == 0, r.stderr
    assert f"play: {len(evs)} events" in r.stdout
    assert took >= span / 4
    time.sleep(0.5)
    out = stop_record(rec)
    got = events(again)
    assert [(ch, d) for _, ch, d in got] == [(ch, d) for _, ch, d in evs], out
    # the played log replays as the original does
    r = run_kinctl(None, "replay", again)
    assert r.returncode == 0 and "BIT-EXACT" in r.stdout, r.stdout + r.stderr


def test_play_inputs_only_drives_a_daemon(session, daemon, kinctl, tmp_path):
    """The recorded goals and commands, played to a fresh daemon, move it
    through the same goals (the goal ids of its setpoints)."""
    path, _ = session
    d = daemon()
    log = str(tmp_path / "driven.lcmlog")
    rec = start_record(d, log)
    r = kinctl(d, "play", path, "--inputs-only")
    assert r.returncode == 0, r.stderr
    time.sleep(1.0 * SLOW)
    stop_record(rec)
    ids = {setpoint_t.decode(dt).goal_id for _, ch, dt in events(log) if ch == "KINCTL_SETPOINT"}
    assert {7001, 7002} <= ids


@pytest.mark.parametrize("args, text", [
    (["replay", "/nonexistent.lcmlog"], "no such file"),
    (["play", "/nonexistent.lcmlog"], "no such file"),
    (["replay", "__FILE__"], "not an LCM event log"),
    (["play", "x.lcmlog", "--speed", "0"], "must be > 0"),
    (["replay", "__LOG__", "--model", "nosuch"], "no such built-in model"),
    (["replay", "__LOG__", "--model", "panda"], "the arm (panda) has 7"),
    (["replay", "__LOG__", "--prefix", "OTHER_"], "no OTHER_SETPOINT messages"),
    (["play", "__LOG__", "--channels", "("], "--channels '('"),
    (["play", "__LOG__", "--channels", "X", "--inputs-only"], "not both"),
    (["record", "/nonexistent/dir/x.lcmlog"], "no directory /nonexistent/dir"),
    (["spy", "--jar", "/nonexistent.jar"], "--jar /nonexistent.jar: no such file"),
])
def test_bad_input_exits_2(session, kinctl, args, text):
    path, _ = session
    args = [path if a == "__LOG__" else __file__ if a == "__FILE__" else a for a in args]
    r = kinctl(None, *args)
    assert r.returncode == 2, r.stdout + r.stderr
    assert text in r.stderr, r.stderr


def test_record_refuses_to_overwrite(kinctl, tmp_path):
    p = tmp_path / "x.lcmlog"
    p.write_bytes(b"")
    r = kinctl(None, "record", str(p), "--duration", "0.1")
    assert r.returncode == 2 and "--force" in r.stderr


def test_replay_takes_the_daemons_configuration(multicast, tmp_path):
    """A panda at 2 kHz replays bit for bit with the daemon's --model and
    --period-us; with another period it differs from the first goal's cycle."""
    path = str(tmp_path / "panda.lcmlog")
    d = start_kinctld("--model", "panda", "--period-us", "500")
    try:
        rec = start_record(d, path)
        ok(run_kinctl(d, "goal", "joint", "--q", "0.3,-0.5,0.2,-2.0,0.1,1.8,0.5", "--id", "8001", "--wait"))
        ok(run_kinctl(d, "status"))
        stop_record(rec)
    finally:
        assert d.stop() == 0, d.stderr
    r = run_kinctl(None, "replay", path, "--model", "panda", "--period-us", "500")
    assert r.returncode == 0 and "BIT-EXACT" in r.stdout, r.stdout + r.stderr
    took = [setpoint_t.decode(dt).cycle for _, ch, dt in events(path)
            if ch == "KINCTL_SETPOINT" and setpoint_t.decode(dt).input_goal_id == 8001]
    r = run_kinctl(None, "replay", path, "--model", "panda", "--period-us", "1000")
    assert r.returncode == 1 and f"DIFFERS at cycle {took[0]}:" in r.stdout, r.stdout + r.stderr


def test_replay_of_goals_the_dry_run_changed(multicast, tmp_path, kinctl):
    """A fast line from rest and one replacing a moving joint move, whose
    joints' jerk the dry run finds beyond their limits: kinctld slows each
    (and may stop the move first), and the setpoints that took them say
    so (input_goal_share < 1, input_goal_stop_first, input_goal_qu). The
    log replays bit for bit; with the first line's share put back to 1
    it differs from that line's first ticks on."""
    path = str(tmp_path / "slowed.lcmlog")
    d = start_kinctld()
    fast = ["--speed", "0.5", "--accel", "3", "--jerk", "200"]
    try:
        rec = start_record(d, path)
        ok(run_kinctl(d, "--deg", "goal", "joint", "--q", QN, "--wait"))
        ok(run_kinctl(d, "goal", "line", "--to", "0.45,0.15,0.38," + DOWN, "--id", "9001", "--wait", *fast))
        ok(run_kinctl(d, "--deg", "goal", "joint", "--q", QN, "--wait"))
        ok(run_kinctl(d, "--deg", "goal", "joint", "--q", "30,30,-160,20,60,10", "--id", "9002"))
        time.sleep(0.4)
        ok(run_kinctl(d, "goal", "line", "--to", "0.45,0.15,0.38," + DOWN, "--id", "9003", "--replace", "--wait",
                      *fast))
        stop_record(rec)
    finally:
        assert d.stop() == 0, d.stderr
    assert "goal 9001 slowed to" in d.stderr and "goal 9003 slowed to" in d.stderr, d.stderr
    evs = events(path)
    took = {s.input_goal_id: s for s in (setpoint_t.decode(dt) for _, ch, dt in evs if ch == "KINCTL_SETPOINT")
            if s.input_goal_id}
    assert {9001, 9002, 9003} <= set(took)
    assert 0.0 < took[9001].input_goal_share < 1.0 and 0.0 < took[9003].input_goal_share < 1.0
    assert took[9002].input_goal_share == 1.0 and took[9001].input_goal_qu > 0.0
    r = kinctl(None, "replay", path)
    assert r.returncode == 0 and "BIT-EXACT" in r.stdout, r.stdout + r.stderr

    as_asked = []
    for t, ch, data in evs:
        if ch == "KINCTL_SETPOINT" and setpoint_t.decode(data).input_goal_id == 9001:
            s = setpoint_t.decode(data)
            s.input_goal_share = 1.0
            data = s.encode()
        as_asked.append((t, ch, data))
    bad = str(tmp_path / "as_asked.lcmlog")
    write_log(bad, as_asked)
    r = kinctl(None, "replay", bad)
    differs = re.search(r"DIFFERS at cycle (\d+):", r.stdout)
    assert r.returncode == 1 and differs, r.stdout + r.stderr
    # from the line's first ticks (their motion the jerk's alone, a few units in the last place)
    assert took[9001].cycle <= int(differs[1]) <= took[9001].cycle + 2, r.stdout
    assert "active goal logged 9001" in r.stdout, r.stdout


def test_replay_of_a_goal_refused_late(multicast, tmp_path, kinctld, kinctl):
    """A replacing goal judged from the moving state is taken only in the
    tick and from the state it was judged for: a PAUSE sent just after it
    reaches the controller first, and the step refuses the goal (REJECTED,
    late), the move pausing. The setpoint of that tick says what schedule
    the goal came with (input_goal_scheduled, input_goal_take_ahead,
    input_goal_take_state); the log replays bit for bit, and with the
    schedule left out the replay takes the goal and differs from that tick
    on."""
    path = str(tmp_path / "late.lcmlog")
    d = kinctld()
    rad = math.pi / 180.0
    home = [float(x) * rad for x in QN.split(",")]
    far = [x * rad for x in (30, 30, -160, 20, 60, 10)]
    other = [x * rad for x in (-20, 40, -170, -10, 50, -20)]
    rec = start_record(d, path)
    late = None
    try:
        for i in range(12):
            base = 9100 + 10 * i
            d.bus.send_goal_joint(base, home)
            finished(d, base)
            d.bus.send_goal_joint(base + 1, far)
            d.bus.wait_event(base + 1, ["STARTED"])
            time.sleep(0.2)
            d.bus.send_goal_joint(base + 2, other, replace=True)
            time.sleep(0.001 * (i % 4))  # after the dry run's snapshot, before the goal's tick
            d.bus.send_command("PAUSE")
            st = d.bus.wait_event(base + 2, ["ACCEPTED", "REJECTED"])
            d.bus.send_command("STOP")
            d.bus.wait_idle()
            if st.event == EVENTS["REJECTED"]:
                assert st.reason.startswith("late"), st.reason
                late = base + 2
                break
        stop_record(rec)
    finally:
        assert d.stop() == 0, d.stderr
    assert late is not None, "no replacing goal was refused as late in 12 tries"
    evs = events(path)
    sp = [s for s in (setpoint_t.decode(dt) for _, ch, dt in evs if ch == "KINCTL_SETPOINT") if s.input_goal_id == late]
    assert len(sp) == 1 and sp[0].input_goal_scheduled == 1 and sp[0].goal_id != late, sp
    r = kinctl(None, "replay", path)
    assert r.returncode == 0 and "BIT-EXACT" in r.stdout, r.stdout + r.stderr

    unscheduled = []
    for t, ch, data in evs:
        if ch == "KINCTL_SETPOINT" and setpoint_t.decode(data).input_goal_id == late:
            s = setpoint_t.decode(data)
            s.input_goal_scheduled, s.input_goal_take_ahead, s.input_goal_take_state = 0, 0, 0
            data = s.encode()
        unscheduled.append((t, ch, data))
    bad = str(tmp_path / "unscheduled.lcmlog")
    write_log(bad, unscheduled)
    r = kinctl(None, "replay", bad)
    assert r.returncode == 1 and f"DIFFERS at cycle {sp[0].cycle}:" in r.stdout, r.stdout + r.stderr
