# SPDX-License-Identifier: BSD-3-Clause
"""daemon_bench.py - one kinctld run under continuous Cartesian motion.

Started by run_daemon_bench.sh, once per period. Starts kinctld (puma560,
SCHED_FIFO, pinned as configured) on a private LCM URL with ttl=0, and for
--duration seconds sends line and arc goals (alternately) back to back: the
next goal is published as soon as the status of the one before says
COMPLETED (or REJECTED, ABORTED, FAULT), so the arm is in Cartesian motion,
with an IK step, on all but a few cycles between goals (moving_fraction).
The targets go round a circle of 8 cm in the y-z plane in front of the arm's
start pose (the joints qn = 0, 45, -180, 0, 45, 0 deg, away from
singularities), keeping the start orientation.

Why not REPLACE goals in flight: the controller brings the current motion to
rest on its path before it starts a replacing goal, so the first setpoint of
a replacing goal measures that stop (hundreds of ms), not the daemon. A goal
sent to an idle arm starts on the first cycle after the I/O thread has
decoded and dry-run it.

Goal-to-first-setpoint: the client's CLOCK_MONOTONIC just before publishing
a goal, and at the receipt of the first setpoint carrying its goal_id (one
thread does both, so both stamps are on the same clock and loop). It is the
daemon's decode and dry run of the goal (IK along the whole path), the wait
for the next cycle, and LCM both ways on loopback.

Whole-run cycle timing comes from the daemon's own histograms: the run's
configuration asks for stats_t every 100 s (stats_hz = 0.01, the slowest it
allows), so for runs shorter than that the one stats_t it publishes, the
final one at exit, covers every cycle of the run (cycle.h: percentiles are
over the cycles since the previous stats_t). The result is one JSON object
on stdout.

    daemon_bench.py --kinctld BIN --period-us 1000 --duration 60 --cpu 1 --priority 80 --nice -5
"""
import argparse
import json
import math
import os
import signal
import struct
import sys
import tempfile
import time

import lcm
from kinctl import local
from kinctl_msgs import goal_arc_t, goal_line_t, setpoint_t, stats_t, status_t

HOME = [0.0, 0.7854, -3.1416, 0.0, 0.7854, 0.0]  # rad (qn)
PREFIX = "KBENCH_"
MOVING = 1
# setpoint_t's wire layout: 8-byte fingerprint, then utime, cycle, goal_id
# (int64, big-endian), state (int8): read without decoding the whole message.
SP_HEAD = struct.Struct(">8xqqqb")


def percentile(sorted_vals, p):
    """The smallest value with at least ceil(p * n) values at or below it."""
    if not sorted_vals:
        return float("nan")
    rank = max(1, math.ceil(p * len(sorted_vals)))
    return sorted_vals[rank - 1]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--kinctld", help="the daemon (default: kinctl.programs.find)")
    ap.add_argument("--period-us", type=int, default=1000)
    ap.add_argument("--duration", type=float, default=60.0)
    ap.add_argument("--cpu", type=int, default=-1)
    ap.add_argument("--priority", type=int, default=80)
    ap.add_argument("--nice", type=int, default=0, help="run kinctld at this nice value (kinctld.service: -5)")
    ap.add_argument("--dma-latency", type=int, default=None, metavar="US",
                    help="hold /dev/cpu_dma_latency at US for the run, as cyclictest does (0) unless "
                         "--default-system")
    ap.add_argument("--url", default="udpm://239.255.76.99:7699?ttl=0")
    ap.add_argument("--log", default=None, help="file for kinctld's stderr")
    a = ap.parse_args()

    cfg = tempfile.NamedTemporaryFile("w", suffix=".cfg", delete=False)
    cfg.write("controller = {\n"
              f"  period_us = {a.period_us};\n"
              '  angles = "rad";\n'
              f"  home = [{', '.join(repr(v) for v in HOME)}];\n"
              "  stats_hz = 0.01;\n"
              f"  rt = {{ priority = {a.priority}; cpu = {a.cpu}; mlock = true; }};\n"
              "};\n")
    cfg.close()

    lc = lcm.LCM(a.url)
    sp_times = {}      # goal_id -> receipt time of its first setpoint
    counters = {"setpoints": 0, "moving": 0, "gaps": 0, "last_cycle": None}
    statuses, stats = [], []
    first_sp = {}

    def on_setpoint(channel, data):
        now = time.monotonic()
        _, cycle, goal_id, state = SP_HEAD.unpack_from(data)
        c = counters
        c["setpoints"] += 1
        if c["last_cycle"] is not None and cycle != c["last_cycle"] + 1:
            c["gaps"] += 1
        c["last_cycle"] = cycle
        if state == MOVING and goal_id > 0:
            c["moving"] += 1
        if goal_id not in sp_times:
            sp_times[goal_id] = now
        if not first_sp:
            first_sp["msg"] = setpoint_t.decode(data)

    def on_status(channel, data):
        statuses.append(status_t.decode(data))

    def on_stats(channel, data):
        stats.append(stats_t.decode(data))

    sub = lc.subscribe(PREFIX + "SETPOINT", on_setpoint)
    sub.set_queue_capacity(100000)
    lc.subscribe(PREFIX + "STATUS", on_status).set_queue_capacity(10000)
    lc.subscribe(PREFIX + "STATS", on_stats)

    # The PM QoS request lasts while the file stays open (as cyclictest's).
    pm_qos = None
    if a.dma_latency is not None:
        pm_qos = open("/dev/cpu_dma_latency", "wb", buffering=0)
        pm_qos.write(struct.pack("i", a.dma_latency))
    daemon = local.Kinctld("--config", cfg.name, binary=a.kinctld, url=a.url, prefix=PREFIX, rt=True,
                           stderr=a.log or os.devnull, stdout=True,
                           wrapper=["nice", "-n", str(a.nice)] if a.nice else ())
    try:
        t0 = time.monotonic()
        while not first_sp:
            lc.handle_timeout(100)
            if daemon.proc.poll() is not None:
                sys.exit(f"kinctld exited with {daemon.proc.returncode} before its first setpoint")
            if time.monotonic() - t0 > 10:
                sys.exit("no setpoint from kinctld within 10 s")
        sp0 = first_sp["msg"]
        centre = list(sp0.position)
        orient = list(sp0.orientation)

        # Targets on a circle of radius r in the y-z plane around the start
        # point; arcs pass through the circle's point half-way between.
        r, k_per_turn = 0.08, 12

        def point(k):
            th = 2 * math.pi * k / k_per_turn
            return [centre[0], centre[1] + r * math.cos(th) - r, centre[2] + r * math.sin(th)]

        sent = {}  # goal_id -> publish time
        answered = {}  # goal_id -> its final event (or REJECTED)
        final_events = (status_t.COMPLETED, status_t.REJECTED, status_t.ABORTED, status_t.EVENT_FAULT,
                        status_t.PREEMPTED)
        goal_id, k = 0, 0
        seen = 0
        start = time.monotonic()
        end = start + a.duration
        current_deadline = 0.0
        while True:
            now = time.monotonic()
            if now >= end:
                break
            for s in statuses[seen:]:
                if s.event in final_events:
                    answered.setdefault(s.event_goal_id, s.event)
            seen = len(statuses)
            if goal_id == 0 or goal_id in answered or now > current_deadline:
                goal_id += 1
                if goal_id % 2:
                    g = goal_line_t()
                    g.position = point(k + 1)
                    k += 1
                else:
                    g = goal_arc_t()
                    g.via = point(k + 1)
                    g.position = point(k + 2)
                    k += 2
                g.mode = g.QUEUE
                g.goal_id = goal_id
                g.orientation = orient
                g.utime = int(time.time() * 1e6)
                data = g.encode()
                channel = PREFIX + ("GOAL_LINE" if isinstance(g, goal_line_t) else "GOAL_ARC")
                sent[goal_id] = time.monotonic()
                lc.publish(channel, data)
                current_deadline = sent[goal_id] + 5.0  # no answer: go on
            lc.handle_timeout(max(1, min(20, int((end - time.monotonic()) * 1000))))
        run_s = time.monotonic() - start

        daemon.stop(signal.SIGTERM, timeout=15, while_waiting=lambda: lc.handle_timeout(50))
        # Whatever is still queued on the socket (the final status and stats).
        while lc.handle_timeout(200) > 0:
            pass
        if daemon.hung:
            sys.exit("kinctld did not exit within 15 s of SIGTERM")
    finally:
        daemon.stop(signal.SIGKILL)
        os.unlink(cfg.name)
        if pm_qos is not None:
            pm_qos.close()

    events = {}
    reasons = []
    for s in statuses:
        if s.event in (status_t.ACCEPTED, status_t.REJECTED):
            events.setdefault(s.event_goal_id, s.event)
            if s.event == status_t.REJECTED and len(reasons) < 3:
                reasons.append(f"goal {s.event_goal_id}: {s.reason}")
    lat = sorted((sp_times[g] - t) * 1e3 for g, t in sent.items() if g in sp_times)
    final = stats[-1] if stats else None
    out = {
        "period_us": a.period_us,
        "duration_s": round(run_s, 3),
        "daemon_exit": daemon.proc.returncode,
        "goals_sent": len(sent),
        "goals_accepted": sum(1 for g in sent if events.get(g) == status_t.ACCEPTED),
        "goals_rejected": sum(1 for g in sent if events.get(g) == status_t.REJECTED),
        "goals_unanswered": sum(1 for g in sent if g not in events),
        "goals_completed": sum(1 for g in sent if answered.get(g) == status_t.COMPLETED),
        "reject_reasons": reasons,
        "goal_to_setpoint_ms": {"n": len(lat), "p50": percentile(lat, 0.5), "p99": percentile(lat, 0.99),
                                "max": lat[-1] if lat else float("nan")},
        "setpoints_received": counters["setpoints"],
        "setpoint_gaps": counters["gaps"],
        "moving_fraction": counters["moving"] / max(1, counters["setpoints"]),
        # the motion a goal's dry run follows tick by tick (kc_check_goal)
        "mean_motion_s": counters["moving"] * a.period_us * 1e-6 / max(1, len(sent)),
        "stats_messages": len(stats),
        "whole_run": len(stats) == 1,
    }
    if final is not None:
        out["daemon"] = {f: getattr(final, f) for f in (
            "period_ns", "cycles", "latency_p50_ns", "latency_p99_ns", "latency_p999_ns", "latency_max_ns",
            "compute_p50_ns", "compute_p99_ns", "compute_max_ns", "overruns", "msgs_in", "msgs_invalid",
            "msgs_out", "msgs_dropped", "rejections")}
    json.dump(out, sys.stdout)
    print()


if __name__ == "__main__":
    main()
