# SPDX-License-Identifier: BSD-3-Clause
"""kinctld's CAN output on a SocketCAN interface: frames per second sustained,
the CAN path's cost per bus cycle, and cycle deadline to frame on the bus.

For each joint count (6: puma560; 12: a 12-joint chain written here), kinctld
runs at --period-us with controller.can on the interface (SYNC every cycle,
feedback off: the output alone) while joint goals go back and forth. Then:

  frames/s       frames of kinctld's on the bus (a raw socket, 8 MiB receive
                 buffer) over the run, beside the daemon's own count of
                 frames sent and dropped (EAGAIN/ENOBUFS);
  CAN path       the I/O thread's time to encode and write one bus cycle (one
                 sendmmsg of SYNC + n RPDOs), p50/p99/max from kinctld's
                 exit summary; the cycle thread itself does no CAN work;
  deadline->frame  the kernel's receive timestamp of each SYNC (SO_TIMESTAMPNS,
                 CLOCK_REALTIME) minus its cycle's deadline (setpoint_t.utime,
                 the same clock); on vcan the receive timestamp is the moment
                 the frame was sent.

Used by tools/bench/run_can_bench.sh, which runs it on this host's vcan or
inside User Mode Linux (there, only the frame counts mean something).
"""
import argparse
import os
import re
import signal
import sys
import tempfile
import time

import lcm

from kinctl import canraw, local
from kinctl_msgs import goal_joint_t, setpoint_t


def chain12():
    """A 12-joint serial chain (alternating axes), 1 rad/s and 5 rad/s^2."""
    rows = []
    for i in range(12):
        alpha = 1.5707963267948966 if i % 2 == 0 else -1.5707963267948966
        rows.append(f'{{ name = "j{i + 1}"; type = "revolute"; a = 0.08; alpha = {alpha}; d = 0.05; theta = 0.0; '
                    'limits = { q = [-2.5, 2.5]; qd = 1.0; qdd = 5.0; qddd = 50.0; }; }')
    return ('robot = { name = "chain12"; angles = "rad";\n  dh = (\n    ' + ",\n    ".join(rows) + "\n  );\n};\n")


def config(n, period_us, iface):
    joints = ", ".join(f"{{ node = {k + 1}; counts_per_unit = 100000.0; }}" for k in range(n))
    text = chain12() if n == 12 else ""
    text += (f'controller = {{ period_us = {period_us};\n  can = {{ interface = "{iface}"; joints = ( {joints} );\n'
             '    feedback = { enable = false; }; };\n};\n')
    return text


def pct(values, p):
    s = sorted(values)
    return s[min(len(s) - 1, int(p * len(s)))] if s else float("nan")


def run_one(kinctld, n, period_us, duration, iface, rt):
    url = local.unique_url(subnet=79, port_base=40000)
    with tempfile.NamedTemporaryFile("w", suffix=".cfg", delete=False) as f:
        f.write(config(n, period_us, iface))
        cfg_path = f.name
    lc = lcm.LCM(url)
    deadlines = {}

    def on_sp(channel, data):
        sp = setpoint_t.decode(data)
        deadlines[sp.cycle] = sp.utime

    sub = lc.subscribe("KINCTL_SETPOINT", on_sp)
    sub.set_queue_capacity(1000000)
    rec = canraw.FrameRecorder(iface, rcvbuf=16 << 20)
    daemon = local.Kinctld("--config", cfg_path, binary=kinctld, url=url, rt=rt,
                           extra_args=["--model", "puma560"] if n == 6 else ())
    t_end = time.monotonic() + duration
    goal = 0
    next_goal = time.monotonic() + 0.5
    while time.monotonic() < t_end:
        lc.handle_timeout(50)
        if time.monotonic() >= next_goal:
            goal += 1
            g = goal_joint_t()
            g.goal_id, g.mode, g.n = goal, goal_joint_t.QUEUE, n
            amp = 0.4 if goal % 2 else 0.0
            home = [0.0, 0.7854, -3.1416, 0.0, 0.7854, 0.0] if n == 6 else [0.0] * n
            g.q = [h + amp for h in home] + [0.0] * (goal_joint_t.MAX_JOINTS - n)
            g.vel_scale = g.acc_scale = 1.0
            lc.publish("KINCTL_GOAL_JOINT", g.encode())
            next_goal += 1.5
    daemon.stop(signal.SIGTERM, timeout=30)
    if daemon.hung:
        sys.exit(f"kinctld did not exit within 30 s of SIGTERM: {daemon.stderr.strip()}")
    err = daemon.stderr
    for _ in range(20):
        lc.handle_timeout(20)
    frames = rec.settle(quiet_s=0.5, longest_s=20.0)  # the backlog read
    rec.close()
    os.unlink(cfg_path)
    ours = {0x080} | {0x200 + k for k in range(1, n + 1)} | {0x77F}
    frames = [f for f in frames if f[1] in ours]
    span_s = (frames[-1][0] - frames[0][0]) * 1e-9 if len(frames) > 1 else float("nan")
    m = re.search(r"CAN \S+: frames (\d+), dropped (\d+), errors (\d+).*per bus cycle p50 (\d+) ns, p99 (\d+) ns, "
                  r"max (\d+) ns over (\d+)", err)
    mc = re.search(r"kinctld: (\d+) cycles, (\d+) overruns", err)
    cycles, overruns = int(mc.group(1)), int(mc.group(2))
    # SYNCs to cycles: in order, each the next cycle, the counter checked.
    syncs = [f for f in frames if f[1] == 0x080]
    first = min(deadlines) if deadlines else None
    lat = []
    gaps = 0
    if first is not None:
        for i, (ts, _, data) in enumerate(syncs):
            k = first + i
            if data[0] != k % 240 + 1:
                gaps += 1
                continue
            if k in deadlines:
                lat.append(ts / 1000.0 - deadlines[k])  # us
    return {
        "joints": n, "cycles": cycles, "overruns": overruns, "frames_seen": len(frames), "span_s": span_s,
        "fps": len(frames) / span_s if span_s == span_s and span_s > 0 else float("nan"),
        "expected_fps": (n + 1) * 1e6 / period_us,
        "sent": int(m.group(1)) if m else -1, "dropped": int(m.group(2)) if m else -1,
        "errors": int(m.group(3)) if m else -1,
        "path_p50_us": int(m.group(4)) / 1000 if m else float("nan"),
        "path_p99_us": int(m.group(5)) / 1000 if m else float("nan"),
        "path_max_us": int(m.group(6)) / 1000 if m else float("nan"),
        "lat_p50_us": pct(lat, 0.5), "lat_p99_us": pct(lat, 0.99), "lat_max_us": max(lat) if lat else float("nan"),
        "lat_n": len(lat), "sync_misaligned": gaps, "reader_lost": rec.lost,
    }


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="example:\n  python3 tools/bench/can_bench.py --kinctld build/daemon/kinctld "
                                       "--duration 10")
    p.add_argument("--kinctld", help="the daemon (default: kinctl.programs.find)")
    p.add_argument("--interface", default="vcan0")
    p.add_argument("--duration", type=float, default=10.0)
    p.add_argument("--period-us", type=int, default=1000)
    p.add_argument("--joints", default="6,12")
    p.add_argument("--rt", action="store_true", help="kinctld --rt (SCHED_FIFO, pinned, mlockall)")
    p.add_argument("--note", default="", help="a line printed under the table")
    args = p.parse_args(argv)
    rows = [run_one(args.kinctld, int(n), args.period_us, args.duration, args.interface, args.rt)
            for n in args.joints.split(",")]
    print(f"\nkinctld CAN output on {args.interface}, {1e6 / args.period_us:g} Hz, SYNC every cycle, "
          f"{args.duration:g} s per run")
    print(f"{'joints':>6} {'cycles':>7} {'overruns':>8} {'frames/cyc':>10} {'frames/s':>9} {'expected':>9} "
          f"{'sent':>8} {'dropped':>8} "
          f"{'path p50':>9} {'p99':>8} {'max':>8}   {'dl->frame p50':>13} {'p99':>8} {'max':>9}")
    for r in rows:
        print(f"{r['joints']:>6} {r['cycles']:>7} {r['overruns']:>8} {r['frames_seen'] / max(1, r['cycles']):>10.2f} "
              f"{r['fps']:>9.0f} {r['expected_fps']:>9.0f} {r['sent']:>8} {r['dropped']:>8} "
              f"{r['path_p50_us']:>7.1f}us {r['path_p99_us']:>6.1f}us {r['path_max_us']:>6.1f}us   "
              f"{r['lat_p50_us']:>11.1f}us {r['lat_p99_us']:>6.1f}us {r['lat_max_us']:>7.1f}us")
    print("frames/s: kinctld's frames seen on the bus over the run; expected: (joints + 1) per cycle at the "
          "period (a cycle the daemon misses (overruns) sends no frames).")
    print("path: the I/O thread's encode + sendmmsg of one bus cycle (SYNC + RPDOs); the cycle thread does no "
          "CAN work.")
    print("dl->frame: the SYNC's kernel timestamp on the bus minus its cycle's deadline (setpoint_t.utime).")
    for r in rows:
        if r["reader_lost"]:
            print(f"{r['joints']} joints: the reader lost {r['reader_lost']} frames at its own full queue (all "
                  "frames, ours and others'): frames/s is a lower bound there, 'sent' is the daemon's count")
        if r["sync_misaligned"]:
            print(f"{r['joints']} joints: {r['sync_misaligned']} SYNCs out of step with the cycles (frames lost "
                  "or dropped)")
    if args.note:
        print(args.note)
    return 0


if __name__ == "__main__":
    sys.exit(main())
