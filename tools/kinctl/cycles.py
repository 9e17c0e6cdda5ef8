# SPDX-License-Identifier: BSD-3-Clause
"""Setpoints counted by cycle number: how many came, and which cycles are
missing and when their gap was seen, so that a logger or recorder that loses
setpoints (its own socket buffer overflowing under a flood, a stall) says
exactly how many and where. kinctld sends one setpoint every cycle, numbered
consecutively."""
import time

SHOWN = 5  # gaps named in a report; the rest are counted


class CycleCount:
    def __init__(self, clock=time.time):
        self.clock = clock
        self.count = 0
        self.first = self.last = None
        self.missing = 0
        self.gaps = []  # (first missing cycle, how many, wall-clock time the next one came)

    def add(self, cycle):
        """One setpoint, of this cycle."""
        if self.last is not None and cycle != self.last + 1:
            lost = cycle - self.last - 1
            if lost > 0:
                self.missing += lost
                self.gaps.append((self.last + 1, lost, self.clock()))
        if self.first is None:
            self.first = cycle
        self.last = cycle
        self.count += 1

    @property
    def span(self):
        return 0 if self.first is None else self.last - self.first + 1

    def report(self):
        """"cycles A..B: none missing", or how many are missing, in how many
        gaps, and the first SHOWN gaps: cycles and the time they were found."""
        if not self.count:
            return "no setpoints received"
        s = f"cycles {self.first}..{self.last}: "
        if not self.missing:
            return s + "none missing"
        shown = ", ".join(
            f"{lost} from cycle {c}" + f" (seen {time.strftime('%H:%M:%S', time.localtime(t))}.{int(t % 1 * 1000):03d})"
            for c, lost, t in self.gaps[:SHOWN])
        more = f", and {len(self.gaps) - SHOWN} more gaps" if len(self.gaps) > SHOWN else ""
        return s + f"{self.missing} missing in {len(self.gaps)} gaps: {shown}{more}"
