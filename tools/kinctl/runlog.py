# SPDX-License-Identifier: BSD-3-Clause
"""A run's setpoints (and status events) from either kind of log:

- the CSV of `kinctl log` (kinctl.logcsv), with its events CSV beside it if given;
- an LCM event log (lcm-logger's format: `lcm-logger`, `kinctl record`), whose
  <prefix>SETPOINT messages are decoded with kinctl_msgs, and whose
  <prefix>STATUS messages give the events.

    from kinctl.runlog import read_run
    cols, events = read_run("run.lcmlog")          # or "run.csv", events="events.csv"

cols is the dict of logcsv.read (utime, cycle, goal_id, state (code), q1..qn,
qd1.., qdd1.., x, y, z, qw, qx, qy, qz as lists); events the list of
logcsv.read_events (utime, cycle, goal_id, event (name), code, reason).
"""
import os
import statistics

from kinctl import logcsv

# lcm-logger files start with this sync word (big-endian), before every event.
LCM_LOG_MAGIC = b"\xed\xa1\xda\x01"


def is_lcm_log(path):
    with open(path, "rb") as f:
        return f.read(4) == LCM_LOG_MAGIC


def read_run(path, events=None, prefix="KINCTL_", progress=False):
    """(columns, events) of a CSV or LCM log. events: an events CSV for a CSV
    log (ignored for an LCM log, which carries its own). ValueError with what
    to do when the file holds no setpoints."""
    if not os.path.exists(path):
        raise ValueError(f"{path}: no such file (a CSV from `kinctl log --csv` or an LCM log from lcm-logger)")
    if is_lcm_log(path):
        return read_lcm_log(path, prefix, progress)
    what = f"{path}: not a setpoint CSV of `kinctl log --csv` nor an LCM event log"
    try:
        with open(path, newline="") as f:
            head = f.readline().strip().split(",")
    except UnicodeDecodeError:
        raise ValueError(what) from None
    missing = [k for k in ("utime", "cycle", "goal_id", "state", "q1", "x", "y", "z") if k not in head]
    if missing:
        raise ValueError(f"{what} (no column {', '.join(missing)})")
    try:
        cols = logcsv.read(path, progress=progress)
    except ValueError as e:
        raise ValueError(f"{path}: a broken row in the setpoint CSV ({e})") from None
    return cols, (logcsv.read_events(events) if events else [])


def read_lcm_log(path, prefix="KINCTL_", progress=False):
    """(columns, events) from an lcm-logger file: <prefix>SETPOINT and <prefix>STATUS."""
    import lcm
    from kinctl.msgs import event_name, setpoint_t, status_t
    from kinctl.progress import bar

    sp_channel, st_channel = prefix + "SETPOINT", prefix + "STATUS"
    sps, events, channels = [], [], {}
    log = lcm.EventLog(path, "r")
    try:
        with bar(log.size(), f"reading {os.path.basename(path)}", unit="B", unit_scale=True,
                 unit_divisor=1024, show=progress) as b:
            last = 0
            for ev in log:
                channels[ev.channel] = channels.get(ev.channel, 0) + 1
                if ev.channel == sp_channel:
                    sps.append(setpoint_t.decode(ev.data))
                elif ev.channel == st_channel:
                    st = status_t.decode(ev.data)
                    if st.event != 0:
                        events.append(dict(utime=st.utime, cycle=st.cycle, goal_id=st.event_goal_id,
                                           event=event_name(st.event), code=st.code, reason=st.reason))
                pos = log.tell()
                if pos - last > 1 << 20:
                    b.update(pos - last)
                    last = pos
    finally:
        log.close()
    if not sps:
        found = ", ".join(f"{c} ({n})" for c, n in sorted(channels.items())) or "none"
        hint = [c[: -len("SETPOINT")] for c in channels if c.endswith("SETPOINT")]
        raise ValueError(f"{path}: no {sp_channel} messages in this LCM log (channels: {found})"
                         + (f"; try --prefix {hint[0]}" if hint else ""))
    return setpoint_columns(sps), events


def setpoint_columns(sps):
    """Columns (as logcsv.read gives) of a list of setpoint_t; the joint count is the first one's."""
    n = sps[0].n
    cols = {k: [] for k in logcsv.header(n)}
    for sp in sps:
        cols["utime"].append(sp.utime)
        cols["cycle"].append(sp.cycle)
        cols["goal_id"].append(sp.goal_id)
        cols["state"].append(sp.state)
        for j in range(n):
            cols[f"q{j + 1}"].append(sp.q[j])
            cols[f"qd{j + 1}"].append(sp.qd[j])
            cols[f"qdd{j + 1}"].append(sp.qdd[j])
        for k, v in zip(("x", "y", "z"), sp.position):
            cols[k].append(v)
        for k, v in zip(("qw", "qx", "qy", "qz"), sp.orientation):
            cols[k].append(v)
    return cols


def trajectory_time(cols):
    """(t, dt): each setpoint's time (s) from the first, as cycles executed
    times the period (so a stall of the logger or the daemon does not show as
    a jump), and the period dt (s): the median step of utime (1 ms if unknown)."""
    dts = [b - a for a, b in zip(cols["utime"], cols["utime"][1:]) if b > a]
    dt = statistics.median(dts) / 1e6 if dts else 1e-3
    c0 = cols["cycle"][0] if cols["cycle"] else 0
    return [(c - c0) * dt for c in cols["cycle"]], dt
