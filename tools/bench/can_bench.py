# SPDX-License-Identifier: BSD-3-Clause
"""kinctld's bus cycle on a SocketCAN interface: SYNC period jitter measured
from the kernel's receive timestamps, beside the cycle thread's wake-up
latency from kinctld's own stats_t, in the same run.

One run: simulated CiA 402 drives (`kinctl drivesim`, nodes 1..--joints,
powered on at the arm's home position) on the interface, kinctld (puma560
for 6 joints, a chain written here for other counts) with controller.can
on it, booting, configuring and enabling the drives (CANopen master,
daemon/README.md), then joint goals back and forth for --duration seconds,
then SIGTERM (the drives disabled). Measured:

  SYNC - T     every SYNC's kernel receive timestamp (SO_TIMESTAMPNS on a
               raw socket with a 16 MiB queue; on vcan the moment the frame
               was sent), the interval from the SYNC before minus the bus
               cycle T = period x sync_every: p50, p99, max and the
               shortest, over every SYNC of the run; the SYNCs seen beside
               kinctld's cycles / sync_every, and the intervals of 1.5 T
               or more counted;
  wake-up      the cycle thread's wake-up latency (its wake-up minus its
               absolute deadline) from the final stats_t, which covers the
               whole run (stats_hz = 0.01: one stats_t per 100 s, and one
               at exit): p50, p99, p99.9, max, and the overruns;
  cyclictest   with --cyclictest, cyclictest at the same period for the
               same time just before, its p50/p99/max, and kinctld's
               wake-up latency as a ratio of it.

The SYNC is written by the cycle thread right after its step, so its jitter
should be the wake-up latency's spread: the two columns side by side say
whether the bus cycle adds to it.

A configuration kinctld refuses (the bus budget: --joints, --sync-every,
--tpdo-every, --bitrate) is reported with kinctld's own reason before
anything runs (kinctld --check).

Used by tools/bench/run_can_bench.sh, which runs it on this host's vcan or
inside User Mode Linux (there it says that the figures are UML's).
"""
import argparse
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import lcm

from kinctl import canraw, local
from kinctl_msgs import goal_joint_t, stats_t, status_t

PUMA_HOME = [0.0, 0.7854, -3.1416, 0.0, 0.7854, 0.0]  # rad (qn)
COUNTS_PER_RAD = 100000.0
DRIVES_ENABLED = getattr(status_t, "DRIVES_ENABLED", 3)  # status_t.drives


def chain(n):
    """An n-joint serial chain (alternating axes), 1 rad/s and 5 rad/s^2."""
    rows = []
    for i in range(n):
        alpha = 1.5707963267948966 if i % 2 == 0 else -1.5707963267948966
        rows.append(f'{{ name = "j{i + 1}"; type = "revolute"; a = 0.08; alpha = {alpha}; d = 0.05; theta = 0.0; '
                    'limits = { q = [-2.5, 2.5]; qd = 1.0; qdd = 5.0; qddd = 50.0; }; }')
    return (f'robot = {{ name = "chain{n}"; angles = "rad";\n  dh = (\n    ' + ",\n    ".join(rows) + "\n  );\n};\n")


def home(n):
    return PUMA_HOME if n == 6 else [0.0] * n


def config(a):
    """kinctld's configuration: controller.can with the drives at nodes
    1..n, booted by kinctld, the bus cycle's figures from the options."""
    joints = ", ".join(f"{{ node = {k + 1}; counts_per_unit = {COUNTS_PER_RAD}; }}" for k in range(a.joints))
    can = (f'interface = "{a.interface}"; bitrate = {a.bitrate}; sync_every = {a.sync_every}; '
           f"tpdo_every = {a.tpdo_every}; sync_counter = {a.sync_counter}; boot = true; joints = ( {joints} );")
    text = chain(a.joints) if a.joints != 6 else ""
    return text + f"controller = {{ period_us = {a.period_us}; stats_hz = 0.01;\n  can = {{ {can} }};\n}};\n"


def write_config(a):
    with tempfile.NamedTemporaryFile("w", suffix=".cfg", delete=False) as f:
        f.write(config(a))
        return f.name


def daemon_args(a):
    return ["--model", "puma560"] if a.joints == 6 else []


def check(a):
    """kinctld --check on the configuration: exits with kinctld's reason
    when it refuses it (the bus budget names what would fit)."""
    path = write_config(a)
    try:
        r = subprocess.run([a.kinctld, "--check", "--config", path] + daemon_args(a), capture_output=True, text=True,
                           timeout=60)
    finally:
        os.unlink(path)
    if r.returncode != 0:
        sys.exit(f"kinctld refuses this configuration: {r.stderr.strip()}")


def percentile(values, p):
    """The smallest value with at least ceil(p * n) values at or below it."""
    s = sorted(values)
    return s[max(0, math.ceil(p * len(s)) - 1)] if s else float("nan")


def sync_jitter(frames, bus_period_us):
    """{p50, p99, max, min, n, late} of SYNC-to-SYNC intervals minus the
    bus cycle (us), from the frames' kernel timestamps (ns); late: the
    intervals of 1.5 bus cycles or more."""
    t = [f[0] for f in frames if f[1] == 0x080]
    dev = [(b - a) / 1e3 - bus_period_us for a, b in zip(t, t[1:])]
    return {"p50": percentile(dev, 0.5), "p99": percentile(dev, 0.99), "max": max(dev, default=float("nan")),
            "min": min(dev, default=float("nan")), "n": len(t),
            "late": sum(1 for d in dev if d >= 0.5 * bus_period_us)}


def following(frames, n):
    """(drives whose RPDO1 target changed during the run, drives whose last
    TPDO1 actual position equals their last RPDO1 target): the drives
    moved with the arm and ended where kinctld left them."""
    def positions(base, node):
        return [int.from_bytes(f[2][2:6], "little", signed=True) for f in frames
                if f[1] == base + node and len(f[2]) == 6]
    moved = at_target = 0
    for node in range(1, n + 1):
        targets, actuals = positions(0x200, node), positions(0x180, node)
        moved += len(set(targets)) > 1
        at_target += bool(targets and actuals) and targets[-1] == actuals[-1]
    return moved, at_target


def cyclictest(period_us, duration, rt):
    """cyclictest at period_us for duration s: {p50, p99, max} (us), or None
    where it is not installed or fails."""
    if shutil.which("cyclictest") is None:
        return None
    with tempfile.NamedTemporaryFile(suffix=".json", delete=False) as f:
        path = f.name
    cmd = ["cyclictest", "-m", "-q", "-i", str(period_us), "-D", str(int(math.ceil(duration))), "-h", "100000",
           f"--json={path}"] + (["-p", "80"] if rt else [])
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=duration + 60)
        if r.returncode != 0:
            return None
        with open(path) as f:
            th = json.load(f)["thread"]["0"]
    except (OSError, ValueError, KeyError, subprocess.TimeoutExpired):
        return None
    finally:
        os.unlink(path)
    hist = sorted((int(k), v) for k, v in th["histogram"].items())

    def pct(p):
        rank, seen = max(1, math.ceil(p * th["cycles"])), 0
        for us, n in hist:
            seen += n
            if seen >= rank:
                return float(us)
        return float(th["max"])
    return {"p50": pct(0.5), "p99": pct(0.99), "max": float(th["max"])}


class DriveSim:
    """`kinctl drivesim` as a subprocess, quit through its stdin."""

    def __init__(self, a):
        starts = ",".join(f"{k + 1}={round(q * COUNTS_PER_RAD)}" for k, q in enumerate(home(a.joints)))
        self.proc = subprocess.Popen([sys.executable, "-m", "kinctl", "drivesim", "--interface", a.interface,
                                      "--nodes", f"1-{a.joints}", "--start", starts],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        line = self.proc.stdout.readline()
        if not line.startswith("ready"):
            self.proc.kill()
            sys.exit(f"kinctl drivesim did not start: {line!r} {self.proc.stderr.read()}")

    def close(self):
        try:
            self.proc.communicate("quit\n", timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.communicate()


def run(a):
    url = local.unique_url(subnet=79, port_base=40000)
    cfg_path = write_config(a)
    lc = lcm.LCM(url)
    statuses, stats = [], []
    lc.subscribe("KINCTL_STATUS", lambda ch, data: statuses.append(status_t.decode(data)))
    lc.subscribe("KINCTL_STATS", lambda ch, data: stats.append(stats_t.decode(data)))
    rec = canraw.FrameRecorder(a.interface, rcvbuf=16 << 20)
    sim = DriveSim(a)
    log = tempfile.NamedTemporaryFile("w+", suffix=".log", delete=False)
    log.close()
    daemon = local.Kinctld("--config", cfg_path, binary=a.kinctld, url=url, rt=a.rt, stderr=log.name,
                           extra_args=daemon_args(a))
    try:
        t0 = time.monotonic()
        while time.monotonic() - t0 < a.boot_timeout:
            lc.handle_timeout(50)
            if any(s.drives == DRIVES_ENABLED for s in statuses) or daemon.proc.poll() is not None:
                break
        if not any(s.drives == DRIVES_ENABLED for s in statuses):
            reasons = sorted({s.reason for s in statuses if s.reason})
            sys.exit(f"the drives were not enabled within {a.boot_timeout:g} s: {reasons}")
        enabled_s = time.monotonic() - t0
        t_end = time.monotonic() + a.duration
        goal, next_goal = 0, time.monotonic() + 0.2
        while time.monotonic() < t_end:
            lc.handle_timeout(50)
            if time.monotonic() >= next_goal:
                goal += 1
                g = goal_joint_t()
                g.goal_id, g.mode, g.n = goal, goal_joint_t.QUEUE, a.joints
                g.q = [h + (0.4 if goal % 2 else 0.0) for h in home(a.joints)]
                g.q += [0.0] * (goal_joint_t.MAX_JOINTS - a.joints)
                g.vel_scale = g.acc_scale = 1.0
                lc.publish("KINCTL_GOAL_JOINT", g.encode())
                next_goal += 1.5
        daemon.stop(signal.SIGTERM, timeout=30, while_waiting=lambda: lc.handle_timeout(50))
        while lc.handle_timeout(200) > 0:
            pass
        if daemon.hung:
            sys.exit(f"kinctld did not exit within 30 s of SIGTERM: {daemon.stderr.strip()}")
        # The drives answer what is still queued for them (a busy host)
        # before they are told to quit.
        frames = rec.settle(quiet_s=0.5, longest_s=20.0)
    finally:
        daemon.stop(signal.SIGKILL)
        sim.close()
        rec.close()
        os.unlink(cfg_path)
        os.unlink(log.name)
    rejected = [s.reason for s in statuses if s.event == status_t.REJECTED]
    return {"sync": sync_jitter(frames, a.period_us * a.sync_every), "drives": following(frames, a.joints), "stats": stats[-1] if stats else None,
            "stats_messages": len(stats), "reader_lost": rec.lost, "enabled_s": enabled_s, "goals": goal,
            "rejected": rejected, "stderr": daemon.stderr, "returncode": daemon.proc.returncode}


def us(v):
    return "-" if v is None or v != v else f"{v:.1f}" if abs(v) < 1000 else f"{v:.0f}"


def report(a, r, ct):
    bus_us = a.period_us * a.sync_every
    print(f"\nkinctld bus cycle on {a.interface}: {a.joints} drives (kinctl drivesim), period {a.period_us} us, "
          f"sync_every {a.sync_every} (SYNC every {bus_us} us), {a.duration:g} s of joint goals")
    if a.note:
        print(a.note)
    print(f"drives booted, configured and enabled by kinctld {r['enabled_s']:.1f} s after its start; "
          f"tpdo_every {a.tpdo_every}, sync_counter {a.sync_counter}, bitrate {a.bitrate} (bus budget)")
    print(f"drives moved with the arm: {r['drives'][0]} of {a.joints}; at their last target at the end "
          f"(last TPDO1 = last RPDO1): {r['drives'][1]} of {a.joints}")
    s, st = r["sync"], r["stats"]
    print(f"{'':28} {'p50':>9} {'p99':>9} {'p99.9':>9} {'max':>9} {'min':>9}   count")
    print(f"{'SYNC interval - T (us)':28} {us(s['p50']):>9} {us(s['p99']):>9} {'':>9} {us(s['max']):>9} "
          f"{us(s['min']):>9}   {s['n']} SYNCs"
          + (f" of {st.cycles // a.sync_every}" if st is not None else "") + f", {s['late']} intervals >= 1.5 T")
    if st is not None:
        lat = [st.latency_p50_ns / 1e3, st.latency_p99_ns / 1e3, st.latency_p999_ns / 1e3, st.latency_max_ns / 1e3]
        print(f"{'cycle wake-up latency (us)':28} {us(lat[0]):>9} {us(lat[1]):>9} {us(lat[2]):>9} {us(lat[3]):>9} "
              f"{'':>9}   {st.cycles} cycles, {st.overruns} overruns")
        if ct is not None:
            print(f"{'cyclictest, same period (us)':28} {us(ct['p50']):>9} {us(ct['p99']):>9} {'':>9} "
                  f"{us(ct['max']):>9}")
            ratio = [f"{x / y:.2f}" if y else "-" for x, y in ((lat[0], ct["p50"]), (lat[1], ct["p99"]),
                                                                  (lat[3], ct["max"]))]
            print(f"{'kinctld / cyclictest':28} {ratio[0]:>9} {ratio[1]:>9} {'':>9} {ratio[2]:>9}")
        print(f"CAN (stats_t): {st.can_frames} frames sent, {st.can_tx_dropped} not sent, {st.can_rx_frames} "
              f"received, {st.can_errors} errors")
        if r["stats_messages"] > 1:
            print(f"note: {r['stats_messages']} stats_t: the wake-up figures cover the last "
                  f"{a.duration:g} s or less, not the whole run")
    else:
        print("no stats_t from kinctld: no wake-up figures")
    print("SYNC interval - T: the kernel's receive timestamps of consecutive SYNCs (on vcan: when each was sent) "
          "minus the bus cycle; a late SYNC makes one interval long and the next short (min).")
    print("wake-up latency: the cycle thread's wake-up minus its deadline, kinctld's histogram over the whole run.")
    if r["reader_lost"]:
        print(f"the reader lost {r['reader_lost']} frames at its own queue: SYNCs may be missing from the figures")
    if r["rejected"]:
        print(f"{len(r['rejected'])} goals rejected, e.g. {r['rejected'][0]!r}")
    events = [line for line in r["stderr"].splitlines() if "kinctld: drive:" in line]
    if events:
        print("kinctld's drive events:\n  " + "\n  ".join(events[:12]) + ("\n  ..." if len(events) > 12 else ""))
    if r["returncode"] != 0:
        print(f"kinctld exited {r['returncode']}: {r['stderr'].strip()[-400:]}")
    if a.note:
        print(a.note)  # under the figures too


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="example:\n  python3 tools/bench/can_bench.py --kinctld build/daemon/kinctld "
                                       "--duration 10 --rt --cyclictest")
    p.add_argument("--kinctld", required=True, help="the daemon")
    p.add_argument("--interface", default="vcan0")
    p.add_argument("--duration", type=float, default=10.0, help="seconds of goals once the drives are enabled")
    p.add_argument("--period-us", type=int, default=1000)
    p.add_argument("--joints", type=int, default=6, help="drives, nodes 1..N (6: puma560; default 6)")
    p.add_argument("--sync-every", type=int, default=2,
                   help="cycles per bus cycle (default 2: 6 drives at 1 kHz exceed a 1 Mbit/s bus every cycle)")
    p.add_argument("--tpdo-every", type=int, default=2, help="TPDO1 every N-th SYNC (default 2)")
    p.add_argument("--sync-counter", type=int, default=0, help="0x1019: 0 empty SYNC (default), 2..240 a counter")
    p.add_argument("--bitrate", type=int, default=1000000, help="for kinctld's bus budget (default 1000000)")
    p.add_argument("--boot-timeout", type=float, default=60.0, help="seconds for the drives to be enabled")
    p.add_argument("--rt", action="store_true", help="kinctld --rt (SCHED_FIFO, pinned, mlockall)")
    p.add_argument("--cyclictest", action="store_true", help="cyclictest at the same period first (rt-tests)")
    p.add_argument("--note", default="", help="a line printed under the figures")
    a = p.parse_args(argv)
    check(a)
    ct = cyclictest(a.period_us, a.duration, a.rt) if a.cyclictest else None
    if a.cyclictest and ct is None:
        a.note = (a.note + "\n" if a.note else "") + "cyclictest: not installed or it failed (rt-tests)"
    report(a, run(a), ct)
    return 0


if __name__ == "__main__":
    sys.exit(main())
