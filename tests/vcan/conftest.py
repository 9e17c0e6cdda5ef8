# SPDX-License-Identifier: BSD-3-Clause
"""Fixtures of the vcan suite: kinctld with its CAN output on vcan0, the
simulated drives (kinctl drivesim) attached, and a recorder of every frame
on the bus. Run by tests/vcan/uml_run.sh: on this host's vcan0, or inside
User Mode Linux where the host has no SocketCAN.

The daemon fixture is tests/daemon's (kinctld, multicast, Bus, from the
suites' shared module tests/pylib/kinctl_testing.py): the same private LCM
URL per test. Frames are read by kinctl.canraw's recorder: a
raw CAN socket with an 8 MiB receive buffer, so the reader does not lose
frames at its own queue, and the kernel's timestamps.
"""
import math
import os
import struct
import subprocess
import sys

import pytest

from kinctl import canraw
from kinctl_testing import EVENTS, SLOW, STATES, kinctld, multicast  # noqa: F401 (fixtures)

IFACE = os.environ.get("KINCTL_VCAN", "vcan0")
IN_UML = os.environ.get("KINCTL_IN_UML") == "1"
# Inside UML everything shares one slow virtual CPU: a 10 ms cycle (the
# suite checks function, not timing), 1 ms on a host with vcan.
PERIOD_US = 10000 if IN_UML else 1000
NODES = [1, 2, 3, 4, 5, 6]
MASTER = 127
# Per joint: counts per rad, sign, offset (counts): every kind of scaling.
SCALING = [(100000.0, 1, 0), (100000.0, -1, 0), (65536.0, 1, 1000), (50000.0, 1, -250000), (100000.0, -1, 12345),
           (131072.0, 1, 0)]


def have_vcan():
    try:
        canraw.open_raw(IFACE).close()
        return True
    except OSError:
        return False


@pytest.fixture(scope="session")
def vcan():
    if not have_vcan():
        if os.environ.get("KINCTL_VCAN_REQUIRED") == "1":
            pytest.fail(f"{IFACE} should be up here (User Mode Linux) but cannot be opened")
        pytest.skip(f"VCAN SUITE SKIPPED: no SocketCAN interface {IFACE} here; run tests/vcan/uml_run.sh "
                    "(it boots User Mode Linux where the host has no AF_CAN)")
    return IFACE


def llround(x):
    """C's llround: halves away from zero."""
    return int(math.copysign(math.floor(abs(x) + 0.5), x))


def pos_counts(j, q):
    cpu, sign, off = SCALING[j]
    return llround(sign * q * cpu + off)


def vel_counts(j, qd):
    cpu, sign, _ = SCALING[j]
    return llround(sign * qd * cpu)


def counts_to_q(j, counts):
    cpu, sign, off = SCALING[j]
    return (counts - off) / (sign * cpu)


# The bound covers the lag of feedback behind the target: a few bus cycles of
# motion on a host, tens of milliseconds of a stalled process inside UML.
FOLLOWING_ERROR = 0.25 if IN_UML else 0.05


def write_config(path, on_error="stop", feedback=True, following_error=FOLLOWING_ERROR, drive_timeout_ms=1500.0,
                 sync_every=1, heartbeat_ms=100.0):
    joints = ", ".join(f"{{ node = {n}; counts_per_unit = {cpu}; sign = {sign}; offset_counts = {off}; }}"
                       for n, (cpu, sign, off) in zip(NODES, SCALING))
    with open(path, "w", encoding="utf-8") as f:
        f.write(f"""controller = {{
  period_us = {PERIOD_US};
  can = {{
    interface = "{IFACE}";
    sync_every = {sync_every};
    master_id = {MASTER};
    heartbeat_ms = {heartbeat_ms};
    on_error = "{on_error}";
    joints = ( {joints} );
    feedback = {{ enable = {"true" if feedback else "false"}; following_error = {following_error};
                 drive_timeout_ms = {drive_timeout_ms}; }};
  }};
}};
""")
    return path


class Recorder(canraw.FrameRecorder):
    """Every frame on the interface, (t_ns, id, data)."""

    def snapshot(self, quiet_s=0.3, longest_s=5.0):
        """The frames so far, once no SYNC or RPDO has arrived for quiet_s
        (the reader may trail the bus; the drives' heartbeats go on), or
        after longest_s."""
        return self.settle(quiet_s * SLOW, longest_s * SLOW, counted=lambda cid: cid == 0x080 or 0x200 < cid < 0x280)


@pytest.fixture
def recorder(vcan):
    r = Recorder(IFACE)
    yield r
    r.close()


class DriveSim:
    """`kinctl drivesim` as a subprocess, controlled through its stdin."""

    def __init__(self, *extra, period_ms=PERIOD_US / 1000.0):
        cmd = [sys.executable, "-m", "kinctl", "drivesim", "--interface", IFACE,
               "--nodes", ",".join(map(str, NODES)), "--period-ms", str(period_ms), "--heartbeat-ms", "50"]
        self.proc = subprocess.Popen(cmd + list(extra), stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, text=True, bufsize=1)
        line = self.proc.stdout.readline()
        if not line.startswith("ready"):
            raise AssertionError(f"drivesim did not start: {line!r} {self.proc.stderr.read()}")

    def command(self, line):
        self.proc.stdin.write(line + "\n")
        self.proc.stdin.flush()
        reply = self.proc.stdout.readline().strip()
        assert reply == "ok " + line, f"drivesim answered {reply!r} to {line!r}"

    def close(self):
        if self.proc.poll() is None:
            try:
                self.proc.stdin.write("quit\n")
                self.proc.stdin.flush()
                self.proc.wait(5)
            except (OSError, subprocess.TimeoutExpired):
                self.proc.kill()
                self.proc.wait()


@pytest.fixture
def drives(vcan):
    started = []

    def start(*extra):
        d = DriveSim(*extra)
        started.append(d)
        return d
    yield start
    for d in started:
        d.close()


@pytest.fixture
def can_daemon(kinctld, vcan, tmp_path):
    """Factory: a kinctld on puma560 with controller.can on vcan0 (keyword
    arguments of write_config); waits for its first setpoints."""
    def start(**cfg):
        path = write_config(str(tmp_path / "can.cfg"), **cfg)
        return kinctld("--config", path, "--model", "puma560")
    return start


# ---- checks ---------------------------------------------------------------

def daemon_frames(frames):
    """The frames kinctld sends: SYNC, RPDOs, its heartbeat."""
    ours = {0x080, 0x700 + MASTER} | {0x200 + n for n in NODES}
    return [f for f in frames if f[1] in ours]


def bus_cycles(frames):
    """[(sync counter, [(target, velocity) per node], SYNC timestamp ns)]
    from kinctld's frames in order; AssertionError when a SYNC is not followed by one RPDO per
    node in node order."""
    out = []
    seq = [f for f in daemon_frames(frames) if f[1] != 0x700 + MASTER]
    i = 0
    while i < len(seq):
        t, cid, data = seq[i]
        assert cid == 0x080, f"frame {i}: 0x{cid:03x} where a SYNC was due"
        assert len(data) == 1
        rpdos = []
        for k, n in enumerate(NODES):
            if i + 1 + k >= len(seq):
                return out  # the recording ended inside the last bus cycle
            _, rid, rdata = seq[i + 1 + k]
            assert rid == 0x200 + n, f"after SYNC {i}: 0x{rid:03x} where node {n}'s RPDO was due"
            rpdos.append(struct.unpack("<ii", rdata))
        out.append((data[0], rpdos, t))
        i += 1 + len(NODES)
    return out


def expected(sp):
    return [(pos_counts(j, sp.q[j]), vel_counts(j, sp.qd[j])) for j in range(len(NODES))]


def align(cycles, setpoints, not_before=0):
    """Matches the bus cycles to the setpoints: the first bus cycle to a
    setpoint from cycle not_before on whose SYNC counter and every count
    agree (an arm at rest repeats its setpoint: of those 240 cycles apart,
    the one whose deadline is nearest the SYNC's time), each next one to
    the next cycle. Returns the cycle numbers; AssertionError on any mismatch,
    gap or reordering."""
    by_cycle = {sp.cycle: sp for sp in setpoints}
    assert cycles, "no bus cycle recorded"
    counter, rpdos, ts = cycles[0]
    first = [k for k, sp in by_cycle.items() if k >= not_before and k % 240 + 1 == counter and expected(sp) == rpdos]
    assert first, f"no setpoint matches the first bus cycle (counter {counter}, {rpdos})"
    # Of the cycles that match (240 apart), the one whose deadline is
    # nearest the SYNC's time on the bus.
    k = min(first, key=lambda c: abs(by_cycle[c].utime * 1000 - ts))
    out = []
    for i, (counter, rpdos, _) in enumerate(cycles):
        assert counter == k % 240 + 1, f"bus cycle {i}: SYNC counter {counter}, cycle {k} wants {k % 240 + 1}"
        if k not in by_cycle:
            break  # past the setpoints recorded
        assert rpdos == expected(by_cycle[k]), \
            f"bus cycle {i} (cycle {k}): RPDOs {rpdos} != setpoint scaled {expected(by_cycle[k])}"
        out.append(k)
        k += 1
    return out


def segments(cycles):
    """Splits bus cycles into runs of consecutive SYNC counters."""
    out = []
    for c in cycles:
        if out and c[0] == out[-1][-1][0] % 240 + 1:
            out[-1].append(c)
        else:
            out.append([c])
    return out


def assert_setpoints_unbroken(setpoints):
    cycles = [sp.cycle for sp in setpoints]
    gaps = [(a, b) for a, b in zip(cycles, cycles[1:]) if b != a + 1]
    assert not gaps, f"the LCM setpoint stream has gaps or reorderings: {gaps[:5]}"


def wait_fault(bus, token, timeout=10.0):
    """The first status with event FAULT whose reason starts with token."""
    def find():
        for s in bus.statuses:
            if s.event == EVENTS["FAULT"] and s.reason.startswith(token):
                return s
        return None
    return bus.wait(find, timeout, f"a FAULT with reason {token}...")


def wait_status(bus, predicate, timeout=10.0, what="a status"):
    def find():
        for s in bus.statuses:
            if predicate(s):
                return s
        return None
    return bus.wait(find, timeout, what)
