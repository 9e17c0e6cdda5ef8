# SPDX-License-Identifier: BSD-3-Clause
"""Fixtures of the vcan suite: kinctld as the CANopen master of six CiA 402
drives on vcan0, the drives simulated by kinctl.drive402 (python canopen:
an SDO server, NMT, heartbeat and EMCY from an EDS, the CiA 402 power state
machine) in this process, so that a test reads each drive's object
dictionary and state directly, and a recorder of every frame on the bus.
Run by tests/vcan/uml_run.sh: on this host's vcan0, or inside User Mode
Linux where the host has no SocketCAN.

The daemon fixture is tests/daemon's (kinctld, multicast, Bus, from the
suites' shared module tests/pylib/kinctl_testing.py): the same private LCM
URL per test. Frames are read by kinctl.canraw's recorder: a raw CAN socket
with an 8 MiB receive buffer, so the reader does not lose frames at its own
queue, and the kernel's timestamps.

The frames and the objects follow daemon/README.md's controller.can (CiA
301's predefined connection set): NMT 0x000, SYNC 0x080 (empty, or a
counter byte), EMCY 0x080 + node, TPDO1 0x180 + node (statusword 0x6041,
position actual 0x6064), RPDO1 0x200 + node (controlword 0x6040, target
position 0x607A), SDO 0x580/0x600 + node, heartbeat 0x700 + id.
"""
import bisect
import math
import os
import struct
import time

import pytest

from kinctl import canraw, drive402
from kinctl_testing import EVENTS, MEMCHECK_DIR, SLOW, STATES, kinctld, multicast, run_kinctld  # noqa: F401 (fixtures)

IFACE = os.environ.get("KINCTL_VCAN", "vcan0")
IN_UML = os.environ.get("KINCTL_IN_UML") == "1"
# Inside UML everything shares one slow virtual CPU: a 10 ms cycle (the
# suite checks function, not timing), 1 ms on a host with vcan.
PERIOD_US = 10000 if IN_UML else 1000
# With kinctld under valgrind there (vcan.memcheck), a test that boots a
# drive again while the bus cycle runs has a bus cycle every SLOW_BUS
# cycles (sync_every). At every cycle the simulated drives, a Python
# process on UML's one CPU beside that kinctld, fell behind the bus in 2
# of 9 runs of test_drive_lost_mid_run alone, and once in the whole
# suite: the booted drive's SDO answers came later and later (8 s after
# 40 s: the master's SDO timeout), or it seemed stuck in switched on, the
# TPDO that answered its enabling still queued. Every 5 cycles: 0 of 8.
# (A 50 ms cycle instead takes the controller's dt with it: a line of the
# suite was then judged unreachable.)
SLOW_BUS = 5 if IN_UML and MEMCHECK_DIR else 1
NODES = [1, 2, 3, 4, 5, 6]
MASTER = 127
# Per joint: counts per rad, sign, offset (counts): every kind of scaling.
SCALING = [(100000.0, 1, 0), (100000.0, -1, 0), (65536.0, 1, 1000), (50000.0, 1, -250000), (100000.0, -1, 12345),
           (131072.0, 1, 0)]
# puma560's joint speed limits (rad/s, core/src/chain.c): the largest step
# of a target or an actual position between two bus cycles.
QD_MAX = [2.0, 2.0, 2.0, 4.0, 4.0, 4.0]
# Where the arm's drives stand at power-on (rad; inside puma560's limits,
# no two alike, none at zero counts).
Q_START = [0.2, 0.9, -2.9, 0.3, 0.6, -0.4]

# status_t.drives (lcmtypes/status_t.lcm)
DRIVES = {"NONE": 0, "BOOTING": 1, "ENABLING": 2, "ENABLED": 3, "DISABLED": 4}
# CiA 402 controlwords kinctld sends
CW_DISABLE_VOLTAGE, CW_QUICK_STOP, CW_SHUTDOWN, CW_SWITCH_ON, CW_ENABLE = 0x00, 0x02, 0x06, 0x07, 0x0F
CW_FAULT_RESET = 0x80
# NMT commands (0x000: command, node) and states (heartbeat byte)
NMT_START, NMT_STOP, NMT_PRE_OPERATIONAL, NMT_RESET_COMMUNICATION = 0x01, 0x02, 0x80, 0x82
NMT_STATE = {"boot-up": 0x00, "stopped": 0x04, "operational": 0x05, "pre-operational": 0x7F}

# The bound covers the lag of feedback behind the target: a few bus cycles of
# motion on a host, tens of milliseconds of a stalled process inside UML.
FOLLOWING_ERROR = 0.25 if IN_UML else 0.05
# What the suite writes into controller.can besides the joints: the
# contract's defaults where they suit a slow UML, longer waits where not.
CAN_SUITE = {
    "sync_every": 1, "master_id": MASTER, "heartbeat_ms": 100.0, "on_error": "stop",
    "drive_heartbeat_ms": 100, "master_timeout_ms": 1500 if IN_UML else 300, "lost_master_reaction": 3,
    "sdo_timeout_ms": 2000 * SLOW if IN_UML else 500, "boot_timeout_ms": 20000 * SLOW if IN_UML else 5000,
    "enable_timeout_ms": 5000 * SLOW if IN_UML else 2000,
}
# (boot_timeout_ms: the tests that power the drives on after kinctld began
# booting them start them, and a recorder, in Python; in UML beside a
# kinctld under valgrind that took more than 5 s.
# sdo_timeout_ms: the drives' SDO servers run in this Python process, which
# shares UML's one CPU with kinctld, the recorder and the LCM receiver; under
# valgrind (SLOW) it once left a read-back unanswered through three sends of
# 2 s each while it worked through the frames queued before it.
# enable_timeout_ms: each step of a drive's way to operation enabled waits
# for a TPDO from that same process; under valgrind a rebooted drive was
# last seen in ready to switch on when 5 s had passed. All three scale with
# SLOW as the suite's own waits do; no test here times a boot, an SDO or an
# enabling out.)


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


# ---- scaling --------------------------------------------------------------

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


def start_counts(q=Q_START):
    """{node: counts} of joint positions q."""
    return {n: pos_counts(j, q[j]) for j, n in enumerate(NODES)}


def max_step_counts(j, sync_every=1):
    """The largest change of joint j's counts in one bus cycle at its speed
    limit, one count of rounding beside."""
    return QD_MAX[j] * SCALING[j][0] * PERIOD_US * 1e-6 * sync_every + 1


# ---- configuration --------------------------------------------------------

def libconfig(value, indent=""):
    """value (dict: group, list of groups: list, list of scalars: array,
    bool, int, float, str) in libconfig's syntax."""
    if isinstance(value, dict):
        inner = indent + "  "
        return "{\n" + "".join(f"{inner}{k} = {libconfig(v, inner)};\n" for k, v in value.items()) + indent + "}"
    if isinstance(value, (list, tuple)):
        brackets = "()" if any(isinstance(v, dict) for v in value) else "[]"
        return brackets[0] + " " + ", ".join(libconfig(v, indent + "  ") for v in value) + " " + brackets[1]
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, float):
        return repr(value)
    return str(int(value))


def can_config(writes=None, identity=None, feedback=True, following_error=FOLLOWING_ERROR, drive_timeout_ms=1500.0,
               nodes=NODES, scaling=SCALING, **keys):
    """controller.can as a dict: the suite's settings (CAN_SUITE), keys over
    them (None drops a key: the daemon's default), the joints with their
    `writes` ({node: [(index, subindex, size, value)]}) and `identity`
    ({node: [vendor, product, revision, serial]})."""
    can = {"interface": IFACE}
    can.update(CAN_SUITE)
    can.update(keys)
    joints = []
    for n, (cpu, sign, off) in zip(nodes, scaling):
        joint = {"node": n, "counts_per_unit": float(cpu), "sign": sign, "offset_counts": off}
        if identity and n in identity:
            joint["identity"] = list(identity[n])
        if writes and writes.get(n):
            joint["writes"] = [{"index": i, "subindex": s, "size": size, "value": v} for i, s, size, v in writes[n]]
        joints.append(joint)
    can["joints"] = joints
    can["feedback"] = {"enable": feedback, "following_error": float(following_error),
                       "drive_timeout_ms": float(drive_timeout_ms)}
    return {k: v for k, v in can.items() if v is not None}


def write_config(path, period_us=PERIOD_US, **kw):
    """A configuration file with controller.period_us and controller.can
    (can_config's keywords); returns the can dict written."""
    can = can_config(**kw)
    with open(path, "w", encoding="utf-8") as f:
        f.write("controller = " + libconfig({"period_us": period_us, "can": can}) + ";\n")
    return can


# ---- the bus --------------------------------------------------------------

class Recorder(canraw.FrameRecorder):
    """Every frame on the interface, (t_ns, id, data)."""

    def snapshot(self, quiet_s=0.3, longest_s=5.0):
        """The frames so far, once no SYNC or RPDO has arrived for quiet_s
        (the reader may trail the bus; the drives' heartbeats go on), or
        after longest_s."""
        return self.settle(quiet_s * SLOW, longest_s * SLOW, counted=lambda cid: cid == 0x080 or 0x200 < cid < 0x280)


    def so_far(self):
        """The frames received so far (the bus still running)."""
        with self.lock:
            return list(self.frames)


@pytest.fixture
def recorder(vcan):
    r = Recorder(IFACE)
    yield r
    r.close()


class Sim:
    """kinctl.drive402's Drives at NODES on vcan0, in this process: the
    control lines of `kinctl drive402` (command) and each drive's state and
    object dictionary read directly.

    Like a drive's CAN controller, the network takes only the frames the
    drives use (NMT, SYNC, their RPDOs and SDO requests, heartbeats) through
    a kernel filter."""

    def __init__(self, starts=None, lag_s=0.0, nodes=NODES, **presets):
        """presets: drive402.presets()'s power-on values (a drive configured
        by other means)."""
        self.starts = dict(starts or start_counts())
        self.drives = drive402.Drives(IFACE, nodes, start_counts=self.starts, lag_s=lag_s, **presets)
        exact = [0x000, 0x080] + [base + n for n in nodes for base in (0x200, 0x300, 0x600)]
        self.drives.network.bus.set_filters([{"can_id": cid, "can_mask": 0x7FF} for cid in exact] +
                                            [{"can_id": 0x700, "can_mask": 0x780}])
        self.sync_at = 0.0  # the kernel's time of the last SYNC the drives have taken
        self.drives.network.subscribe(0x080, self._synced)  # called after the drives' own handler

    def _synced(self, can_id, data, timestamp):
        self.sync_at = timestamp

    def command(self, line):
        reply = self.drives.command(line)
        assert reply.startswith("ok " + line), f"drive402 answered {reply!r} to {line!r}"
        return reply

    def drive(self, n):
        return self.drives.drives[n]

    def od(self, n, index, sub=0):
        with self.drives.lock:
            return self.drive(n).od(index, sub)

    def state(self, n):
        """(NMT state, CiA 402 state, statusword, actual position in counts)."""
        with self.drives.lock:
            d = self.drive(n)
            return d.nmt, d.state, d.statusword(), int(round(d.pos))

    def wait_until(self, done, timeout=2.0 * SLOW):
        """Until done(self) holds or timeout s have passed: the drives take
        their frames in their own thread, after the frames are on the bus.
        The caller asserts what it waited for."""
        end = time.monotonic() + timeout
        while not done(self) and time.monotonic() < end:
            time.sleep(0.01)

    def wait_taken(self, timeout=2.0 * SLOW):
        """Until the drives have taken a SYNC sent after this call, and so
        every frame sent before it (the bus cycle running; the drives take
        frames in their order on the bus)."""
        since = time.time()
        self.wait_until(lambda s: s.sync_at > since, timeout)
        assert self.sync_at > since, f"the drives took no SYNC within {timeout:.1f} s"

    def events(self, n):
        """What drive n did besides its cycle: [("emcy", code), ("sync_error", length), ...]."""
        with self.drives.lock:
            return list(self.drive(n).events)

    def close(self):
        self.drives.close()


@pytest.fixture
def drives(vcan):
    """Factory: drives(starts={node: counts}, lag_s=..., presets...) -> Sim."""
    started = []

    def start(**kw):
        s = Sim(**kw)
        started.append(s)
        return s
    yield start
    for s in started:
        s.close()


# ---- the daemon -----------------------------------------------------------

@pytest.fixture
def can_daemon(kinctld, vcan, tmp_path):
    """Factory: a kinctld on puma560 with controller.can on vcan0 (keywords
    of write_config); waits for its first setpoints. The daemon's can dict
    is d.can."""
    def start(model="puma560", **cfg):
        path = str(tmp_path / "can.cfg")
        can = write_config(path, **cfg)
        d = kinctld("--config", path, "--model", model)
        d.can = can
        return d
    return start


def stopped_with(d, what):
    """Stops d and returns an AssertionError naming what and its stderr."""
    d.stop()
    return AssertionError(f"{what}; kinctld's stderr:\n{d.stderr}")


def wait_drives(d, value, timeout=30.0, since=0, with_reason=False):
    """The first status from index since on whose drives is value (DRIVES
    name), and with with_reason one that says why (a periodic status may
    show the drives' new state before the one that reports it); on a
    timeout the daemon is stopped and its stderr shown."""
    want = DRIVES[value]

    def find():
        for s in d.bus.statuses[since:]:
            if s.drives == want and (s.reason or not with_reason):
                return s
        return None
    try:
        return d.bus.wait(find, timeout, f"status drives = DRIVES_{value}")
    except AssertionError as e:
        with d.bus.lock:
            seen = [(s.drives, s.reason) for s in d.bus.statuses if s.reason]
        raise stopped_with(d, f"{e}; statuses with a reason: {seen}") from None


# The speed and acceleration scale of a goal under way when a test acts on
# it (a fault, ESTOP, the link down): the motion must outlast the test's lag
# behind kinctld, as old as the last setpoints this process has taken, which
# under valgrind (SLOW) in UML's one CPU reached about a second.
MOVING_SCALE = 0.5 / SLOW


def start_moving(d, goal_id, q):
    """Sends a joint goal to q at MOVING_SCALE; returns once the arm is
    well under way (a joint faster than 0.05 rad/s)."""
    d.bus.send_goal_joint(goal_id, q, vel_scale=MOVING_SCALE, acc_scale=MOVING_SCALE)
    d.bus.wait(lambda: any(s.state == STATES["MOVING"] and max(abs(v) for v in s.qd[:6]) > 0.05
                           for s in d.bus.setpoints[-5:]), what="motion")


def enabled_daemon(can_daemon, **cfg):
    """A kinctld whose drives are enabled: (daemon, the status that says so)."""
    d = can_daemon(**cfg)
    return d, wait_drives(d, "ENABLED")


def statuses(d):
    with d.bus.lock:
        return list(d.bus.statuses)


def setpoints_of(d):
    with d.bus.lock:
        return list(d.bus.setpoints)


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


# ---- frames ---------------------------------------------------------------

def assert_configured(sim, n, can, writes=()):
    """Drive n's object dictionary holds what controller.can (the dict
    write_config wrote) says."""
    sync_every = can["sync_every"]
    period_s = PERIOD_US * 1e-6 * sync_every
    od = lambda index, sub=0: sim.od(n, index, sub)  # noqa: E731
    assert od(0x6060) == 8, f"node {n}: modes of operation"
    value, index = od(0x60C2, 1), od(0x60C2, 2)
    assert math.isclose(value * 10.0 ** index, period_s, rel_tol=1e-9), \
        f"node {n}: 0x60C2 = {value} x 10^{index} s, the bus cycle is {period_s} s"
    # 0x1006 only with cycle_period (else the EDS's 0: not checked)
    assert od(0x1006) == (PERIOD_US * sync_every if can.get("cycle_period") else 0), \
        f"node {n}: communication cycle period {od(0x1006)}"
    assert od(0x1019) == can.get("sync_counter", 0), f"node {n}: synchronous counter overflow"
    assert od(0x1017) == can["drive_heartbeat_ms"], f"node {n}: producer heartbeat"
    if can["master_timeout_ms"]:
        assert od(0x1016, 1) == MASTER << 16 | can["master_timeout_ms"], \
            f"node {n}: consumer heartbeat 0x{od(0x1016, 1):08x}"
    assert od(0x6007) == can["lost_master_reaction"], f"node {n}: abort connection option code"
    # RPDO1: controlword + target position, synchronous, at 0x200 + node
    assert od(0x1400, 1) & 0x800007FF == 0x200 + n, f"node {n}: RPDO1 COB-ID 0x{od(0x1400, 1):08x}"
    assert od(0x1400, 2) <= 240, f"node {n}: RPDO1 transmission type {od(0x1400, 2)} is not synchronous"
    assert [od(0x1600, s) for s in range(od(0x1600, 0) + 1)] == [2, 0x60400010, 0x607A0020]
    # RPDO2: the velocity offset with velocity_offset, else invalid
    if can.get("velocity_offset"):
        assert od(0x1401, 1) & 0x800007FF == 0x300 + n, f"node {n}: RPDO2 COB-ID 0x{od(0x1401, 1):08x}"
        assert [od(0x1601, s) for s in range(od(0x1601, 0) + 1)] == [1, 0x60B10020]
    else:
        assert od(0x1401, 1) & 0x80000000, f"node {n}: RPDO2 valid (0x{od(0x1401, 1):08x}) without velocity_offset"
    # TPDO1: statusword + position actual every tpdo_every-th SYNC at 0x180 + node
    assert od(0x1800, 1) & 0x800007FF == 0x180 + n, f"node {n}: TPDO1 COB-ID 0x{od(0x1800, 1):08x}"
    assert od(0x1800, 2) == can.get("tpdo_every", 1), f"node {n}: TPDO1 transmission type"
    assert [od(0x1A00, s) for s in range(od(0x1A00, 0) + 1)] == [2, 0x60410010, 0x60640020]
    for index, sub, _, value in writes:
        assert od(index, sub) == value, f"node {n}: configured write 0x{index:04x}:{sub:02x} reads {od(index, sub)}"


def rpdo1(data):
    """(controlword, target position) of an RPDO1."""
    assert len(data) == 6, f"RPDO1 of {len(data)} bytes: {data.hex()}"
    return struct.unpack("<Hi", data)


def tpdo1(data):
    """(statusword, position actual) of a TPDO1."""
    assert len(data) == 6, f"TPDO1 of {len(data)} bytes: {data.hex()}"
    return struct.unpack("<Hi", data)


def bus_cycles(frames, nodes=NODES, cut=None):
    """[(SYNC data, [(controlword, target) per node], SYNC timestamp ns)]
    from kinctld's SYNCs and RPDO1s in order; AssertionError when a SYNC is
    not followed by one RPDO1 per node in joint order. Where the output is
    lost mid-cycle (the link going down or the queue refusing frames
    between two writes), kinctld's bus cycle is cut short after its SYNC:
    with a list for cut, such a cycle is skipped and its SYNC timestamp
    appended to cut instead of failing."""
    ours = {0x080} | {0x200 + n for n in nodes}
    seq = [f for f in frames if f[1] in ours]
    out = []
    i = 0
    while i < len(seq):
        t, cid, data = seq[i]
        assert cid == 0x080, f"frame {i}: 0x{cid:03x} where a SYNC was due"
        if i + len(nodes) >= len(seq):
            break  # the recording ended inside the last bus cycle
        rpdos = []
        for k, n in enumerate(nodes):
            _, rid, rdata = seq[i + 1 + k]
            if rid == 0x080 and cut is not None:
                break
            assert rid == 0x200 + n, f"after SYNC {i}: 0x{rid:03x} where node {n}'s RPDO1 was due"
            rpdos.append(rpdo1(rdata))
        if len(rpdos) < len(nodes):
            cut.append(t)
        else:
            out.append((bytes(data), rpdos, t))
        i += 1 + len(rpdos)
    return out


def expected(sp, n=len(NODES)):
    """A setpoint's targets in counts."""
    return [pos_counts(j, sp.q[j]) for j in range(n)]


def align(cycles, setpoints, sync_every=1):
    """Matches consecutive bus cycles to every sync_every-th setpoint by
    their targets (to the count): of the setpoints the first bus cycle
    matches (an arm at rest repeats its setpoint), the one nearest the
    SYNC's time whose successors match every next bus cycle. Returns the
    cycle numbers; AssertionError when none does."""
    assert cycles, "no bus cycle recorded"
    assert setpoints, "no setpoint recorded"
    want = [tuple(expected(sp)) for sp in setpoints]
    got = [tuple(t for _, t in rpdos) for _, rpdos, _ in cycles]
    first = [i for i, w in enumerate(want) if w == got[0]]
    assert first, f"no setpoint matches the first bus cycle's targets {got[0]}"
    first.sort(key=lambda i: abs(setpoints[i].utime * 1000 - cycles[0][2]))
    best = None
    for i in first[:40]:
        n = 0
        while n < len(got) and i + n * sync_every < len(want) and want[i + n * sync_every] == got[n]:
            n += 1
        if n == len(got) or i + n * sync_every >= len(want):
            return [sp.cycle for sp in setpoints[i:i + n * sync_every:sync_every]]
        if best is None or n > best[1]:
            best = (i, n)
    i, n = best
    k = i + n * sync_every
    raise AssertionError(f"bus cycle {n} (targets {got[n]}) is not the setpoint of cycle {setpoints[k].cycle} "
                         f"({want[k]}) after {n} that matched from cycle {setpoints[i].cycle}")


def runs(cycles, setpoints, slack=3):
    """Splits bus cycles where bus cycles are missing (the interface down,
    writes failing), not where the machine stalled: each bus cycle's SYNC
    went out after its step, so it is placed at the latest setpoint whose
    deadline (utime, CLOCK_REALTIME) precedes it; a stalled cycle thread
    runs late and skips deadlines but no cycle number, a lost bus leaves
    cycles without a SYNC. A jump of more than slack cycles (a write
    preempted past the next deadline moves one by a cycle) splits."""
    deadlines = [sp.utime * 1000 for sp in setpoints]
    out, before = [], None
    for c in cycles:
        i = bisect.bisect_right(deadlines, c[2]) - 1
        assert i >= 0, "a SYNC before the first setpoint's deadline"
        k = setpoints[i].cycle
        if out and k - before <= slack:
            out[-1].append(c)
        else:
            out.append([c])
        before = k
    return out


def assert_setpoints_unbroken(setpoints):
    cycles = [sp.cycle for sp in setpoints]
    gaps = [(a, b) for a, b in zip(cycles, cycles[1:]) if b != a + 1]
    assert not gaps, f"the LCM setpoint stream has gaps or reorderings: {gaps[:5]}"


def per_node(frames, n):
    """Node n's RPDO1s and TPDO1s in bus order: [("rpdo", cw, target) or
    ("tpdo", statusword, actual)]."""
    out = []
    for _, cid, data in frames:
        if cid == 0x200 + n:
            out.append(("rpdo",) + rpdo1(data))
        elif cid == 0x180 + n:
            out.append(("tpdo",) + tpdo1(data))
    return out


def assert_no_jump(frames, nodes=NODES, sync_every=1):
    """No drive jumps: every RPDO1 that enables a drive (controlword 0x0F
    after another) carries the drive's last reported actual position as its
    target; two targets sent to an enabled drive, and two actual positions
    it reports, differ by at most the joint's speed limit over a bus cycle.
    Returns the number of enablings per node."""
    enablings = {}
    for j, n in enumerate(nodes):
        bound = max_step_counts(j, sync_every)
        cw_before, target_before, actual = None, None, None
        enablings[n] = 0
        for kind, a, b in per_node(frames, n):
            if kind == "tpdo":
                if actual is not None:
                    assert abs(b - actual) <= bound, f"node {n}'s actual position jumps {actual} -> {b}"
                actual = b
                continue
            cw, target = a, b
            if cw == CW_ENABLE and cw_before != CW_ENABLE:
                enablings[n] += 1
                assert actual is not None, f"node {n} enabled before it reported its position"
                assert target == actual, f"node {n} enabled with target {target}, its actual position {actual}"
            elif cw == CW_ENABLE:
                assert abs(target - target_before) <= bound, \
                    f"node {n}'s target jumps {target_before} -> {target} while enabled"
            cw_before, target_before = cw, target
    return enablings


def sdo_requests(frames, n):
    """The master's SDO requests to node n in order, with their position in
    frames: [(i, "download", index, sub, value) or (i, "upload", index, sub)],
    and its aborts (i, "abort", index, sub, code)."""
    out = []
    for i, (_, cid, data) in enumerate(frames):
        if cid not in (0x600 + n, 0x580 + n) or len(data) != 8:
            continue
        cs = data[0]
        index, sub = struct.unpack_from("<HB", data, 1)
        if cid == 0x600 + n and cs & 0xE0 == 0x20:
            assert cs & 0x02, f"node {n}: SDO download 0x{cs:02x} not expedited"
            size = 4 - ((cs >> 2) & 3) if cs & 1 else 4
            out.append((i, "download", index, sub, int.from_bytes(data[4:4 + size], "little")))
        elif cid == 0x600 + n and cs == 0x40:
            out.append((i, "upload", index, sub))
        elif cs == 0x80:
            out.append((i, "abort", index, sub, struct.unpack_from("<I", data, 4)[0]))
    return out


def refused(sim, n, sdo):
    """The aborts in sdo (sdo_requests) but those of the master's optional
    writes that a drive without the object may refuse: the PDOs of the
    predefined set it does not use, made invalid where they exist
    (daemon/README.md). [(index, sub, abort code)]"""
    od = sim.drive(n).node.object_dictionary
    return [(index, sub, code) for _, kind, index, sub, code in (s for s in sdo if s[1] == "abort")
            if not (0x1400 <= index < 0x1C00 and index not in od and code == 0x06020000)]


def nmt_commands(frames, n):
    """[(i, command)] of the NMT frames that address node n (or all)."""
    return [(i, data[0]) for i, (_, cid, data) in enumerate(frames)
            if cid == 0x000 and len(data) == 2 and data[1] in (0, n)]
