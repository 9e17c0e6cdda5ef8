# SPDX-License-Identifier: BSD-3-Clause
"""`kinctl drivesim`'s drives (kinctl.drive402) met by a CANopen master on
python-can's in-process virtual bus (no kernel CAN needed): python canopen's
SDO client writes what kinctld's boot writes (daemon/README.md), each read
back from the drive, then NMT start,
SYNC with and without the counter, the controlword's walk to operation
enabled through RPDO1, the velocity offset through RPDO2, TPDO1 every N-th
SYNC, the software position limits. The same drives on vcan under kinctld
are tests/vcan's."""
import itertools
import json
import struct
import subprocess
import sys
import time

import pytest

canopen = pytest.importorskip("canopen")

from kinctl import dbc, drive402  # noqa: E402

NODE = 3
START = 4123
_channels = itertools.count()


def wait_for(pred, timeout=3.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        got = pred()
        if got:
            return got
        time.sleep(0.005)
    return pred()


class Master:
    """A canopen.Network on the virtual channel: SDO client of the drive at
    NODE and a recorder of every frame."""

    def __init__(self, channel):
        import can
        self.wire = can.Bus(interface="virtual", channel=channel, receive_own_messages=False)
        self.log = can.BufferedReader()
        self.notifier = can.Notifier(self.wire, [self.log])  # every frame, the master's too
        self.net = canopen.Network()
        self.net.connect(interface="virtual", channel=channel, receive_own_messages=False)
        self.frames = []
        for cid in range(0x800):
            if not 0x580 < cid < 0x600:
                self.net.subscribe(cid, lambda cid, data, t: self.frames.append((cid, bytes(data))))
        self.node = canopen.RemoteNode(NODE, drive402.default_eds())
        self.net.add_node(self.node)

    def write(self, index, sub, value, size):
        """An expedited SDO download, then its upload: the value read back."""
        raw = value.to_bytes(size, "little", signed=value < 0)
        self.node.sdo.download(index, sub, raw)
        return int.from_bytes(self.node.sdo.upload(index, sub), "little", signed=value < 0)

    def read(self, index, sub, signed=False):
        return int.from_bytes(self.node.sdo.upload(index, sub), "little", signed=signed)

    def sent(self, cid):
        return [d for c, d in self.frames if c == cid]

    def sync(self, counter=None):
        self.net.send_message(0x080, b"" if counter is None else bytes([counter]))

    def candump(self, path):
        """Every frame on the bus so far as `candump -L` writes them."""
        with open(path, "w", encoding="utf-8") as f:
            while (msg := self.log.get_message(0.0)) is not None:
                f.write(f"({msg.timestamp:.6f}) vcan0 {msg.arbitration_id:03X}#{bytes(msg.data).hex().upper()}\n")

    def close(self):
        self.notifier.stop()
        self.wire.shutdown()
        self.net.disconnect()


@pytest.fixture
def bus():
    channel = f"kinctl-drivesim-{next(_channels)}"
    made = []

    def start(**kwargs):
        master = Master(channel)
        sim = drive402.Drives(channel, [NODE], start_counts={NODE: START}, interface="virtual", **kwargs)
        made.append((master, sim))
        return master, sim
    yield start
    for master, sim in made:
        sim.close()
        master.close()


def configure(m, sync_counter=0, tpdo_every=1, velocity_offset=True):
    """What kinctld's boot writes (CiA 301's order for the mapping, 0x1019
    while 0x1006 is 0), each write checked by reading it back."""
    writes = [(0x1400, 1, 0x80000200 + NODE, 4), (0x1400, 2, 1, 1), (0x1600, 0, 0, 1),
              (0x1600, 1, 0x60400010, 4), (0x1600, 2, 0x607A0020, 4), (0x1600, 0, 2, 1), (0x1400, 1, 0x200 + NODE, 4)]
    if velocity_offset:
        writes += [(0x1401, 1, 0x80000300 + NODE, 4), (0x1401, 2, 1, 1), (0x1601, 0, 0, 1),
                   (0x1601, 1, 0x60B10020, 4), (0x1601, 0, 1, 1), (0x1401, 1, 0x300 + NODE, 4)]
    writes += [(0x1800, 1, 0x80000180 + NODE, 4), (0x1800, 2, tpdo_every, 1), (0x1A00, 0, 0, 1),
               (0x1A00, 1, 0x60410010, 4), (0x1A00, 2, 0x60640020, 4), (0x1A00, 0, 2, 1), (0x1800, 1, 0x180 + NODE, 4),
               (0x6060, 0, 8, 1), (0x60C2, 1, 2, 1), (0x60C2, 2, -3, 1), (0x1019, 0, sync_counter, 1),
               (0x1006, 0, 2000, 4), (0x1017, 0, 100, 2), (0x1016, 1, (127 << 16) | 300, 4),
               (0x6007, 0, 3, 2), (0x6065, 0, 5000, 4), (0x607D, 1, -100000, 4), (0x607D, 2, 100000, 4),
               (0x605A, 0, 2, 2)]
    for index, sub, value, size in writes:
        assert m.write(index, sub, value, size) == value, f"0x{index:04X}:{sub:02X} read back"


def tpdo1(m):
    """(statusword, actual) of every TPDO1 so far."""
    return [struct.unpack("<Hi", d) for d in m.sent(0x180 + NODE)]


def test_boot_configure_enable_move(bus, tmp_path):
    m, sim = bus()
    d = sim.drives[NODE]
    assert wait_for(lambda: m.sent(0x700 + NODE)) == [b"\x00"]  # boot-up
    assert d.nmt == drive402.NMT_PRE_OPERATIONAL
    assert m.read(0x1000, 0) & 0xFFFF == 0x0192
    configure(m, sync_counter=0, tpdo_every=2)
    assert m.read(0x6061, 0) == 8  # mode display follows 0x6060
    assert wait_for(lambda: m.sent(0x700 + NODE)[1:]) and m.sent(0x700 + NODE)[1] == b"\x7f"  # 0x1017: heartbeats

    # PDOs only in operational: a SYNC now answers nothing.
    m.sync()
    time.sleep(0.05)
    assert tpdo1(m) == []
    m.net.send_message(0x000, bytes([0x01, NODE]))
    assert wait_for(lambda: d.nmt == drive402.NMT_OPERATIONAL)

    def cycle(cw, target, n=2):
        """n bus cycles: RPDO1 then SYNC (the drive applies it at the SYNC)."""
        for _ in range(n):
            m.net.send_message(0x200 + NODE, struct.pack("<Hi", cw, target))
            m.sync()
            time.sleep(0.01)

    # TPDO1 at every 2nd SYNC (transmission type 2).
    cycle(0x00, START, n=4)
    assert wait_for(lambda: len(tpdo1(m)) == 2)
    assert tpdo1(m)[-1] == (0x0240, START)  # switch on disabled, remote, at its power-on position
    for cw, state_bits in ((0x06, 0x21), (0x07, 0x23), (0x0F, 0x27)):
        cycle(cw, START)
        assert wait_for(lambda: tpdo1(m)[-1][0] & 0x6F == state_bits), (hex(cw), tpdo1(m)[-1])
    assert tpdo1(m)[-1] == (0x1237, START)  # enabled, voltage, no quick stop, remote, follows: no jump

    m.net.send_message(0x300 + NODE, struct.pack("<i", -777))  # RPDO2: velocity offset
    cycle(0x0F, START + 2500)
    assert wait_for(lambda: tpdo1(m)[-1][1] == START + 2500)
    assert m.read(0x60B1, 0, signed=True) == -777

    # Beyond 0x607D's max: held at the limit, bit 11 (internal limit active).
    cycle(0x0F, 150000)
    assert wait_for(lambda: tpdo1(m)[-1] == (0x1237 | 1 << 11, 100000))
    # Quick stop (0x605A = 2: switch on disabled once stopped), then fault reset from a fault.
    cycle(0x02, 100000)
    assert wait_for(lambda: tpdo1(m)[-1][0] & 0x4F == 0x40)
    assert sim.command(f"fault {NODE} 0x5530") == f"ok fault {NODE} 0x5530"
    emcy = wait_for(lambda: m.sent(0x080 + NODE))
    assert struct.unpack_from("<HB", emcy[-1]) == (0x5530, 0x01)
    cycle(0x00, 100000, n=1)
    cycle(0x80, 100000, n=1)
    assert wait_for(lambda: struct.unpack_from("<H", m.sent(0x080 + NODE)[-1]) == (0x0000,))
    assert d.state == drive402.SWITCH_ON_DISABLED

    # The whole sequence, as candump would log it, decodes with the DBC.
    log = tmp_path / "boot.log"
    m.candump(log)
    r = subprocess.run([sys.executable, "-m", "kinctl", "candecode", "--strict", "--json", str(log)],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stdout + r.stderr
    names = [json.loads(line)["name"] for line in r.stdout.splitlines()]
    for kind in ("NMT", "SYNC", "SDORequest_Node3", "SDOResponse_Node3", "RPDO1_Node3", "RPDO2_Node3", "TPDO1_Node3",
                 "EMCY_Node3", "Heartbeat_Node3"):
        assert kind in names, kind
    assert names.count("SDORequest_Node3") == names.count("SDOResponse_Node3")


def test_sync_length_follows_0x1019(bus):
    m, sim = bus()
    d = sim.drives[NODE]
    configure(m, sync_counter=4, velocity_offset=False)
    m.net.send_message(0x000, bytes([0x01, 0]))  # start all
    assert wait_for(lambda: d.nmt == drive402.NMT_OPERATIONAL)
    for k in range(1, 5):
        m.sync(counter=k)
    assert wait_for(lambda: len(tpdo1(m)) == 4)
    assert m.sent(0x080 + NODE) == []
    m.sync()  # empty, where 0x1019 = 4 wants a counter: not processed, EMCY 0x8240
    emcy = wait_for(lambda: m.sent(0x080 + NODE))
    assert struct.unpack_from("<HB", emcy[0]) == (drive402.EMCY_SYNC_LENGTH, 0x10)  # communication error
    time.sleep(0.05)
    assert len(tpdo1(m)) == 4


def test_lost_master(bus):
    """0x1016:1 = 127 << 16 | 300 ms: heartbeats of the master every 100 ms
    keep the drive enabled; 300 ms without one raise EMCY 0x8130 and 0x6007
    = 3's quick stop (0x605A = 2: switch on disabled)."""
    m, sim = bus()
    d = sim.drives[NODE]
    configure(m, velocity_offset=False)
    m.net.send_message(0x000, bytes([0x01, NODE]))
    assert wait_for(lambda: d.nmt == drive402.NMT_OPERATIONAL)
    for cw in (0x06, 0x07, 0x0F):
        m.net.send_message(0x200 + NODE, struct.pack("<Hi", cw, START))
        m.sync()
        time.sleep(0.02)
    assert wait_for(lambda: d.state == drive402.ENABLED)
    for _ in range(8):  # 0.8 s of heartbeats every 100 ms
        m.net.send_message(0x77F, b"\x05")
        time.sleep(0.1)
    assert m.sent(0x080 + NODE) == [] and d.state == drive402.ENABLED
    silent_from = time.monotonic()
    emcy = wait_for(lambda: m.sent(0x080 + NODE), timeout=2.0)
    assert 0.2 < time.monotonic() - silent_from < 1.0
    assert struct.unpack_from("<HB", emcy[0]) == (drive402.EMCY_HEARTBEAT, 0x10)
    assert d.state == drive402.SWITCH_ON_DISABLED


def test_reset_communication_restores_power_on_values(bus):
    m, sim = bus(period_s=0.0025, heartbeat_ms=50, window=300, configured=True)
    d = sim.drives[NODE]
    assert wait_for(lambda: m.sent(0x700 + NODE))
    assert [m.read(0x60C2, 1), m.read(0x60C2, 2, signed=True), m.read(0x1006, 0)] == [25, -4, 0]
    assert [m.read(0x1017, 0), m.read(0x6065, 0), m.read(0x6060, 0)] == [50, 300, 8]
    assert [m.read(0x1600, s) for s in range(3)] == [2, 0x60400010, 0x607A0020]
    assert [m.read(0x1A00, s) for s in range(3)] == [2, 0x60410010, 0x60640020]
    assert [m.read(0x1400, 1), m.read(0x1800, 1), m.read(0x1800, 2)] == [0x200 + NODE, 0x180 + NODE, 1]
    assert m.write(0x1017, 0, 20, 2) == 20
    m.net.send_message(0x000, bytes([0x82, NODE]))  # reset communication: boot-up, the power-on values
    assert wait_for(lambda: m.sent(0x700 + NODE).count(b"\x00") == 2)
    assert m.read(0x1017, 0) == 50 and d.nmt == drive402.NMT_PRE_OPERATIONAL
    # 0x1019 only while 0x1006 is 0, and only 0 or 2..240 (CiA 301).
    assert m.write(0x1006, 0, 2500, 4) == 2500
    for value, code in ((4, 0x08000022), (1, 0x06090030), (241, 0x06090030)):
        with pytest.raises(canopen.SdoAbortedError) as e:
            m.node.sdo.download(0x1019, 0, bytes([value]))
        assert e.value.code == code, value
    assert m.write(0x1006, 0, 0, 4) == 0 and m.write(0x1019, 0, 4, 1) == 4
    # A valid PDO is not remapped (CiA 301): abort 0x06010000 (unsupported access).
    with pytest.raises(canopen.SdoAbortedError) as e:
        m.node.sdo.download(0x1600, 0, b"\x00")
    assert e.value.code == 0x06010000


def trimmed_eds(path, drop):
    """The shipped EDS without the objects in drop (and their sub-indices)."""
    import re
    text = open(drive402.default_eds(), encoding="utf-8").read()
    sections = re.split(r"(?m)^(?=\[)", text)
    keep = [sec for sec in sections
            if not any(sec.startswith(f"[{i:04X}]") or sec.startswith(f"[{i:04X}sub") for i in drop)]
    path.write_text("".join(keep))
    return str(path)


def test_an_eds_without_the_optional_objects(bus, tmp_path):
    """A drive whose EDS has only the objects CSP needs: the master's writes
    to the others are refused (abort 0x06020000, no such object), and the
    drive still boots, enables and moves with the standard's defaults."""
    optional = (0x1006, 0x1016, 0x1019, 0x6007, 0x605A, 0x6065, 0x607D, 0x60C2, 0x6502)
    m, sim = bus(eds=trimmed_eds(tmp_path / "bare.eds", optional))
    d = sim.drives[NODE]
    assert wait_for(lambda: m.sent(0x700 + NODE))
    for index in optional:
        with pytest.raises(canopen.SdoAbortedError) as e:
            m.node.sdo.download(index, 1 if index in (0x1016, 0x607D, 0x60C2) else 0, b"\x00")
        assert e.value.code == 0x06020000, hex(index)
    for index, sub, value, size in [(0x1400, 1, 0x80000200 + NODE, 4), (0x1600, 0, 0, 1), (0x1600, 1, 0x60400010, 4),
                                    (0x1600, 2, 0x607A0020, 4), (0x1600, 0, 2, 1), (0x1400, 1, 0x200 + NODE, 4),
                                    (0x1400, 2, 1, 1), (0x1800, 1, 0x80000180 + NODE, 4), (0x1A00, 0, 0, 1),
                                    (0x1A00, 1, 0x60410010, 4), (0x1A00, 2, 0x60640020, 4), (0x1A00, 0, 2, 1),
                                    (0x1800, 2, 1, 1), (0x1800, 1, 0x180 + NODE, 4), (0x6060, 0, 8, 1)]:
        assert m.write(index, sub, value, size) == value
    m.net.send_message(0x000, bytes([0x01, NODE]))
    assert wait_for(lambda: d.nmt == drive402.NMT_OPERATIONAL)
    for cw, target in ((0x06, START), (0x07, START), (0x0F, START), (0x0F, START - 900)):
        m.net.send_message(0x200 + NODE, struct.pack("<Hi", cw, target))
        m.sync()
        time.sleep(0.02)
    assert wait_for(lambda: tpdo1(m) and tpdo1(m)[-1] == (0x1237, START - 900))
    m.net.send_message(0x200 + NODE, struct.pack("<Hi", 0x02, START - 900))  # quick stop: 0x605A's default 2
    m.sync()
    assert wait_for(lambda: d.state == drive402.SWITCH_ON_DISABLED)


def test_interpolation_period():
    assert drive402.interpolation_period(0.001) == (1, -3)
    assert drive402.interpolation_period(0.0005) == (5, -4)
    assert drive402.interpolation_period(0.000250) == (25, -5)
    assert drive402.interpolation_period(0.2) == (200, -3)
    for bad in (0.0000005, 0.3, 0.256):
        with pytest.raises(ValueError):
            drive402.interpolation_period(bad)


# CiA 402-2's device control table: (from, controlword, to), written out here
# from the standard's transitions 2..16, apart from next_state's code.
TRANSITIONS = [
    (drive402.SWITCH_ON_DISABLED, 0x06, drive402.READY),            # 2
    (drive402.READY, 0x07, drive402.SWITCHED_ON),                   # 3
    (drive402.SWITCHED_ON, 0x0F, drive402.ENABLED),                 # 4
    (drive402.ENABLED, 0x07, drive402.SWITCHED_ON),                 # 5
    (drive402.SWITCHED_ON, 0x06, drive402.READY),                   # 6
    (drive402.READY, 0x00, drive402.SWITCH_ON_DISABLED),            # 7
    (drive402.ENABLED, 0x06, drive402.READY),                       # 8
    (drive402.ENABLED, 0x00, drive402.SWITCH_ON_DISABLED),          # 9
    (drive402.SWITCHED_ON, 0x02, drive402.SWITCH_ON_DISABLED),      # 10
    (drive402.ENABLED, 0x02, drive402.QUICK_STOP),                  # 11
    (drive402.QUICK_STOP, 0x00, drive402.SWITCH_ON_DISABLED),       # 12
    (drive402.SWITCH_ON_DISABLED, 0x0F, drive402.SWITCH_ON_DISABLED),
    (drive402.READY, 0x02, drive402.SWITCH_ON_DISABLED),
    (drive402.ENABLED, 0x0F, drive402.ENABLED),
]


@pytest.mark.parametrize("state, cw, expect", TRANSITIONS)
def test_power_state_machine(state, cw, expect):
    assert drive402.next_state(state, cw, 0x00, 6) == expect


def test_fault_reset_needs_a_rising_edge():
    assert drive402.next_state(drive402.FAULT, 0x80, 0x00, 2) == drive402.SWITCH_ON_DISABLED  # 15
    assert drive402.next_state(drive402.FAULT, 0x80, 0x80, 2) == drive402.FAULT
    assert drive402.next_state(drive402.FAULT, 0x0F, 0x00, 2) == drive402.FAULT


def test_statusword_states_decode():
    """The simulator's statusword of each state reads back as that state
    through the DBC module's CiA 402 masks (the decoder's own table)."""
    for state, bits in drive402.STATE_BITS.items():
        assert dbc.statusword_state(bits | drive402.SW_REMOTE) == state.replace(" ", "_"), state
