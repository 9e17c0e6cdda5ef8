# SPDX-License-Identifier: BSD-3-Clause
"""kinctld's CAN output on a real SocketCAN interface (vcan0), with the
simulated drives attached: frames against the LCM setpoints, feedback, and
each failure's reaction. See conftest.py for the fixtures and checks."""
import json
import os
import re
import socket
import struct
import subprocess
import sys
import time

import pytest

from conftest import (EVENTS, IFACE, MASTER, NODES, PERIOD_US, SCALING, SLOW, STATES, align,
                      assert_setpoints_unbroken, bus_cycles, counts_to_q, pos_counts, segments, vel_counts, wait_fault,
                      wait_status)
from kinctl import dbc

Q_HOME = [0.0, 0.7854, -3.1416, 0.0, 0.7854, 0.0]
Q_A = [0.3, 0.5, -2.8, 0.4, 0.6, -0.5]


def test_frames_are_the_setpoints(can_daemon, drives, recorder):
    """Every frame decodes with the DBC and is the LCM setpoint of its cycle
    to the count; one SYNC per cycle, none missing or reordered."""
    drives()
    d = can_daemon()
    d.bus.send_goal_joint(11, Q_A, vel_scale=0.5, acc_scale=0.5)
    st = d.bus.wait_event(11, ["COMPLETED", "REJECTED", "ABORTED"], timeout=30)
    if st.event != EVENTS["COMPLETED"]:
        d.stop()
        raise AssertionError(f"goal 11 ended with event {st.event}: {st.reason}; kinctld: {d.stderr}")
    d.bus.wait_setpoints(50)
    assert d.stop() == 0
    frames = recorder.snapshot()
    db = dbc.load()
    for t, cid, data in frames:
        msg = db.get_message_by_frame_id(cid)
        assert len(data) == msg.length
        msg.decode(data)
    cycles = bus_cycles(frames)
    with d.bus.lock:
        setpoints = list(d.bus.setpoints)
    assert_setpoints_unbroken(setpoints)
    matched = align(cycles, setpoints)
    moving = [k for k in matched if any(abs(x) > 0 for x in next(sp for sp in setpoints if sp.cycle == k).qd[:6])]
    assert len(moving) > 100, "the goal's motion went out on CAN"
    # One SYNC per cycle: as many SYNCs on the bus as cycles the daemon ran
    # (its own count, in its exit line) and setpoints on LCM, and every one
    # of them matched above.
    ran = int(re.search(r"kinctld: (\d+) cycles", d.stderr).group(1))
    syncs = [f for f in frames if f[1] == 0x080]
    assert len(syncs) == ran == len(setpoints)
    assert len(matched) == ran and matched == [sp.cycle for sp in setpoints]
    hb = [f for f in frames if f[1] == 0x700 + MASTER]
    assert hb and all(f[2] == b"\x05" for f in hb)


def statuses(d):
    with d.bus.lock:
        return list(d.bus.statuses)


def setpoints_of(d):
    with d.bus.lock:
        return list(d.bus.setpoints)


def test_feedback_closes_the_loop(can_daemon, drives, recorder):
    """With a lagging drive, status_t's measured joints are the drives'
    positions from their TPDOs (to the count), behind the setpoint while
    moving and on it at rest; without feedback they would equal it."""
    drives("--lag", "0.1")
    d = can_daemon(following_error=1.0)
    d.bus.send_goal_joint(21, Q_A, vel_scale=0.5, acc_scale=0.5)
    st = d.bus.wait_event(21, ["COMPLETED", "REJECTED", "ABORTED"], timeout=30)
    assert st.event == EVENTS["COMPLETED"], st.reason
    time.sleep(1.5 * SLOW)  # the lag settles (10 time constants)
    final = d.bus.wait(lambda: [s for s in d.bus.statuses if s.event == 0][-1:], what="a periodic status")[0]
    assert d.stop() == 0
    tpdo = {n: {struct.unpack("<i", data[:4])[0] for t, cid, data in recorder.snapshot() if cid == 0x180 + n}
            for n in NODES}
    moving = [s for s in statuses(d) if s.state == STATES["MOVING"]]
    assert moving, "statuses while moving"
    sp = {p.cycle: p for p in setpoints_of(d)}
    lagging = 0
    for s in moving + [final]:
        for j, n in enumerate(NODES):
            counts = pos_counts(j, s.q_measured[j])
            # Exactly a position some TPDO of this drive reported.
            assert counts in tpdo[n], f"status q_measured[{j}] = {s.q_measured[j]} is no TPDO position of node {n}"
            assert abs(counts_to_q(j, counts) - s.q_measured[j]) < 1e-9
        if s.cycle in sp and abs(s.q_measured[2] - sp[s.cycle].q[2]) > 0.01:
            lagging += 1
    assert lagging >= len(moving) // 2, "the measured joints lag the setpoint while moving (the drive's lag)"
    for j in range(6):
        assert abs(final.q_measured[j] - Q_A[j]) < 2.0 / SCALING[j][0], f"joint {j + 1} at rest on its target"


def wait_moving(d):
    """Until the arm is well under way (a joint faster than 0.05 rad/s)."""
    d.bus.wait(lambda: any(s.state == STATES["MOVING"] and max(abs(v) for v in s.qd[:6]) > 0.05
                           for s in d.bus.setpoints[-5:]), what="motion")


def run_to_fault(d, drives_cmd, token, sim, goal_id=31):
    """Starts a goal, applies the drive command, waits for the FAULT with
    reason token; returns the fault status."""
    d.bus.send_goal_joint(goal_id, Q_A, vel_scale=0.5, acc_scale=0.5)
    wait_moving(d)
    if drives_cmd:
        sim.command(drives_cmd)
    return wait_fault(d.bus, token, timeout=15)


def assert_stopped_in_fault(d, goal_id):
    ab = d.bus.wait_event(goal_id, ["ABORTED", "COMPLETED"])
    assert ab.event == EVENTS["ABORTED"]
    d.bus.wait(lambda: d.bus.setpoints[-1].state == STATES["FAULT"], timeout=10, what="state FAULT")
    last = d.bus.last_setpoint()
    assert all(v == 0.0 for v in last.qd[:6]), "at rest"


def test_drive_fault(can_daemon, drives, recorder):
    """Statusword bit 3: FAULT naming the joint and node, the arm stopped,
    goals refused until the drive is cleared and the daemon RESET."""
    sim = drives()
    d = can_daemon()
    st = run_to_fault(d, "fault 3", "drive: joint 3 (node 3) reports a fault", sim)
    assert "statusword 0x0208" in st.reason and st.code < 0
    assert_stopped_in_fault(d, 31)
    sim.command("clear 3")
    time.sleep(0.3 * SLOW)
    d.bus.send_command("RESET")
    d.bus.wait(lambda: d.bus.setpoints[-1].state == STATES["IDLE"], what="IDLE after RESET")
    d.bus.send_goal_joint(32, Q_HOME[:1] + Q_A[1:], vel_scale=0.5, acc_scale=0.5)
    assert d.bus.wait_event(32, ["COMPLETED", "ABORTED", "REJECTED"], timeout=30).event == EVENTS["COMPLETED"]
    assert d.stop() == 0
    assert_setpoints_unbroken(setpoints_of(d))


def test_drive_fault_persisting_after_reset(can_daemon, drives, recorder):
    """A drive still faulted when the daemon is RESET faults it again."""
    sim = drives()
    d = can_daemon()
    run_to_fault(d, "fault 2", "drive: joint 2 (node 2) reports a fault", sim, goal_id=35)
    d.bus.wait(lambda: d.bus.setpoints[-1].state == STATES["FAULT"], timeout=10, what="state FAULT")
    n_faults = len([s for s in statuses(d) if s.event == EVENTS["FAULT"]])
    d.bus.send_command("RESET")
    d.bus.wait(lambda: len([s for s in d.bus.statuses if s.event == EVENTS["FAULT"]]) > n_faults, timeout=10,
               what="a second FAULT")
    assert d.stop() == 0
    assert_setpoints_unbroken(setpoints_of(d))


def test_silent_drive(can_daemon, drives, recorder):
    """No heartbeat from a drive for drive_timeout_ms: FAULT, stopped."""
    sim = drives()
    d = can_daemon(drive_timeout_ms=600.0)
    st = run_to_fault(d, "silent 4", "drive: joint 4 (node 4) is silent: no heartbeat for", sim, goal_id=41)
    assert "drive_timeout_ms 600" in st.reason
    assert_stopped_in_fault(d, 41)
    assert d.stop() == 0
    assert_setpoints_unbroken(setpoints_of(d))


def test_following_error(can_daemon, drives, recorder):
    """A drive that cannot keep up (speed-limited) trips the daemon's own
    following-error bound."""
    sim = drives()
    d = can_daemon(following_error=0.1)
    st = run_to_fault(d, "vmax 3 500", "drive: joint 3 (node 3) following error", sim, goal_id=51)
    err = float(re.search(r"following error ([0-9.e+-]+) beyond 0.1", st.reason).group(1))
    assert err > 0.1
    assert_stopped_in_fault(d, 51)
    assert d.stop() == 0
    assert_setpoints_unbroken(setpoints_of(d))


def ip_link(state):
    subprocess.run(["ip", "link", "set", IFACE, state], check=True)


@pytest.fixture
def link_restored(vcan):
    yield
    subprocess.run(["ip", "link", "set", IFACE, "up"], check=False)


def test_interface_down_and_up_stop(can_daemon, drives, recorder, link_restored):
    """on_error = stop: the interface down faults the arm with a can: reason,
    counted in stats; back up, the output resumes with the current cycle's
    setpoints only (nothing stale), and LCM never stopped."""
    sim = drives()
    d = can_daemon(on_error="stop", drive_timeout_ms=0.0)
    d.bus.send_goal_joint(61, Q_A, vel_scale=0.5, acc_scale=0.5)
    wait_moving(d)
    ip_link("down")
    st = wait_fault(d.bus, "can: vcan0 is down")
    wait_status(d.bus, lambda s: s.can_state == 2, what="a status with can_state LOST")
    assert "CAN output lost" in st.reason
    assert_stopped_in_fault(d, 61)
    stats = d.bus.wait_stats(lambda s: s.can_link_down >= 1 and s.can_state == 2, timeout=5)
    assert stats.can_errors >= 1 and stats.can_tx_dropped >= 1
    cli = subprocess.run([sys.executable, "-m", "kinctl", "--lcm-url", d.url, "status", "--json"],
                         capture_output=True, text=True, timeout=30)
    assert cli.returncode == 0, cli.stderr
    assert json.loads(cli.stdout)["can"] == "lost" and json.loads(cli.stdout)["state"] == "FAULT"
    time.sleep(0.5 * SLOW)
    with d.bus.lock:
        last_before_up = d.bus.setpoints[-1].cycle
    ip_link("up")
    wait_status(d.bus, lambda s: s.reason.startswith("can: vcan0 is back"), what="the output back")
    d.bus.wait(lambda: d.bus.statuses[-1].can_state == 1, what="can_state OK")
    d.bus.wait_setpoints(30)
    assert d.stop() == 0
    # Two runs of bus cycles, each its cycles' setpoints: before the loss,
    # and after the recovery starting with a cycle computed after it.
    runs = segments(bus_cycles(recorder.snapshot()))
    assert len(runs) == 2, f"{len(runs)} runs of consecutive SYNCs, expected 2 (before and after the loss)"
    before = align(runs[0], setpoints_of(d))
    after = align(runs[1], setpoints_of(d), not_before=before[-1] + 1)
    assert after[0] > last_before_up, \
        f"the first bus cycle after recovery is cycle {after[0]}, computed before it (cycle {last_before_up})"
    assert after[0] - before[-1] > 10, "a gap while the interface was down"
    assert_setpoints_unbroken(setpoints_of(d))


def test_interface_down_and_up_lcm_only(can_daemon, drives, recorder, link_restored):
    """on_error = lcm_only: the goal goes on over LCM while the bus is
    down; the loss and the recovery are reported, no fault."""
    drives()
    d = can_daemon(on_error="lcm_only", drive_timeout_ms=0.0)
    d.bus.send_goal_joint(71, Q_A, vel_scale=0.5, acc_scale=0.5)
    wait_moving(d)
    ip_link("down")
    wait_status(d.bus, lambda s: s.reason.startswith("can: vcan0 is down") and "lcm_only" in s.reason,
                what="the loss reported")
    time.sleep(0.3 * SLOW)
    ip_link("up")
    wait_status(d.bus, lambda s: s.reason.startswith("can: vcan0 is back"), what="the output back")
    st = d.bus.wait_event(71, ["COMPLETED", "ABORTED"], timeout=30)
    assert st.event == EVENTS["COMPLETED"], st.reason
    assert not [s for s in statuses(d) if s.event == EVENTS["FAULT"]]
    assert d.stop() == 0
    assert_setpoints_unbroken(setpoints_of(d))


def test_flood_of_foreign_frames(can_daemon, drives, recorder):
    """cangen floods the bus with frames of other ids: the daemon filters
    them in the kernel, the goal completes, every frame of the daemon still
    matches its setpoint, no fault. (cangen runs niced, with a drive timeout
    of 5 s: inside UML the flood otherwise takes the one CPU from the
    Python drive simulator, whose heartbeats then stop.)"""
    drives()
    d = can_daemon(drive_timeout_ms=5000.0)
    flood = subprocess.Popen(["nice", "-n", "19", "cangen", IFACE, "-g", "0.1", "-I", "7E5", "-L", "8", "-D", "r",
                              "-n", "20000"])
    try:
        d.bus.send_goal_joint(81, Q_A, vel_scale=0.5, acc_scale=0.5)
        st = d.bus.wait_event(81, ["COMPLETED", "ABORTED"], timeout=60)
        assert st.event == EVENTS["COMPLETED"], st.reason
    finally:
        flood.wait(60)
    assert d.stop() == 0
    frames = recorder.snapshot()
    foreign = [f for f in frames if f[1] == 0x7E5]
    assert len(foreign) > 1000, "the flood reached the bus"
    assert align(bus_cycles(frames), setpoints_of(d))
    assert not [s for s in statuses(d) if s.event == EVENTS["FAULT"]]
    assert_setpoints_unbroken(setpoints_of(d))


def test_candump_sees_the_same_frames(can_daemon, drives, recorder, tmp_path):
    """candump (its receive buffer sized with -r) logs exactly the frames the
    recorder saw, and kinctl candecode decodes every one with the DBC."""
    drives()
    log = tmp_path / "candump.log"
    with open(log, "w") as f:
        dump = subprocess.Popen(["candump", "-L", "-r", str(8 << 20), IFACE], stdout=f)
    try:
        time.sleep(0.3 * SLOW)
        d = can_daemon()
        live = subprocess.run([sys.executable, "-m", "kinctl", "candecode", "--interface", IFACE, "--count", "40",
                               "--json", "--strict", "--duration", str(20 * SLOW)], capture_output=True, text=True)
        assert live.returncode == 0, live.stderr
        names = {json.loads(line)["name"] for line in live.stdout.splitlines()}
        assert {"SYNC", "RPDO1_Node1", "RPDO1_Node6", "TPDO1_Node1"} <= names, names
        d.bus.send_goal_joint(91, Q_A, vel_scale=0.5, acc_scale=0.5)
        assert d.bus.wait_event(91, ["COMPLETED", "ABORTED"], timeout=30).event == EVENTS["COMPLETED"]
        assert d.stop() == 0
        time.sleep(0.3 * SLOW)
    finally:
        dump.terminate()
        dump.wait(5)
    dumped = [l for l in log.read_text().splitlines() if l.strip()]
    ours = {0x080, 0x700 + MASTER} | {0x200 + n for n in NODES}
    seen = [(cid, data) for t, cid, data in recorder.snapshot() if cid in ours]
    logged = []
    for line in dumped:
        _, iface, frame = line.split()
        cid, data = frame.split("#")
        if int(cid, 16) in ours:
            logged.append((int(cid, 16), bytes.fromhex(data)))
    # The recorder started before candump and stopped after it: candump's
    # frames are a contiguous run of the recorder's.
    assert len(logged) > 100
    start = next(i for i in range(len(seen)) if seen[i:i + len(logged)] == logged)
    assert start is not None
    r = subprocess.run([sys.executable, "-m", "kinctl", "candecode", "--strict", "--json", str(log)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    decoded = [json.loads(l) for l in r.stdout.splitlines()]
    assert len(decoded) == len(dumped)
    rpdo = next(x for x in decoded if x["id"] == 0x201)
    assert set(rpdo["signals"]) == {"TargetPosition_607A", "VelocityOffset_60B1"}


def test_bus_off_error_frame(can_daemon, drives, recorder):
    """A bus-off error frame (injected: vcan passes a raw socket's error
    frames to the sockets that ask for them) is counted and loses the output
    under on_error = stop: FAULT with a can: reason; the interface being up,
    the output comes back with fresh setpoints only."""
    drives()
    d = can_daemon(on_error="stop", drive_timeout_ms=0.0)
    d.bus.send_goal_joint(65, Q_A, vel_scale=0.5, acc_scale=0.5)
    wait_moving(d)
    s = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
    s.bind((IFACE,))
    with d.bus.lock:
        cycle_at_bus_off = d.bus.setpoints[-1].cycle
    s.send(struct.pack("=IB3x8s", 0x20000000 | 0x40, 8, bytes(8)))  # CAN_ERR_FLAG | CAN_ERR_BUSOFF
    s.close()
    st = wait_fault(d.bus, "can: vcan0 is bus-off")
    assert "CAN output lost" in st.reason
    assert_stopped_in_fault(d, 65)
    wait_status(d.bus, lambda s: s.reason.startswith("can: vcan0 is back"), what="the output back")
    stats = d.bus.wait_stats(lambda s: s.can_bus_off == 1 and s.can_state == 1, timeout=5)
    assert stats.can_error_frames == 1 and stats.can_errors >= 1
    d.bus.wait_setpoints(30)
    assert d.stop() == 0
    runs = segments(bus_cycles(recorder.snapshot()))
    assert len(runs) == 2, f"{len(runs)} runs of consecutive SYNCs, expected 2 (before and after the bus-off)"
    before = align(runs[0], setpoints_of(d))
    after = align(runs[1], setpoints_of(d), not_before=before[-1] + 1)
    assert before[-1] >= cycle_at_bus_off - 1 and after[0] > before[-1] + 1
    assert_setpoints_unbroken(setpoints_of(d))


def test_drive_following_error_bit(can_daemon, drives, recorder):
    """A drive that reports its own following error (statusword bit 13,
    beyond its window) stops the arm before the daemon's bound is reached."""
    sim = drives("--window", "200")
    d = can_daemon()
    st = run_to_fault(d, "vmax 5 2000", "drive: joint 5 (node 5) reports a following error", sim, goal_id=55)
    assert "bit 13" in st.reason
    assert_stopped_in_fault(d, 55)
    assert d.stop() == 0
    assert_setpoints_unbroken(setpoints_of(d))


def test_sync_every_two_cycles(can_daemon, drives, recorder):
    """sync_every = 2: a bus cycle (SYNC + RPDOs) every other cycle, the
    counter counting bus cycles, each RPDO its even cycle's setpoint."""
    drives("--period-ms", str(2 * PERIOD_US / 1000.0))
    d = can_daemon(sync_every=2)
    d.bus.send_goal_joint(95, Q_A, vel_scale=0.5, acc_scale=0.5)
    assert d.bus.wait_event(95, ["COMPLETED", "ABORTED"], timeout=30).event == EVENTS["COMPLETED"]
    assert d.stop() == 0
    cycles = bus_cycles(recorder.snapshot())
    sps = setpoints_of(d)
    by_cycle = {sp.cycle: sp for sp in sps}
    even = [sp.cycle for sp in sps if sp.cycle % 2 == 0]
    assert len(cycles) == len(even)
    for (counter, rpdos, _), k in zip(cycles, even):
        assert counter == (k // 2) % 240 + 1
        assert rpdos == [(pos_counts(j, by_cycle[k].q[j]), vel_counts(j, by_cycle[k].qd[j])) for j in range(6)]


@pytest.fixture
def qdisc_restored(vcan):
    yield
    subprocess.run(["tc", "qdisc", "del", "dev", IFACE, "root"], check=False, capture_output=True)


def test_enobufs_counted_never_retried(can_daemon, drives, recorder, qdisc_restored):
    """A queue that drops every frame (pfifo limit 0: each write fails with
    ENOBUFS): the bus cycles are counted as dropped, the output stays up
    (no loss, no fault: the next bus cycle is tried afresh), nothing is
    retried once the queue passes frames again."""
    drives()
    d = can_daemon(feedback=False)
    d.bus.send_goal_joint(97, Q_A, vel_scale=0.3, acc_scale=0.5)
    wait_moving(d)
    subprocess.run(["tc", "qdisc", "add", "dev", IFACE, "root", "pfifo", "limit", "0"], check=True)
    stats = d.bus.wait_stats(lambda s: s.can_tx_dropped >= 50, timeout=10)
    assert stats.can_state == 1 and stats.can_errors >= stats.can_tx_dropped // 7
    subprocess.run(["tc", "qdisc", "del", "dev", IFACE, "root"], check=True)
    st = d.bus.wait_event(97, ["COMPLETED", "ABORTED"], timeout=60)
    assert st.event == EVENTS["COMPLETED"], st.reason
    assert d.stop() == 0
    sent = int(re.search(r"CAN vcan0: frames (\d+), dropped (\d+)", d.stderr).group(1))
    dropped = int(re.search(r"CAN vcan0: frames (\d+), dropped (\d+)", d.stderr).group(2))
    frames = recorder.snapshot()
    ours = [f for f in frames if f[1] == 0x080 or 0x200 < f[1] < 0x280 or f[1] == 0x700 + MASTER]
    assert len(ours) == sent and dropped >= 50
    runs = segments(bus_cycles(frames))
    assert len(runs) == 2, f"{len(runs)} runs of consecutive SYNCs, expected 2"
    before = align(runs[0], setpoints_of(d))
    after = align(runs[1], setpoints_of(d), not_before=before[-1] + 1)
    assert after[0] - before[-1] - 1 >= dropped // 8, "the dropped bus cycles are missing, not sent late"
    assert not [s for s in statuses(d) if s.event == EVENTS["FAULT"]]
    assert_setpoints_unbroken(setpoints_of(d))
