# SPDX-License-Identifier: BSD-3-Clause
"""The CAN tools that need no CAN interface: the DBC shipped with the package
is make_dbc()'s and decodes kinctld's frames as can_io.h lays them out,
`kinctl candecode` on candump logs, `kinctl drivesim`'s command line (its
drives: test_drivesim.py). On a real interface they run in tests/vcan."""
import json
import struct
import subprocess
import sys

import pytest

from kinctl import dbc
from kinctl.argtypes import parse_nodes
from kinctl.candecode import parse_line


def run(*args, stdin=None):
    return subprocess.run([sys.executable, "-m", "kinctl"] + list(args), capture_output=True, text=True,
                          input=stdin, timeout=60)


def test_shipped_dbc_is_generated():
    with open(dbc.repo_dbc_path(), encoding="utf-8") as f:
        assert f.read() == dbc.make_dbc()


def test_dbc_decodes_kinctld_layout():
    """Each frame of the contract (daemon/README.md) packed here by hand,
    little-endian, and decoded through the shipped DBC."""
    db = dbc.load()
    # RPDO1 of node 5: controlword u16, target position i32; RPDO2: velocity offset i32.
    assert db.decode_message(0x205, struct.pack("<Hi", 0x000F, -123456)) == {
        "Controlword_6040": 0x000F, "TargetPosition_607A": -123456}
    assert db.decode_message(0x305, struct.pack("<i", -7890)) == {"VelocityOffset_60B1": -7890}
    # TPDO1: statusword u16, position actual i32.
    assert db.decode_message(0x185, struct.pack("<Hi", 0x1237, 2 ** 31 - 1)) == {
        "Statusword_6041": 0x1237, "PositionActual_6064": 2 ** 31 - 1}
    assert db.decode_message(0x080, b"\xf0") == {"Counter": 240}
    m = db.decode_message(0x000, bytes([0x82, 3]))
    assert (str(m["Command"]), m["Node"]) == ("ResetCommunication", 3)
    assert str(db.decode_message(0x000, bytes([0x01, 0]))["Command"]) == "Start"
    m = db.decode_message(0x083, struct.pack("<HB5s", 0x8240, 0x11, b"\x01\x02\x03\x04\x05"))
    assert str(m["ErrorCode_603F"]) == "SyncLengthUnexpected" and m["ErrorRegister_1001"] == 0x11
    assert m["VendorData"] == 0x0504030201
    assert db.decode_message(0x083, struct.pack("<HB5x", 0x5530, 0x01), decode_choices=False)[
        "ErrorCode_603F"] == 0x5530
    # SDO: download 1 byte 0x6060:00 = 8; its response; an abort with its code.
    m = db.decode_message(0x603, struct.pack("<BHBI", 0x2F, 0x6060, 0, 8))
    assert (str(m["Command"]), m["Index"], m["Subindex"], m["Data"]) == ("Download1", 0x6060, 0, 8)
    m = db.decode_message(0x583, struct.pack("<BHBI", 0x80, 0x6060, 0, 0x06090030))
    assert (str(m["Command"]), m["Index"], m["Data"]) == ("Abort", 0x6060, 0x06090030)
    m = db.decode_message(0x583, struct.pack("<BHBI", 0x43, 0x1000, 0, 0x00020192))
    assert (str(m["Command"]), m["Data"]) == ("Upload4", 0x00020192)
    assert str(db.decode_message(0x77F, b"\x05")["NMTState"]) == "Operational"
    assert str(db.decode_message(0x710, b"\x7f")["NMTState"]) == "PreOperational"
    # NMT, SYNC, and per drive EMCY, TPDO1, RPDO1, RPDO2, SDO both ways and
    # heartbeat, and the master's heartbeat.
    assert len(db.messages) == 2 + 16 * 7 + 1
    assert {m.length for m in db.messages if 0x200 < m.frame_id < 0x280} == {6}
    assert dbc.min_length(db.get_message_by_frame_id(0x080)) == 0
    assert {dbc.min_length(m) == m.length for m in db.messages if m.frame_id != 0x080} == {True}


def test_make_dbc_other_ids_and_refusals():
    db = dbc.load(nodes=[20, 21], master=1)
    per_node = (0x080, 0x180, 0x200, 0x300, 0x580, 0x600, 0x700)
    assert {m.frame_id for m in db.messages} == {0x000, 0x080, 0x701} | {b + n for b in per_node for n in (20, 21)}
    with pytest.raises(ValueError):
        dbc.make_dbc([1, 2], master=2)
    with pytest.raises(ValueError):
        dbc.make_dbc([0])


def test_statusword_and_controlword_text():
    assert dbc.statusword_text(0x1237) == "0x1237 operation_enabled follows"
    assert dbc.statusword_text(0x0250) == "0x0250 switch_on_disabled"
    assert dbc.statusword_text(0x0231) == "0x0231 ready_to_switch_on"
    assert dbc.statusword_text(0x0218) == "0x0218 fault"
    assert dbc.statusword_text(0x3A37) == "0x3a37 operation_enabled internal_limit,follows,following_error"
    assert dbc.statusword_text(0x0217) == "0x0217 quick_stop_active"
    assert [dbc.controlword_text(c) for c in (0x06, 0x07, 0x0F, 0x00, 0x02, 0x80, 0x8F)] == [
        "0x0006 shutdown", "0x0007 switch_on", "0x000f enable_operation", "0x0000 disable_voltage",
        "0x0002 quick_stop", "0x0080 fault_reset", "0x008f fault_reset"]


# A boot and a first bus cycle of node 1 as candump -L writes them (the
# contract's frames, written out by hand), an empty SYNC among them.
BOOT_LOG = """\
(1700000000.000100) vcan0 000#8201
(1700000000.000200) vcan0 701#00
(1700000000.000300) vcan0 601#4000100000000000
(1700000000.000400) vcan0 581#4300100092010200
(1700000000.000500) vcan0 601#2F60600008000000
(1700000000.000600) vcan0 581#6060600000000000
(1700000000.000700) vcan0 601#2B17100064000000
(1700000000.000800) vcan0 581#8017100000000206
(1700000000.000900) vcan0 000#0101
(1700000000.001000) vcan0 080#
(1700000000.001010) vcan0 201#0F0040E20100
(1700000000.001020) vcan0 301#CEFFFFFF
(1700000000.001100) vcan0 181#3712E8030000
(1700000000.001200) vcan0 081#3055010000000000
(1700000000.001300) vcan0 77F#05
  vcan0  080   [1]  07
(1700000000.001400) vcan0 201#40E2010000000000
(1700000000.001500) vcan0 123#DEADBEEF
not a frame
"""


def test_candecode_boot_log(tmp_path):
    log = tmp_path / "boot.log"
    log.write_text(BOOT_LOG)
    r = run("candecode", str(log), "--json")
    assert r.returncode == 0, r.stderr
    rows = [json.loads(line) for line in r.stdout.splitlines()]
    assert [x["name"] for x in rows] == [
        "NMT", "Heartbeat_Node1", "SDORequest_Node1", "SDOResponse_Node1", "SDORequest_Node1", "SDOResponse_Node1",
        "SDORequest_Node1", "SDOResponse_Node1", "NMT", "SYNC", "RPDO1_Node1", "RPDO2_Node1", "TPDO1_Node1",
        "EMCY_Node1", "Heartbeat_Master", "SYNC", None, None]  # an 8-byte RPDO1 is not the contract's
    assert rows[0]["signals"] == {"Command": "ResetCommunication", "Node": 1}
    assert rows[3]["signals"] == {"Command": "Upload4", "Index": 0x1000, "Subindex": 0, "Data": 0x00020192}
    assert rows[7]["signals"]["Command"] == "Abort" and rows[7]["signals"]["Data"] == 0x06020000
    assert rows[9]["signals"] == {} and rows[9]["data"] == ""  # the empty SYNC
    assert rows[10]["signals"] == {"Controlword_6040": 0x000F, "TargetPosition_607A": 123456}
    assert rows[11]["signals"] == {"VelocityOffset_60B1": -50}
    assert rows[12]["signals"] == {"Statusword_6041": 0x1237, "PositionActual_6064": 1000}
    assert rows[13]["signals"]["ErrorRegister_1001"] == 1 and rows[13]["signals"]["ErrorCode_603F"] == 0x5530
    assert rows[15]["t"] is None and rows[15]["signals"] == {"Counter": 7}
    text = run("candecode", str(log)).stdout.splitlines()
    assert text[4] == ("(1700000000.000500) vcan0 601 SDORequest_Node1 Command=Download1 Index=0x6060 Subindex=0 "
                       "Data=0x00000008")
    assert text[9] == "(1700000000.001000) vcan0 080 SYNC"
    assert text[10].endswith("RPDO1_Node1 Controlword_6040=0x000f enable_operation TargetPosition_607A=123456")
    assert text[12].endswith("TPDO1_Node1 Statusword_6041=0x1237 operation_enabled follows PositionActual_6064=1000")
    assert text[13].endswith("EMCY_Node1 ErrorCode_603F=0x5530 ErrorRegister_1001=0x01 VendorData=0x0000000000")
    assert text[16].endswith("201 ? 40 e2 01 00 00 00 00 00")
    assert run("candecode", str(log), "--strict").returncode == 1  # 0x123 and the long RPDO1 are not kinctl's
    assert parse_line("(1.0) can0 7FF#") == (1.0, "can0", 0x7FF, b"")


def test_drivesim_bad_input():
    with pytest.raises(ValueError):
        parse_nodes("0-3")
    with pytest.raises(ValueError):
        parse_nodes("1,1")
    assert parse_nodes("1-3,7") == [1, 2, 3, 7]
    r = run("drivesim", "--nodes", "x")
    assert r.returncode == 2 and "node" in r.stderr
    r = run("drivesim", "--period-ms", "0.0005", "--interface", "no-such-can")
    assert r.returncode == 2 and "0x60C2" in r.stderr
    r = run("drivesim", "--start", "9=5", "--nodes", "1-3", "--interface", "no-such-can")
    assert r.returncode == 2 and "not in --nodes" in r.stderr
    r = run("drivesim", "--help")
    assert r.returncode == 0 and "kinctl drivesim --interface vcan0" in r.stdout and "--configured" in r.stdout
    assert run("drive402", "--help").returncode == 2  # one simulator, one name
    r = run("candecode", "--help")
    assert r.returncode == 0 and "candump -L vcan0 | kinctl candecode" in r.stdout
