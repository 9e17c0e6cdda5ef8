# SPDX-License-Identifier: BSD-3-Clause
"""ik_bench_rtb.py - the Robotics Toolbox for Python's C++ ik_LM for ik_bench.

ik_bench runs this once per timed block, interleaved with the other
libraries' blocks, on the IK set file it wrote (format in bench_common.h):

  ik_bench_rtb.py check <set file>
      prints the largest |rtb FK(q_true) - T| over the set: the toolbox's
      model must be ours (rtb.models.DH.Puma560 / DH.Panda, whose tables
      are those of tests/vectors/fk.json), or it would solve other problems.
  ik_bench_rtb.py ik <set file> <fixed|random> <first> <count>
      solves targets first..first+count-1 and prints per target
        ik <k> <ns> <1 if rtb says success> <iterations> <searches - 1> <q n>
      then "overhead <ns>": the median time of ik_LM started at the solution
      (one iteration), mostly the cost of the Python call itself.

ik_LM is called on the robot's ETS, made once: DHRobot.ik_LM rebuilds the
ETS on every call (about 0.5 ms of Python) and, on the DH Panda, misses
targets that ETS.ik_LM reaches. Settings: method "chan" (the default),
ilimit 30 iterations per search, slimit 100 searches (random restarts after
the given q0: rtb's own restart mechanism, reported), tol 1e-15 on
E = 0.5 e'e (|e| < 4.5e-8, where the default 1e-6 would allow |e| up to
1.4e-3 and fail the 1e-6 acceptance), joint_limits on. Times are
time.perf_counter_ns around the call, nothing subtracted.
"""

import statistics
import sys
import time

import numpy as np
import roboticstoolbox as rtb

ILIMIT = 30
SLIMIT = 100
TOL = 1e-15
WARMUP = 10  # untimed solves before a block, as the C++ libraries get


def load(path):
    with open(path) as f:
        magic, model, n, count = f.readline().split()
        if magic != "kinctl-ik-set":
            sys.exit(f"error: {path} is not an IK set")
        n, count = int(n), int(count)
        fixed = np.array([float(x) for x in f.readline().split()[1:]])
        rows = np.loadtxt(f, ndmin=2)
    if rows.shape != (count, 12 + 2 * n) or fixed.shape != (n,):
        sys.exit(f"error: {path}: unexpected shape {rows.shape}")
    T = np.zeros((count, 4, 4))
    T[:, :3, :3] = rows[:, :9].reshape(count, 3, 3)
    T[:, :3, 3] = rows[:, 9:12]
    T[:, 3, 3] = 1.0
    return model, fixed, T, rows[:, 12 : 12 + n], rows[:, 12 + n :]


def robot_ets(model):
    robot = {"puma560": rtb.models.DH.Puma560, "panda": rtb.models.DH.Panda}[model]()
    return robot.ets()


def main(argv):
    if len(argv) == 3 and argv[1] == "check":
        model, _, T, q_true, _ = load(argv[2])
        ets = robot_ets(model)
        d = max(np.abs(ets.fkine(q).A - T[k]).max() for k, q in enumerate(q_true))
        print(f"{d:.1e}")
        return 0 if d <= 1e-9 else 1
    if len(argv) != 6 or argv[1] != "ik" or argv[3] not in ("fixed", "random"):
        sys.exit(f"usage: {argv[0]} check <set> | ik <set> <fixed|random> <first> <count>")
    model, fixed, T, q_true, q_start = load(argv[2])
    first, count = int(argv[4]), int(argv[5])
    ets = robot_ets(model)

    def solve(k):
        q0 = fixed if argv[3] == "fixed" else q_start[k]
        t0 = time.perf_counter_ns()
        sol = ets.ik_LM(T[k], q0=q0, ilimit=ILIMIT, slimit=SLIMIT, tol=TOL, joint_limits=True)
        return time.perf_counter_ns() - t0, sol

    for k in range(first, first + min(WARMUP, count)):
        solve(k)
    lines = []
    for k in range(first, first + count):
        ns, sol = solve(k)
        q = " ".join(f"{x:.17g}" for x in sol.q)
        lines.append(f"ik {k} {ns} {int(bool(sol.success))} {sol.iterations} {sol.searches - 1} {q}")
    overhead = []
    for k in range(first, first + min(50, count)):
        t0 = time.perf_counter_ns()
        ets.ik_LM(T[k], q0=q_true[k], ilimit=ILIMIT, slimit=SLIMIT, tol=TOL, joint_limits=True)
        overhead.append(time.perf_counter_ns() - t0)
    print("\n".join(lines))
    print(f"overhead {statistics.median(overhead)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
