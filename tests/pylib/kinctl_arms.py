# SPDX-License-Identifier: BSD-3-Clause
"""An arm's joint limits as its description file gives them (models/*.cfg,
which hold the built-in models' values), for the suites that check what a
running kinctld publishes against them: random targets inside them,
Ruckig's time-synchronised duration (Python ruckig package), and a
setpoint stream's checks. Slack: the daemon's core is double; the limits
and the jerk get 1e-6 of themselves, the continuity checks 1e-12 rad
(rounding of positions of a few rad) and 1e-9 rad/s."""
import os
import re

from ruckig import InputParameter, Result, Ruckig, Synchronization, Trajectory

from kinctl_testing import DT, MODELS, QN

SLACK = 1e-6
# Poses from which lines and arcs stay mostly reachable: puma560's
# nominal pose, and one of the panda's away from mid-range (its IK
# objective's rest) where its null-space motion is at work.
HOMES = {"puma560": QN, "panda": [0.0, -0.3, 0.0, -2.0, 0.0, 1.8, 0.8]}
# Targets keep this far inside the position limits (rad): a replacing
# goal's overshoot from full speed (about vmax^2 / (2 amax) plus the jerk
# phases) stays clear of them, so the dry run accepts every goal.
MARGIN = 0.9
LIMITS = re.compile(r"limits\s*=\s*\{\s*q\s*=\s*\[([^,\]]+),([^\]]+)\];\s*qd\s*=\s*([^;]+);\s*qdd\s*=\s*([^;]+);"
                    r"\s*qddd\s*=\s*([^;]+);")


class Arm:
    """An arm's joint limits, from its description file (models/NAME.cfg, or
    the file at path)."""

    def __init__(self, name, path=None):
        with open(path or os.path.join(MODELS, name + ".cfg")) as f:
            rows = [[float(x) for x in m.groups()] for m in LIMITS.finditer(f.read())]
        assert rows, name
        self.name, self.n = name, len(rows)
        self.q = [(r[0], r[1]) for r in rows]
        self.qd, self.qdd, self.qddd = [r[2] for r in rows], [r[3] for r in rows], [r[4] for r in rows]

    def random_target(self, rng):
        # A joint whose range is narrower than two margins goes to its middle.
        return [rng.uniform(lo + MARGIN, hi - MARGIN) if hi - lo > 2 * MARGIN else 0.5 * (lo + hi)
                for lo, hi in self.q]

    def ruckig_ticks(self, q, qd, qdd, target):
        """Ruckig's time-synchronised duration from (q, qd, qdd) to rest at
        target within the arm's limits, in cycles."""
        n = self.n
        inp = InputParameter(n)
        inp.current_position, inp.current_velocity, inp.current_acceleration = list(q), list(qd), list(qdd)
        inp.target_position, inp.target_velocity, inp.target_acceleration = list(target), [0.0] * n, [0.0] * n
        inp.max_velocity, inp.max_acceleration, inp.max_jerk = self.qd, self.qdd, self.qddd
        inp.synchronization = Synchronization.Time
        traj = Trajectory(n)
        assert Ruckig(n).calculate(inp, traj) == Result.Working
        return traj.duration / DT

    def check_limits(self, stream):
        """Consecutive cycles, each with q inside its limits, within qd_max
        and qdd_max, q changing by at most qd_max dt and qd by at most
        qdd_max dt a cycle (continuity), and qdd changing by at most
        qddd_max dt a cycle."""
        for a, b in zip(stream, stream[1:]):
            assert b.cycle == a.cycle + 1, (a.cycle, b.cycle)
            for j in range(self.n):
                where = (b.cycle, b.goal_id, j)
                assert self.q[j][0] <= b.q[j] <= self.q[j][1], where
                assert abs(b.q[j] - a.q[j]) <= self.qd[j] * DT * (1 + SLACK) + 1e-12, where
                assert abs(b.qd[j] - a.qd[j]) <= self.qdd[j] * DT * (1 + SLACK) + 1e-9, where
                assert abs(b.qd[j]) <= self.qd[j] * (1 + SLACK), where
                assert abs(b.qdd[j]) <= self.qdd[j] * (1 + SLACK), where
                assert abs(b.qdd[j] - a.qdd[j]) <= self.qddd[j] * DT * (1 + SLACK), where

    def check_stream(self, stream):
        """check_limits, and q and qd continuous as a jerk-limited joint
        motion integrates them: each follows from the cycle before within
        what the jerk limit allows over one cycle."""
        self.check_limits(stream)
        for a, b in zip(stream, stream[1:]):
            for j in range(self.n):
                where = (b.cycle, b.goal_id, j)
                J = self.qddd[j]
                assert abs(b.qd[j] - a.qd[j] - a.qdd[j] * DT) <= J * DT ** 2 / 2 * (1 + SLACK) + 1e-9, where
                assert abs(b.q[j] - a.q[j] - a.qd[j] * DT - a.qdd[j] * DT ** 2 / 2) <= \
                    J * DT ** 3 / 6 * (1 + SLACK) + 1e-12, where
