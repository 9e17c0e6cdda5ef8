# SPDX-License-Identifier: BSD-3-Clause
"""`kinctl candecode`: CAN frames decoded with kinctl's DBC (kinctl.dbc).

Reads a candump log (`candump -L` lines "(t) iface ID#DATA", or candump's
default "  iface  ID   [n]  11 22 ..." lines) or a live interface, and prints
one line a frame:

    (1700000000.000123) vcan0 201 RPDO1_Node1 Controlword_6040=0x000f enable_operation TargetPosition_607A=1234
    (1700000000.000124) vcan0 603 SDORequest_Node3 Command=Download1 Index=0x6060 Subindex=0 Data=0x00000008

the statusword with its CiA 402 power state and named bits, the controlword
with its command, SDO indexes, data and EMCY codes in hex; or, with --json,
one JSON object a line ({"t", "interface", "id", "name", "signals", "data"};
signal values as numbers, or the DBC's names for the values it names; name
null for a frame the DBC does not know or whose length it does not allow).
An empty SYNC (0x1019 = 0) decodes as SYNC with no signals.
"""
import json
import re
import sys
import time

from kinctl import canraw, dbc

LOG_LINE = re.compile(r"^\s*\((?P<t>[0-9.]+)\)\s+(?P<iface>\S+)\s+(?P<id>[0-9A-Fa-f]+)#(?P<data>[0-9A-Fa-f]*)\s*$")
PLAIN_LINE = re.compile(r"^\s*(?:\((?P<t>[0-9.]+)\)\s+)?(?P<iface>\S+)\s+(?P<id>[0-9A-Fa-f]+)\s+\[(?P<n>\d)\]"
                        r"(?P<data>(?:\s+[0-9A-Fa-f]{2})*)\s*$")


def parse_line(line):
    """(t or None, interface, id, data bytes) of one candump line, or None."""
    m = LOG_LINE.match(line)
    if m:
        return float(m["t"]), m["iface"], int(m["id"], 16), bytes.fromhex(m["data"])
    m = PLAIN_LINE.match(line)
    if m:
        data = bytes.fromhex("".join(m["data"].split()))
        if len(data) != int(m["n"]):
            return None
        return (float(m["t"]) if m["t"] else None), m["iface"], int(m["id"], 16), data
    return None


HEX_SIGNALS = {"Index": 4, "Data": 8, "ErrorCode_603F": 4, "ErrorRegister_1001": 2, "VendorData": 10}


def decode(db, can_id, data):
    """(message name, {signal: value}) or (None, None) for a frame the DBC
    does not describe (or whose length it does not allow: the message's,
    or down to dbc.min_length where the DBC says so, a frame's missing
    signals then absent)."""
    try:
        msg = db.get_message_by_frame_id(can_id)
    except KeyError:
        return None, None
    if not dbc.min_length(msg) <= len(data) <= msg.length:
        return None, None
    signals = msg.decode(data, decode_choices=True, allow_truncated=len(data) < msg.length)
    return msg.name, {k: (str(v) if not isinstance(v, (int, float)) else v) for k, v in signals.items()}


def signal_text(name, value):
    """One signal as the text line shows it."""
    if isinstance(value, str):
        return value
    if name.startswith("Statusword"):
        return dbc.statusword_text(int(value))
    if name.startswith("Controlword"):
        return dbc.controlword_text(int(value))
    if name in HEX_SIGNALS:
        return f"0x{int(value):0{HEX_SIGNALS[name]}x}"
    return f"{value}"


def format_frame(t, iface, can_id, data, name, signals, as_json):
    if as_json:
        return json.dumps({"t": t, "interface": iface, "id": can_id, "name": name, "signals": signals,
                           "data": data.hex()})
    head = (f"({t:.6f}) " if t is not None else "") + f"{iface} {can_id:03X}"
    if name is None:
        return f"{head} ? {data.hex(' ')}"
    return " ".join([head, name] + [f"{k}={signal_text(k, v)}" for k, v in signals.items()])


def live_frames(interface, count=None, duration=None):
    """(t, interface, id, data) from the interface, t the kernel's receive
    timestamp in seconds."""
    s = canraw.open_raw(interface)
    end = None if duration is None else time.monotonic() + duration
    seen = 0
    try:
        while (count is None or seen < count) and (end is None or time.monotonic() < end):
            got = canraw.receive(s)
            if got is None:
                continue
            seen += 1
            t_ns, can_id, data, _ = got
            yield t_ns * 1e-9, interface, can_id, data
    finally:
        s.close()


def run(args):
    if args.nodes is not None or args.master is not None:
        from kinctl.argtypes import parse_nodes
        db = dbc.load(nodes=parse_nodes(args.nodes) if args.nodes else None, master=args.master)
    else:
        db = dbc.load(args.dbc)
    if args.interface:
        source = live_frames(args.interface, args.count, args.duration)
    else:
        f = sys.stdin if args.log in (None, "-") else open(args.log, encoding="utf-8")
        source = (p for p in (parse_line(line) for line in f) if p is not None)
    unknown = 0
    for n, (t, iface, can_id, data) in enumerate(source):
        if args.count is not None and n >= args.count:
            break
        name, signals = decode(db, can_id, data)
        unknown += name is None
        print(format_frame(t, iface, can_id, data, name, signals, args.json), flush=args.interface is not None)
    return 1 if unknown and args.strict else 0
