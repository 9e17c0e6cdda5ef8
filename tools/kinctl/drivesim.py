# SPDX-License-Identifier: BSD-3-Clause
"""A CiA 402-style drive simulator on a SocketCAN interface (python-can).

Any number of drives (node ids), each in cyclic synchronous position mode as
kinctld drives them (daemon/can_io.h, tools/kinctl/kinctl.dbc):

  - an RPDO1 (0x200 + node: target position 0x607A, velocity offset 0x60B1,
    int32 counts and counts/s) is latched and acted on at the next SYNC
    (0x080), as a synchronous RPDO;
  - at each SYNC the drive moves toward its target over one bus cycle
    (period_s): with lag_s = 0 and no limits it reaches it exactly, else a
    first-order lag of lag_s with its speed limited to vmax (counts/s) and
    its acceleration to amax (counts/s^2); then it answers with TPDO1
    (0x180 + node: position actual 0x6064 int32, statusword 0x6041 uint16);
  - it sends its heartbeat (0x700 + node, state 0x05) every heartbeat_ms.

Statusword: 0x0237 (operation enabled, remote) with bit 12 set while it
follows; bit 13 when |target - actual| exceeds window (counts, 0: never);
on a fault 0x0208 (bit 3, nothing enabled, bit 12 clear).

The drive starts where the first target it receives puts it (as a real
drive enabled at its actual position), unless start counts are given.

Control (stdin of `kinctl drivesim`, or DriveSim.command): one command a
line, answered with "ok <command>" on stdout once applied:
    fault N | clear N        set or clear node N's fault
    silent N | talk N        stop or resume node N's TPDOs and heartbeat
    lag N SECONDS            node N's lag (0: none)
    vmax N COUNTS_S          node N's speed limit (0: none)
    quit
"""
import math
import struct
import sys
import threading
import time

from kinctl import canraw
from kinctl.dbc import HEARTBEAT_BASE, RPDO_BASE, SYNC_ID, TPDO_BASE

RCVBUF = 8 << 20
SW_ENABLED = 0x0237
SW_FOLLOWS = 1 << 12
SW_FOLLOWING_ERROR = 1 << 13
SW_FAULT_STATE = 0x0208
NMT_OPERATIONAL = 0x05


class Drive:
    """One node's state; stepped by DriveSim at each SYNC."""

    def __init__(self, node, lag_s=0.0, vmax=0.0, amax=0.0, window=0.0, start=None):
        self.node = node
        self.lag_s, self.vmax, self.amax, self.window = lag_s, vmax, amax, window
        self.pos = None if start is None else float(start)
        self.vel = 0.0
        self.pending = None  # target received since the last SYNC
        self.target = None
        self.faulted = False
        self.silent = False
        self.rpdos = 0
        self.syncs = 0

    def step(self, dt):
        """One bus cycle: latch the pending target, move, return the
        (position counts, statusword) to answer with."""
        self.syncs += 1
        if self.pending is not None:
            self.target = self.pending
            self.pending = None
            if self.pos is None:
                self.pos = float(self.target)
        if self.pos is None:
            return None
        if self.target is not None and not self.faulted:
            err = self.target - self.pos
            v = err / max(self.lag_s, dt)
            if self.vmax > 0:
                v = max(-self.vmax, min(self.vmax, v))
            if self.amax > 0:
                dv = self.amax * dt
                v = max(self.vel - dv, min(self.vel + dv, v))
            self.vel = v
            self.pos += v * dt
            if self.lag_s == 0 and self.vmax == 0 and self.amax == 0:
                self.pos = float(self.target)  # exact, no rounding drift
        else:
            self.vel = 0.0
        if self.faulted:
            sw = SW_FAULT_STATE
        else:
            sw = SW_ENABLED | SW_FOLLOWS
            if self.window > 0 and self.target is not None and abs(self.target - self.pos) > self.window:
                sw |= SW_FOLLOWING_ERROR
        return int(round(self.pos)), sw


class DriveSim:
    """Drives on a CAN interface, served by a thread."""

    def __init__(self, channel, nodes, period_s, heartbeat_ms=100.0, out=None, **drive_args):
        import can
        self.channel = channel
        self.period_s = period_s
        self.heartbeat_s = heartbeat_ms / 1000.0
        self.drives = {n: Drive(n, **drive_args) for n in nodes}
        filters = [{"can_id": SYNC_ID, "can_mask": 0x7FF, "extended": False}]
        filters += [{"can_id": RPDO_BASE + n, "can_mask": 0x7FF, "extended": False} for n in nodes]
        self.bus = can.Bus(interface="socketcan", channel=channel, can_filters=filters,
                           receive_own_messages=False)
        canraw.size_receive_buffer(self.bus.socket, RCVBUF)
        self.out = out
        self.lock = threading.Lock()
        self.running = False
        self.thread = None
        self.sent = 0
        self.send_errors = 0

    # -- control ------------------------------------------------------------
    def command(self, line):
        """Applies one control line (see the module's text); returns the
        reply. ValueError for a bad line."""
        verb, args, d = control_line(self, line, ("fault", "clear", "silent", "talk", "lag", "vmax"),
                                     "fault/clear/silent/talk N, lag N S, vmax N C, quit")
        if d is None:
            return "ok quit"
        with self.lock:
            if verb == "fault":
                d.faulted = True
            elif verb == "clear":
                d.faulted = False
            elif verb == "silent":
                d.silent = True
            elif verb == "talk":
                d.silent = False
            else:
                if len(args) != 2:
                    raise ValueError(f"{verb} needs a node id and a value")
                value = float(args[1])
                if not math.isfinite(value) or value < 0:
                    raise ValueError(f"{verb} {value}: expected a value >= 0")
                if verb == "lag":
                    d.lag_s = value
                else:
                    d.vmax = value
        return "ok " + " ".join(line.split())

    # -- serving ------------------------------------------------------------
    def _send(self, can_id, data):
        import can
        try:
            self.bus.send(can.Message(arbitration_id=can_id, data=data, is_extended_id=False), timeout=0.01)
            self.sent += 1
        except can.CanError:
            self.send_errors += 1

    def _heartbeats(self):
        for d in self.drives.values():
            if not d.silent:
                self._send(HEARTBEAT_BASE + d.node, bytes([NMT_OPERATIONAL]))

    def serve(self, duration=None):
        """Serves until quit (or duration seconds)."""
        import can
        self.running = True
        end = None if duration is None else time.monotonic() + duration
        next_hb = time.monotonic()
        while self.running:
            now = time.monotonic()
            if end is not None and now >= end:
                break
            if self.heartbeat_s > 0 and now >= next_hb:
                with self.lock:
                    self._heartbeats()
                next_hb += self.heartbeat_s
                if next_hb <= now:
                    next_hb = now + self.heartbeat_s
            try:
                msg = self.bus.recv(timeout=min(0.02, max(0.0, next_hb - time.monotonic())))
            except (OSError, can.CanError):
                time.sleep(0.05)  # the interface is down: wait for it
                continue
            if msg is None or msg.is_error_frame:
                continue
            cid = msg.arbitration_id
            with self.lock:
                if cid == SYNC_ID:
                    for d in self.drives.values():
                        answer = d.step(self.period_s)
                        if answer is not None and not d.silent:
                            self._send(TPDO_BASE + d.node, struct.pack("<iH", answer[0], answer[1]))
                elif cid - RPDO_BASE in self.drives and len(msg.data) >= 8:
                    d = self.drives[cid - RPDO_BASE]
                    d.pending = struct.unpack_from("<i", msg.data, 0)[0]
                    d.rpdos += 1

    def start(self):
        self.thread = threading.Thread(target=self.serve, daemon=True)
        self.thread.start()

    def stop(self):
        self.running = False
        if self.thread is not None:
            self.thread.join(2)
        self.bus.shutdown()


def parse_nodes(text):
    """'1-6' or '1,2,5' or '3' -> [1, ...]; ValueError otherwise."""
    nodes = []
    try:
        for part in text.split(","):
            part = part.strip()
            if "-" in part:
                a, b = part.split("-", 1)
                nodes += list(range(int(a), int(b) + 1))
            elif part:
                nodes.append(int(part))
    except ValueError:
        nodes = []
    if not nodes or any(not 1 <= n <= 127 for n in nodes) or len(set(nodes)) != len(nodes):
        raise ValueError(f"--nodes {text!r}: expected distinct node ids in 1..127, e.g. 1-6 or 1,2,3")
    return nodes


def control_line(sim, line, verbs, usage):
    """One control line of a drive simulator sim (this module's DriveSim,
    drive402's Drives): (verb, arguments, drive) for one of verbs followed
    by the node id of one of sim.drives, or ("quit", [], None) once quit has
    stopped sim (sim.running). ValueError otherwise; usage lists the
    commands."""
    words = line.split()
    if not words:
        raise ValueError("empty command")
    verb, args = words[0], words[1:]
    if verb == "quit":
        sim.running = False
        return verb, args, None
    if verb not in verbs or not args:
        raise ValueError(f"unknown command {line!r} ({usage})")
    node = int(args[0])
    if node not in sim.drives:
        raise ValueError(f"no drive with node id {node}")
    return verb, args, sim.drives[node]


def serve_control(sim, no_stdin, alive):
    """Answers control lines on stdin with sim.command's replies (or
    "error ...") until quit or the end of input; with no_stdin, waits while
    alive() holds instead."""
    if no_stdin:
        while alive():
            time.sleep(0.5)
        return
    for line in sys.stdin:
        line = line.strip()
        if not line:
            continue
        try:
            print(sim.command(line), flush=True)
        except ValueError as e:
            print(f"error {e}", flush=True)
        if not sim.running:
            break


def run(args):
    """`kinctl drivesim`: serve until stdin says quit or closes, or SIGINT."""
    try:
        sim = DriveSim(args.interface, parse_nodes(args.nodes), args.period_ms / 1000.0,
                       heartbeat_ms=args.heartbeat_ms, lag_s=args.lag, vmax=args.vmax, amax=args.amax,
                       window=args.window)
    except OSError as e:
        raise OSError(f"cannot open CAN interface {args.interface!r}: {e}") from e
    sim.start()
    print(f"ready {args.interface} nodes {args.nodes}", flush=True)
    try:
        serve_control(sim, args.no_stdin, sim.thread.is_alive)
    finally:
        sim.stop()
    return 0
