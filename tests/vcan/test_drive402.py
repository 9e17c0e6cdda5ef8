# SPDX-License-Identifier: BSD-3-Clause
"""`kinctl drivesim` (tools/kinctl/drive402.py) met by a CANopen master it
did not come with: python canopen's own RemoteNode and BaseNode402, on a
real SocketCAN interface (vcan0, inside User Mode Linux where the host has
none). The master boots the drives (NMT reset communication, boot-up),
checks the device type, remaps the PDOs with canopen's own CiA 301 sequence,
configures mode 8 and the interpolation period by SDO and reads every value
back, starts them, walks the CiA 402 state machine with BaseNode402 and
moves them with CSP targets; the frames on the bus are recorded by a raw
socket of their own.
"""
import struct
import subprocess
import sys
import threading
import time

import pytest

from conftest import IFACE, IN_UML, Recorder

import canopen
from kinctl import drive402

NODES = (1, 2)
START = {1: 5000, 2: -7000}
MASTER_ID = 127
# Inside UML one slow virtual CPU runs the drives, the master and pytest.
PERIOD_S = 0.01 if IN_UML else 0.002
WAIT_S = 4.0 if IN_UML else 1.0


class Sim:
    """`kinctl drivesim` as a subprocess, controlled through its stdin."""

    def __init__(self, nodes=NODES, start=START):
        cmd = [sys.executable, "-m", "kinctl", "drivesim", "--interface", IFACE,
               "--nodes", ",".join(map(str, nodes)),
               "--start", ",".join(f"{n}={c}" for n, c in start.items())]
        self.proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     text=True, bufsize=1)
        line = self.proc.stdout.readline()
        if not line.startswith("ready"):
            raise AssertionError(f"drivesim did not start: {line!r} {self.proc.stderr.read()}")

    def command(self, line):
        self.proc.stdin.write(line + "\n")
        self.proc.stdin.flush()
        reply = self.proc.stdout.readline().strip()
        assert reply.startswith("ok " + line), f"drivesim answered {reply!r} to {line!r}"
        return reply

    def state(self, node):
        """(NMT state, CiA 402 state, statusword, actual position)."""
        _, _, _, nmt, state, sw, pos = self.command(f"state {node}").split()
        return int(nmt), state.replace("_", " "), int(sw, 16), int(pos)

    def close(self):
        if self.proc.poll() is None:
            try:
                self.proc.stdin.write("quit\n")
                self.proc.stdin.flush()
                self.proc.wait(5)
            except (OSError, subprocess.TimeoutExpired):
                self.proc.kill()
                self.proc.wait()
        err = self.proc.stderr.read()
        if err:
            print("drivesim's stderr:\n" + err)  # shown with a failure


def sdo_var(node, index, sub):
    obj = node.sdo[index]
    return obj if isinstance(obj, canopen.sdo.SdoVariable) else obj[sub]


class Master:
    """python canopen's master side: a Network, a BaseNode402 per drive
    (made from the same EDS), the EMCYs received."""

    def __init__(self, nodes=NODES):
        self.net = canopen.Network()
        self.net.connect(interface="socketcan", channel=IFACE, receive_own_messages=False)
        self.emcy = []
        self.nodes = {}
        for n in nodes:
            node = canopen.BaseNode402(n, drive402.default_eds())
            for attr in ("TIMEOUT_SWITCH_STATE_FINAL", "TIMEOUT_SWITCH_STATE_SINGLE", "TIMEOUT_CHECK_TPDO"):
                setattr(node, attr, WAIT_S)
            self.net.add_node(node)
            self.net.subscribe(0x80 + n, self._on_emcy)
            self.nodes[n] = node
        self.heartbeat = None
        self.running = False
        self.configured = []
        self.booted = {n: threading.Event() for n in nodes}
        for n in nodes:
            self.net.subscribe(0x700 + n, self._on_heartbeat)

    def _on_heartbeat(self, can_id, data, timestamp):
        if len(data) >= 1 and data[0] == 0x00:
            self.booted[can_id - 0x700].set()

    def reset(self, n):
        """NMT reset communication of node n; waits for its boot-up."""
        self.booted[n].clear()
        self.nodes[n].nmt.state = "RESET COMMUNICATION"
        assert self.booted[n].wait(WAIT_S), f"no boot-up from node {n}"

    def _on_emcy(self, can_id, data, timestamp):
        code, register = struct.unpack_from("<HB", data)
        self.emcy.append((can_id - 0x80, code, register))

    def wait_emcy(self, node, code):
        end = time.monotonic() + WAIT_S
        while time.monotonic() < end:
            if any(e[0] == node and e[1] == code for e in self.emcy):
                return next(e for e in self.emcy if e[0] == node and e[1] == code)
            time.sleep(0.01)
        raise AssertionError(f"no EMCY 0x{code:04x} from node {node}; EMCYs: {self.emcy}")

    def configure(self, n, tpdo_every=1, sdo_writes=()):
        """Boots and configures drive n in pre-operational; every write read
        back. Returns its BaseNode402."""
        node = self.nodes[n]
        self.reset(n)
        assert node.sdo[0x1000].raw == 0x00020192
        assert node.sdo[0x6502].raw & 0x80  # CSP supported
        assert node.sdo[0x6064].raw == START[n]  # where the drive is, not 0
        node.rpdo.read()
        node.tpdo.read()
        # CiA 402's defaults: RPDO1 the controlword, TPDO1 the statusword
        assert [v.index for v in node.rpdo[1].map] == [0x6040]
        assert [v.index for v in node.tpdo[1].map] == [0x6041]
        node.rpdo[1].clear()
        node.rpdo[1].add_variable(0x6040)
        node.rpdo[1].add_variable(0x607A)
        node.rpdo[1].trans_type = 1
        node.rpdo[1].enabled = True
        node.tpdo[1].clear()
        node.tpdo[1].add_variable(0x6041)
        node.tpdo[1].add_variable(0x6064)
        node.tpdo[1].trans_type = tpdo_every
        node.tpdo[1].enabled = True
        node.rpdo.save()
        node.tpdo.save()
        period_ms = int(round(PERIOD_S * 1000))
        writes = [(0x6060, 0, 8), (0x60C2, 1, period_ms), (0x60C2, 2, -3), (0x1017, 0, 50)] + list(sdo_writes)
        for index, sub, value in writes:
            sdo_var(node, index, sub).raw = value
        # read back, as a fresh upload each
        assert node.sdo[0x1600][0].raw == 2
        assert node.sdo[0x1600][1].raw == 0x60400010
        assert node.sdo[0x1600][2].raw == 0x607A0020
        assert node.sdo[0x1400][1].raw & 0x800007FF == 0x200 + n
        assert node.sdo[0x1400][2].raw == 1
        assert node.sdo[0x1A00][0].raw == 2
        assert node.sdo[0x1A00][1].raw == 0x60410010
        assert node.sdo[0x1A00][2].raw == 0x60640020
        assert node.sdo[0x1800][1].raw & 0x800007FF == 0x180 + n
        assert node.sdo[0x1800][2].raw == tpdo_every
        for index, sub, value in writes:
            got = sdo_var(node, index, sub).raw
            assert got == value, f"0x{index:04x}:{sub} reads {got}, {value} written"
        node.setup_402_state_machine(read_pdos=True)
        self.configured.append(n)
        return node

    def run(self, heartbeat=True):
        """NMT start, SYNC, the RPDOs with target = actual and controlword
        0, the master's heartbeat."""
        for n in self.configured:
            node = self.nodes[n]
            node.nmt.state = "OPERATIONAL"
            node.rpdo[1]["Target position"].raw = node.sdo[0x6064].raw
            node.rpdo[1]["Controlword"].raw = 0
        self.net.sync.start(PERIOD_S)
        for n in self.configured:
            self.nodes[n].rpdo[1].start(PERIOD_S)
        self.running = True
        if heartbeat:
            self.heartbeat = self.net.send_periodic(0x700 + MASTER_ID, [0x05], 0.05)

    def stop(self):
        if not self.running:
            return
        self.running = False
        for n in self.configured:
            self.nodes[n].rpdo[1].stop()
        self.net.sync.stop()
        if self.heartbeat is not None:
            self.heartbeat.stop()
            self.heartbeat = None

    def close(self):
        self.stop()
        self.net.disconnect()


@pytest.fixture
def sim(vcan):
    s = Sim()
    yield s
    s.close()


@pytest.fixture
def master(vcan):
    m = Master()
    yield m
    m.close()


def wait_for(what, predicate):
    end = time.monotonic() + WAIT_S
    while time.monotonic() < end:
        got = predicate()
        if got:
            return got
        time.sleep(0.01)
    raise AssertionError(f"timed out waiting for {what}")


def test_boot_configure_enable_move(sim, master, vcan):
    rec = Recorder(IFACE)
    try:
        for n in NODES:
            master.configure(n, tpdo_every=n)  # node 2 answers every 2nd SYNC
        for n in NODES:
            nmt, state, sw, pos = sim.state(n)
            assert (nmt, state, pos) == (0x7F, "switch on disabled", START[n])
        master.run()
        for n, node in master.nodes.items():
            node.state = "OPERATION ENABLED"
            assert node.statusword & 0x6F == 0x27
            # enabled where it stood: no jump
            assert sim.state(n)[3] == START[n]
        # CSP targets, applied at SYNC
        for n, node in master.nodes.items():
            node.rpdo[1]["Target position"].raw = START[n] + 2500 * n
        for n, node in master.nodes.items():
            wait_for(f"node {n} at its target",
                     lambda n=n, node=node: node.tpdo_values.get(0x6064) == START[n] + 2500 * n)
            assert node.statusword & 0x1000  # bit 12: follows the target
            assert sim.state(n)[1:] == ("operation enabled", 0x1237, START[n] + 2500 * n)
        time.sleep(20 * PERIOD_S)
    finally:
        master.stop()
        frames = rec.settle(0.2, 5.0)
        lost = rec.lost
        rec.close()
    assert lost == 0, f"the recorder's socket dropped {lost} frames"
    # TPDO1 of node n answers every n-th SYNC, once operational: the i-th
    # TPDO after the first answers the (i n)-th SYNC after the first's,
    # each late by at most 2 SYNCs (the drives' process answers a SYNC while
    # the next one may already be on the bus). Counted from the first TPDO,
    # whose own SYNC is not known (it may be late too): the TPDOs' lateness
    # relative to it, the first's 0 included, spans at most 2 SYNCs.
    for n in NODES:
        seen = [f for f in frames if f[1] in (0x080, 0x180 + n)]
        first = [f[1] for f in seen].index(0x180 + n)
        syncs, late = 0, []
        for _, cid, _ in seen[first + 1:]:
            if cid == 0x080:
                syncs += 1
            else:
                late.append(syncs - (len(late) + 1) * n)
        assert len(late) >= 10
        # A failure shows the frames from the one before the first TPDO on
        # (receive time in us after it, id).
        start = seen[first][0]
        around = [(round((t - start) / 1000), hex(cid)) for t, cid, _ in seen[max(0, first - 1):first + 8]]
        assert max(late + [0]) - min(late + [0]) <= 2, \
            f"node {n}: its TPDOs against every {n}-th SYNC: {late}; {around}"
        assert syncs - len(late) * n <= 2 + n  # none missing at the end
    # the RPDOs are controlword + target (6 bytes); SYNC empty
    assert all(len(f[2]) == 0 for f in frames if f[1] == 0x080)
    assert all(len(f[2]) == 6 for f in frames if f[1] in (0x201, 0x202))
    assert not master.emcy


def test_fault_emcy_and_reset(sim, master):
    for n in NODES:
        master.configure(n)
    master.run()
    node = master.nodes[1]
    node.state = "OPERATION ENABLED"
    sim.command("fault 1 0x2310")
    assert master.wait_emcy(1, 0x2310) == (1, 0x2310, 0x01)
    wait_for("node 1 in fault", lambda: node.state == "FAULT")
    assert node.sdo[0x603F].raw == 0x2310
    assert node.sdo[0x1001].raw & 0x01
    # fault reset (BaseNode402: 0x80, a rising edge after 0x0F), then enable
    node.state = "OPERATION ENABLED"
    assert master.wait_emcy(1, 0x0000) == (1, 0x0000, 0x00)
    assert node.sdo[0x603F].raw == 0
    assert sim.state(1)[1] == "operation enabled"
    # the other drive saw nothing
    assert not [e for e in master.emcy if e[0] == 2]


def test_sync_and_rpdo_length_mismatch(sim, master):
    # node 2 expects a SYNC counter (0x1019 = 10), node 1 an empty SYNC
    master.configure(1)
    master.configure(2, sdo_writes=[(0x1019, 0, 10)])
    for n in NODES:
        master.nodes[n].nmt.state = "OPERATIONAL"
    master.net.sync.transmit()  # empty: wrong for node 2
    assert master.wait_emcy(2, 0x8240)[2] & 0x10  # communication error
    master.net.sync.transmit(1)  # a counter: wrong for node 1
    assert master.wait_emcy(1, 0x8240)[2] & 0x10
    # RPDO1 is mapped to 6 bytes: 8 bytes (the old frames) and 4 bytes
    master.net.send_message(0x201, bytes(8))
    assert master.wait_emcy(1, 0x8220)
    master.net.send_message(0x202, bytes(4))
    assert master.wait_emcy(2, 0x8210)
    # neither was taken: still switch on disabled, target untouched
    assert sim.state(1)[1] == "switch on disabled"
    assert master.nodes[1].sdo[0x607A].raw == START[1]


def test_pdo_mapping_rules(sim, master):
    node = master.nodes[1]
    master.reset(1)
    # a valid PDO's mapping cannot change
    with pytest.raises(canopen.SdoAbortedError) as e:
        node.sdo[0x1600][0].raw = 0
    assert e.value.code == 0x06010000
    node.sdo[0x1400][1].raw = 0x80000201
    node.sdo[0x1600][0].raw = 0
    # not mappable (0x6065), a wrong length, more than 64 bits
    node.sdo[0x1600][1].raw = 0x60650020
    with pytest.raises(canopen.SdoAbortedError) as e:
        node.sdo[0x1600][0].raw = 1
    assert e.value.code == 0x06040041
    node.sdo[0x1600][1].raw = 0x607A0010
    with pytest.raises(canopen.SdoAbortedError) as e:
        node.sdo[0x1600][0].raw = 1
    assert e.value.code == 0x06040041
    for s, entry in enumerate([0x607A0020, 0x60B10020, 0x60400010], start=1):
        node.sdo[0x1600][s].raw = entry
    with pytest.raises(canopen.SdoAbortedError) as e:
        node.sdo[0x1600][0].raw = 3
    assert e.value.code == 0x06040042
    node.sdo[0x1600][0].raw = 2
    # only CSP: another mode is refused
    with pytest.raises(canopen.SdoAbortedError) as e:
        node.sdo[0x6060].raw = 1
    assert e.value.code == 0x06090030
    # reset communication brings the defaults back
    master.reset(1)
    assert node.sdo[0x1600][0].raw == 1
    assert node.sdo[0x1600][1].raw == 0x60400010


@pytest.mark.parametrize("reaction, option, want, emcy", [(1, 2, "fault", 0x8130),
                                                         (3, 6, "quick stop active", 0x8130)])
def test_lost_master(sim, master, reaction, option, want, emcy):
    """0x1016 watches the master's heartbeat (500 ms); when it falls
    silent the drive reacts as 0x6007 says: 1 fault, 3 quick stop (with
    0x605A = 6 the drive stays in quick stop active)."""
    node = master.nodes[1]
    master.configure(1, sdo_writes=[(0x1016, 1, MASTER_ID << 16 | 500), (0x6007, 0, reaction),
                                    (0x605A, 0, option)])
    master.configure(2)
    master.run()
    node.state = "OPERATION ENABLED"
    time.sleep(0.6)  # longer than the consumer time: the master is alive
    assert sim.state(1)[1] == "operation enabled"
    master.stop()  # heartbeat, SYNC and RPDOs gone
    wait_for(f"node 1 in {want}", lambda: sim.state(1)[1] == want)
    assert master.wait_emcy(1, emcy)
    assert sim.state(2)[1] == "switch on disabled"  # no consumer configured


def test_reboot(sim, master, vcan):
    rec = Recorder(IFACE)
    master.configure(1)
    master.run()
    master.nodes[1].state = "OPERATION ENABLED"
    sim.command("reboot 1")
    wait_for("node 1's boot-up", lambda: any(f[1] == 0x701 and bytes(f[2]) == b"\x00" for f in rec.frames))
    rec.close()
    nmt, state, _, _ = sim.state(1)
    assert (nmt, state) == (0x7F, "switch on disabled")
    assert master.nodes[1].sdo[0x1600][1].raw == 0x60400010  # the EDS's mapping again


def test_preop(sim, master, vcan):
    """preop N: the drive's heartbeat says pre-operational, and it sends no
    TPDO and takes no RPDO (the SYNCs go on) until an NMT start; SDO still
    answers."""
    master.configure(1)
    master.run()
    master.nodes[1].state = "OPERATION ENABLED"
    rec = Recorder(IFACE)
    sim.command("preop 1")
    wait_for("node 1's heartbeat in pre-operational",
             lambda: any(f[1] == 0x701 and bytes(f[2]) == b"\x7f" for f in rec.frames))
    quiet_from = len(rec.frames)
    before = sim.state(1)[3]
    master.nodes[1].rpdo[1]["Target position"].raw = before + 5000
    wait_for("ten SYNCs", lambda: sum(f[1] == 0x080 for f in rec.frames[quiet_from:]) >= 10)
    assert not [f for f in rec.frames[quiet_from:] if f[1] == 0x181], "a TPDO in pre-operational"
    assert sim.state(1)[0] == 0x7F and sim.state(1)[3] == before, "moved in pre-operational"
    assert master.nodes[1].sdo[0x6064].raw == before
    master.nodes[1].nmt.state = "OPERATIONAL"
    wait_for("node 1 at its target", lambda: sim.state(1)[3] == before + 5000)
    wait_for("a TPDO again", lambda: any(f[1] == 0x181 for f in rec.frames[quiet_from:]))
    rec.close()
