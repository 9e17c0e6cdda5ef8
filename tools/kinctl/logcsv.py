# SPDX-License-Identifier: BSD-3-Clause
"""The setpoint CSV of `kinctl log` and the demo, and its status-event CSV.

Setpoints: utime,cycle,goal_id,state,q1..qn,qd1..qdn,qdd1..qddn,x,y,z,qw,qx,qy,qz
(state by name; SI units; floats written with repr, so they read back exactly).
Events:    utime,cycle,goal_id,event,code,reason
"""
import csv

from kinctl.cycles import CycleCount
from kinctl.msgs import event_name, state_name, STATES

EVENT_HEADER = ["utime", "cycle", "goal_id", "event", "code", "reason"]


def header(n):
    return (["utime", "cycle", "goal_id", "state"] + [f"q{i}" for i in range(1, n + 1)]
            + [f"qd{i}" for i in range(1, n + 1)] + [f"qdd{i}" for i in range(1, n + 1)]
            + ["x", "y", "z", "qw", "qx", "qy", "qz"])


def row(sp, n):
    return ([sp.utime, sp.cycle, sp.goal_id, state_name(sp.state)] + [repr(v) for v in sp.q[:n]]
            + [repr(v) for v in sp.qd[:n]] + [repr(v) for v in sp.qdd[:n]]
            + [repr(v) for v in sp.position] + [repr(v) for v in sp.orientation])


def event_row(st):
    return [st.utime, st.cycle, st.event_goal_id, event_name(st.event), st.code, st.reason]


class SetpointWriter:
    """Writes setpoints as they come; the joint count is the first one's.
    Counts them by cycle (kinctl.cycles), to tell whether any were lost."""

    def __init__(self, f):
        self.f = f
        self.w = csv.writer(f, lineterminator="\n")
        self.n = None
        self.cycles = CycleCount()

    def write(self, sp):
        if self.n is None:
            self.n = sp.n
            self.w.writerow(header(self.n))
        self.w.writerow(row(sp, self.n))
        self.cycles.add(sp.cycle)

    @property
    def count(self):
        return self.cycles.count

    def report(self):
        if not self.count:
            return "no setpoints received"
        return f"{self.count} setpoints received, " + self.cycles.report()


def read(path, progress=False):
    """The setpoint CSV as columns: dict name -> list (numbers; state as its code).
    progress: show a progress bar (tqdm, on stderr when it is a terminal)."""
    with open(path, newline="") as f:
        lines = f
        if progress:
            from kinctl.progress import lines_with_bar
            lines = lines_with_bar(f, path)
        r = csv.reader(lines)
        names = next(r)
        cols = {k: [] for k in names}
        for rec in r:
            for k, v in zip(names, rec):
                if k == "state":
                    cols[k].append(STATES.get(v, int(v) if v.lstrip("-").isdigit() else -1))
                elif k in ("utime", "cycle", "goal_id"):
                    cols[k].append(int(v))
                else:
                    cols[k].append(float(v))
    return cols


def read_events(path):
    with open(path, newline="") as f:
        return [dict(utime=int(r["utime"]), cycle=int(r["cycle"]), goal_id=int(r["goal_id"]), event=r["event"],
                     code=int(r["code"]), reason=r["reason"]) for r in csv.DictReader(f)]
