"""kinctld's CAN output on a real SocketCAN interface (vcan0), with the
simulated drives attached: frames against the LCM setpoints, feedback, and
each failure's reaction. See conftest.py for the fixtures and checks."""
import os
import re
import subprocess
import sys
import time

import pytest

from conftest import (IFACE, MASTER, NODES, PERIOD_US, SCALING, STATES, EVENTS, align, assert_setpoints_unbroken,
                      bus_cycles, counts_to_q, daemon_frames, wait_fault, wait_status)
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
