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
    db = dbc.load()
    # RPDO1 of node 5: int32 target then int32 velocity offset, little-endian.
    m = db.decode_message(0x205, struct.pack("<ii", -123456, 7890))
    assert m == {"TargetPosition_607A": -123456, "VelocityOffset_60B1": 7890}
    m = db.decode_message(0x185, struct.pack("<iH", 2 ** 31 - 1, 0x3237))
    assert m == {"PositionActual_6064": 2 ** 31 - 1, "Statusword_6041": 0x3237}
    assert db.decode_message(0x080, b"\xf0") == {"Counter": 240}
    assert str(db.decode_message(0x77F, b"\x05")["NMTState"]) == "Operational"
    assert str(db.decode_message(0x710, b"\x7f")["NMTState"]) == "PreOperational"
    assert len(db.messages) == 1 + 16 * 3 + 1


def test_make_dbc_other_ids_and_refusals():
    db = dbc.load(nodes=[20, 21], master=1)
    assert {m.frame_id for m in db.messages} == {0x080, 0x214, 0x215, 0x194, 0x195, 0x714, 0x715, 0x701}
    with pytest.raises(ValueError):
        dbc.make_dbc([1, 2], master=2)
    with pytest.raises(ValueError):
        dbc.make_dbc([0])


def test_candecode_log_formats(tmp_path):
    log = tmp_path / "x.log"
    log.write_text("(1700000000.000100) vcan0 080#05\n"
                   "(1700000000.000200) vcan0 201#40E2010000000000\n"
                   "  vcan0  181   [6]  E8 03 00 00 37 12\n"
                   "(1700000000.000300) vcan0 123#DEADBEEF\n"
                   "not a frame\n")
    r = run("candecode", str(log), "--json")
    assert r.returncode == 0, r.stderr
    rows = [json.loads(line) for line in r.stdout.splitlines()]
    assert [x["name"] for x in rows] == ["SYNC", "RPDO1_Node1", "TPDO1_Node1", None]
    assert rows[1]["signals"] == {"TargetPosition_607A": 123456, "VelocityOffset_60B1": 0}
    assert rows[2]["t"] is None and rows[2]["signals"]["Statusword_6041"] == 0x1237
    text = run("candecode", str(log))
    assert "TPDO1_Node1 PositionActual_6064=1000 Statusword_6041=0x1237 follows" in text.stdout
    assert run("candecode", str(log), "--strict").returncode == 1  # 0x123 is not kinctl's
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
