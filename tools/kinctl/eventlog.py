# SPDX-License-Identifier: BSD-3-Clause
"""LCM event logs of kinctl channels: `kinctl record` and `kinctl play`.

The files are LCM's own event log format (lcm.EventLog, what lcm-logger
writes and lcm-logplayer, lcm-spy's log player and `kinctl replay` read).
Each event's timestamp is the recorder's wall clock at receipt (us), as
lcm-logger's is.
"""
import re
import struct
import threading
import time

import lcm

from kinctl.cycles import CycleCount
from kinctl.msgs import setpoint_t

SETPOINT_FINGERPRINT = setpoint_t._get_packed_fingerprint()
SETPOINT_SIZE = len(setpoint_t().encode())

# Channel suffixes that carry what clients send the daemon (the inputs a
# recorded run can be played back into another daemon with).
QUEUE_CAPACITY = 100000  # messages LCM may hold for the recorder (100 s of setpoints at 1 kHz)
INPUT_SUFFIXES = ("GOAL_JOINT", "GOAL_LINE", "GOAL_ARC", "GOAL_PATH", "GOAL_SERVO", "COMMAND")


def _bar(**kw):
    from tqdm import tqdm
    return tqdm(dynamic_ncols=True, disable=None, **kw)


def channel_regex(prefix, inputs_only=False):
    """The LCM channel regex of every kinctl channel under prefix (or of its inputs)."""
    if inputs_only:
        return re.escape(prefix) + "(" + "|".join(INPUT_SUFFIXES) + ")"
    return re.escape(prefix) + ".*"


class Recorder:
    """Writes every message on channels matching regex to an event log.

    Counts events and bytes, and the setpoints' cycle numbers (read from the
    datagram: bytes 16..23 after the fingerprint and utime), so that a lost
    setpoint is reported."""

    def __init__(self, path, url=None, regex=".*", setpoint_channel=None, overwrite=False):
        self.log = lcm.EventLog(path, "w", overwrite=overwrite)
        self.lc = lcm.LCM(url) if url else lcm.LCM()
        self.setpoint_channel = setpoint_channel
        self.events = 0
        self.bytes = 0
        self.channels = {}
        self.cycles = CycleCount()
        self.sub = self.lc.subscribe(regex, self._on)
        # LCM drops what waits beyond a subscription's queue (30 by default):
        # a recorder that falls behind for a moment must not lose setpoints.
        self.sub.set_queue_capacity(QUEUE_CAPACITY)

    def _on(self, channel, data):
        self.log.write_event(time.time_ns() // 1000, channel, data)
        self.events += 1
        self.bytes += len(data)
        self.channels[channel] = self.channels.get(channel, 0) + 1
        # A setpoint is counted when it is one (its fingerprint and size):
        # anything else on the channel is recorded as it came, not counted.
        if channel == self.setpoint_channel and len(data) == SETPOINT_SIZE and data[:8] == SETPOINT_FINGERPRINT:
            self.cycles.add(struct.unpack(">q", data[16:24])[0])

    def run(self, stop, duration=None, progress=True):
        """Handles messages until stop (a threading.Event) is set or duration (s) has passed."""
        t0 = time.monotonic()
        bar = _bar(total=duration, unit="s", bar_format="{l_bar}{bar}| {n:.1f}/{total:.1f} s{postfix}"
                   if duration else "{desc}: {elapsed}{postfix}", desc="record") if progress else None
        last_update = t0
        try:
            while not stop.is_set():
                now = time.monotonic()
                if duration is not None and now - t0 >= duration:
                    break
                try:
                    self.lc.handle_timeout(50)
                except OSError:
                    if stop.is_set():  # a signal interrupted the wait
                        break
                    raise
                if bar is not None and now - last_update >= 0.25:
                    bar.set_postfix_str(f"{self.events} events, {self.bytes / 1e6:.1f} MB", refresh=False)
                    if duration:
                        bar.n = min(now - t0, duration)
                    bar.refresh()
                    last_update = now
        finally:
            if bar is not None:
                bar.set_postfix_str(f"{self.events} events, {self.bytes / 1e6:.1f} MB", refresh=False)
                if duration:
                    bar.n = min(time.monotonic() - t0, duration)
                bar.close()

    def close(self):
        self.lc.unsubscribe(self.sub)
        self.log.close()

    def report(self):
        s = f"{self.events} events ({self.bytes / 1e6:.2f} MB) on {len(self.channels)} channels"
        if self.cycles.count:
            s += "; setpoints of " + self.cycles.report()
        return s


def read_events(path):
    """Every event of a log as (utime, channel, data); ValueError for a file that is not a log."""
    log = lcm.EventLog(path, "r")
    out = []
    try:
        for ev in log:
            out.append((ev.timestamp, ev.channel, ev.data))
    finally:
        log.close()
    return out


def check_log(path):
    """Raises ValueError with a readable text unless path is a readable, non-empty LCM event log."""
    import os
    if not os.path.isfile(path):
        raise ValueError(f"{path}: no such file")
    with open(path, "rb") as f:
        head = f.read(4)
    if len(head) == 0:
        raise ValueError(f"{path}: empty file, not an LCM event log")
    if head != b"\xed\xa1\xda\x01":
        raise ValueError(f"{path}: not an LCM event log (written by kinctl record or lcm-logger)")


def play(path, url=None, speed=1.0, regex=None, progress=True, stop=None):
    """Publishes the events of a log with their original spacing divided by
    speed; only channels matching regex (a full match) when given. Returns
    (events published, seconds taken)."""
    check_log(path)
    pattern = re.compile(regex) if regex else None
    lc = lcm.LCM(url) if url else lcm.LCM()
    log = lcm.EventLog(path, "r")
    size = log.size()
    bar = _bar(total=size, unit="B", unit_scale=True, desc="play") if progress else None
    sent = 0
    t0 = first = None
    last_pos = 0
    try:
        for ev in log:
            if stop is not None and stop.is_set():
                break
            if pattern is not None and not pattern.fullmatch(ev.channel):
                continue
            if first is None:
                first, t0 = ev.timestamp, time.monotonic()
            due = t0 + (ev.timestamp - first) / 1e6 / speed
            wait = due - time.monotonic()
            if wait > 0:
                time.sleep(wait)
            lc.publish(ev.channel, ev.data)
            sent += 1
            if bar is not None and sent % 200 == 0:
                pos = log.tell()
                bar.update(pos - last_pos)
                last_pos = pos
        if bar is not None:
            bar.update(size - last_pos)
    finally:
        if bar is not None:
            bar.close()
        log.close()
    return sent, (time.monotonic() - t0) if t0 is not None else 0.0


def record_until(path, url, regex, setpoint_channel, duration=None, stop=None, progress=True, overwrite=False,
                 ready=None):
    """Records until duration or stop; returns the Recorder (closed)."""
    stop = stop or threading.Event()
    rec = Recorder(path, url, regex, setpoint_channel, overwrite=overwrite)
    try:
        if ready is not None:
            ready(rec)
        rec.run(stop, duration, progress)
    finally:
        rec.close()
    return rec
