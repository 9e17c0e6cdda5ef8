# SPDX-License-Identifier: BSD-3-Clause
"""soak.py - kinctld under a random goal stream for a long time, then the
books: every goal answered, every accepted goal ended, a setpoint for every
cycle, memory flat. Started by soak.sh (which loads the other CPU).

Goals, at random every 0.05-1 s: joint moves anywhere within 90 % of the
ranges, lines and arcs around the nominal pose, joint and Cartesian paths,
short servo twist streams; a fifth of them replace the motion in progress;
now and then STOP, PAUSE/RESUME, or an ESTOP followed by RESET. Some goals
are bad on purpose (a target outside the limits, an unreachable line): they
are counted as rejected, which is what they must be.

Printed at the end (and as JSON with --json FILE): cycles, overruns, wake-up
latency max (when it came, and how many one-second stats windows had a
wake-up over 1 ms late), goals sent = accepted + rejected (a servo stream whose goal
ended, say by its timeout while the sender stalled, starts a new goal under
its id: those restarts are counted with the goals sent), completed +
preempted + aborted = accepted, setpoints received = cycles, kinctld's resident memory at
the start and the end. Exit status 1 when a book does not balance.
"""
import argparse
import json
import random
import signal
import sys
import tempfile
import threading
import time

import lcm

from kinctl import client, local
from kinctl.msgs import event_name
from kinctl_msgs import command_t, setpoint_t, stats_t, status_t

QN = [0.0, 0.7854, -3.1416, 0.0, 0.7854, 0.0]
LIMITS = [(-2.79, 2.79), (-0.785, 3.93), (-3.93, 0.785), (-1.92, 2.97), (-1.75, 1.75), (-4.64, 4.64)]
ENDS = {status_t.COMPLETED: "completed", status_t.PREEMPTED: "preempted", status_t.ABORTED: "aborted"}


def rss_kib(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return -1


class Books:
    """What came back from the daemon, kept by the LCM thread."""

    def __init__(self):
        self.lock = threading.Lock()
        self.setpoints = 0
        self.first_cycle = self.last_cycle = None
        self.cycle_gaps = 0
        self.last = None
        # Per goal id, in order: every answer (ACCEPTED / REJECTED) and every
        # end. A servo message whose goal has ended starts a new goal under
        # the same id (daemon/README), so a servo id may hold several goals;
        # any other id must hold exactly one.
        self.answers = {}   # goal_id -> [answer, ...]
        self.ends = {}      # goal_id -> [end event, ...]
        self.servo_ids = set()
        self.out_of_order = 0   # answered again before the previous goal ended, or ended unanswered
        self.history = {}   # goal_id -> [(utime, event name, reason, state)]: printed for an id out of order
        self.odd_ids = []
        self.latency_max_ns = 0  # over every stats window (each stats_t covers the cycles since the last)
        self.latency_max_at_s = 0.0  # when that window ended, in seconds since the first
        self.windows_over_1ms = 0  # windows whose worst wake-up was over 1 ms late: how often stalls came
        self.first_stats_utime = None
        self.stats_windows = 0
        self.stats = None
        self.reject_reasons = {}  # reason token -> count

    def on_setpoint(self, channel, data):
        sp = setpoint_t.decode(data)
        with self.lock:
            self.setpoints += 1
            if self.last_cycle is not None and sp.cycle != self.last_cycle + 1:
                self.cycle_gaps += 1
            if self.first_cycle is None:
                self.first_cycle = sp.cycle
            self.last_cycle = sp.cycle
            self.last = sp

    def on_status(self, channel, data):
        st = status_t.decode(data)
        with self.lock:
            gid = st.event_goal_id
            answers, ends = self.answers.setdefault(gid, []), self.ends.setdefault(gid, [])
            if gid:
                self.history.setdefault(gid, []).append((st.utime, event_name(st.event), st.reason,
                                                         st.state))
            odd = False
            if st.event in (status_t.ACCEPTED, status_t.REJECTED):
                if answers and self.open_goals(gid):
                    odd = True
                answers.append(st.event)
                if st.event == status_t.REJECTED:
                    token = st.reason.split(":")[0]
                    self.reject_reasons[token] = self.reject_reasons.get(token, 0) + 1
            elif st.event in ENDS:
                if not self.open_goals(gid):
                    odd = True
                ends.append(st.event)
            if odd:
                self.out_of_order += 1
                self.odd_ids.append(gid)

    def open_goals(self, gid):
        """Accepted goals under this id that have not ended yet."""
        return self.answers[gid].count(status_t.ACCEPTED) - len(self.ends[gid])

    def tally(self):
        """(answers, ends, goals the servo streams restarted, ids answered more than once that are no servo stream)"""
        answers = [a for v in self.answers.values() for a in v]
        ends = [e for v in self.ends.values() for e in v]
        restarts = sum(len(v) - 1 for gid, v in self.answers.items() if gid in self.servo_ids and v)
        twice = sum(1 for gid, v in self.answers.items() if gid not in self.servo_ids and len(v) > 1)
        return answers, ends, restarts, twice

    def on_stats(self, channel, data):
        with self.lock:
            self.stats = st = stats_t.decode(data)
            if self.first_stats_utime is None:
                self.first_stats_utime = st.utime
            if st.latency_max_ns > self.latency_max_ns:
                self.latency_max_ns = st.latency_max_ns
                self.latency_max_at_s = (st.utime - self.first_stats_utime) / 1e6
            self.windows_over_1ms += st.latency_max_ns > 1_000_000
            self.stats_windows += 1


def random_goal(rng, gid, here):
    """A goal message (bad on purpose about one time in twelve)."""
    kind = rng.choice(["joint", "joint", "line", "arc", "path", "cpath"])
    replace = rng.random() < 0.2
    bad = rng.random() < 1 / 12
    if kind == "joint":
        q = [lo + (hi - lo) * (0.05 + 0.9 * rng.random()) for lo, hi in LIMITS]
        if bad:
            q[rng.randrange(6)] = 10.0
        return client.make_goal_joint(q, goal_id=gid, replace=replace, vel_scale=rng.uniform(0.2, 1.0),
                                      acc_scale=rng.uniform(0.2, 1.0))
    x, y, z = here
    orient = [0.7071068, 0.0, 0.7071068, 0.0]
    d = lambda: rng.uniform(-0.08, 0.08)
    if kind == "line":
        to = [x + d(), y + d(), z + d()] + orient
        if bad:
            to[0] += 2.0
        return client.make_goal_line(to, goal_id=gid, replace=replace, speed=rng.uniform(0.05, 0.4))
    if kind == "arc":
        return client.make_goal_arc([x + d(), y + d(), z + d()], [x + d(), y + d(), z + d()] + orient,
                                    goal_id=gid, replace=replace)
    if kind == "path":
        pts = [[c + rng.uniform(-0.2, 0.2) for c in QN] for _ in range(rng.randint(1, 5))]
        return client.make_goal_path(pts, method=rng.choice(["blend", "spline", "quintic"]), goal_id=gid,
                                     replace=replace)
    pts = [[x + d(), y + d(), z + d()] + orient for _ in range(rng.randint(1, 4))]
    return client.make_goal_path(pts, space="cartesian", method=rng.choice(["blend", "spline"]), goal_id=gid,
                                 replace=replace)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--kinctld", help="the daemon (default: kinctl.programs.find)")
    ap.add_argument("--duration", type=float, default=600.0, help="seconds (default 600)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--rt", action="store_true", help="SCHED_FIFO, pinned to the last CPU, mlockall")
    ap.add_argument("--json", help="also write the figures to this file")
    a = ap.parse_args()

    url = local.unique_url(subnet=79, port_base=40000)
    prefix = "KSOAK_"
    cfg = tempfile.NamedTemporaryFile("w", suffix=".cfg", delete=False)
    cfg.write('controller = {\n  angles = "rad";\n'
              f"  home = [{', '.join(map(repr, QN))}];\n"
              "  stats_hz = 1.0;\n  rt = { priority = 80; cpu = -1; mlock = true; };\n};\n")
    cfg.close()

    books = Books()
    lc = lcm.LCM(url)
    lc.subscribe(prefix + "SETPOINT", books.on_setpoint).set_queue_capacity(200000)
    lc.subscribe(prefix + "STATUS", books.on_status).set_queue_capacity(100000)
    lc.subscribe(prefix + "STATS", books.on_stats)
    running = True

    def pump():
        while running:
            lc.handle_timeout(50)

    pumper = threading.Thread(target=pump, daemon=True)
    pumper.start()
    log = tempfile.NamedTemporaryFile("w", suffix=".log", delete=False)
    log.close()
    daemon = local.Kinctld("--config", cfg.name, binary=a.kinctld, url=url, prefix=prefix, rt=a.rt, stderr=log.name,
                           stdout=True)
    rng = random.Random(a.seed)
    sent = 0
    sent_log = {}   # goal_id -> what was sent, when (wall clock)
    commands = []   # (utime, command)
    try:
        deadline = time.monotonic() + 10
        while books.last is None:
            if daemon.proc.poll() is not None or time.monotonic() > deadline:
                sys.exit(f"kinctld did not start (log: {log.name})")
            time.sleep(0.05)
        time.sleep(2.0)
        rss_start = rss_kib(daemon.proc.pid)
        start = time.monotonic()
        next_report = start + 10
        gid = 1000
        while time.monotonic() - start < a.duration:
            with books.lock:
                here = list(books.last.position)
                state = books.last.state
            r = rng.random()
            if state in (setpoint_t.FAULT, setpoint_t.ESTOP) or r < 0.02:
                cmd = command_t()
                cmd.command = command_t.ESTOP if r < 0.01 and state not in (setpoint_t.FAULT, setpoint_t.ESTOP) \
                    else command_t.RESET
                cmd.utime = int(time.time() * 1e6)
                lc.publish(prefix + "COMMAND", cmd.encode())
                commands.append((cmd.utime, cmd.command))
            elif r < 0.06:
                cmd = command_t()
                cmd.command = rng.choice([command_t.STOP, command_t.PAUSE, command_t.RESUME])
                cmd.utime = int(time.time() * 1e6)
                lc.publish(prefix + "COMMAND", cmd.encode())
                commands.append((cmd.utime, cmd.command))
            elif r < 0.10:
                # A short servo stream (its updates carry one goal id).
                gid += 1
                sent += 1
                with books.lock:
                    books.servo_ids.add(gid)
                twist = [rng.uniform(-0.03, 0.03) for _ in range(3)] + [0.0, 0.0, 0.0]
                count = rng.randint(5, 40)
                sent_log[gid] = f"servo stream of {count} messages from {time.time():.6f}"
                for _ in range(count):
                    m = client.make_servo_message(gid, twist=twist, replace=True, timeout_s=0.1)
                    lc.publish(prefix + "GOAL_SERVO", m.encode())
                    time.sleep(0.01)
                sent_log[gid] += f" to {time.time():.6f}"
            else:
                gid += 1
                sent += 1
                m = random_goal(rng, gid, here)
                channel = {"goal_joint_t": "GOAL_JOINT", "goal_line_t": "GOAL_LINE", "goal_arc_t": "GOAL_ARC",
                           "goal_path_t": "GOAL_PATH"}[type(m).__name__]
                sent_log[gid] = f"{type(m).__name__} mode {m.mode} at {time.time():.6f}"
                lc.publish(prefix + channel, m.encode())
            time.sleep(rng.uniform(0.05, 1.0))
            now = time.monotonic()
            if now >= next_report:
                next_report += 10
                with books.lock:
                    answers, ends, _, _ = books.tally()
                    print(f"soak: {now - start:6.0f}/{a.duration:.0f} s  goals {sent}  answered {len(answers)}"
                          f"  ended {len(ends)}  setpoints {books.setpoints}  rss {rss_kib(daemon.proc.pid)} KiB",
                          file=sys.stderr, flush=True)
        # Quiet down: stop, let the last answers and ends arrive.
        cmd = command_t()
        cmd.command = command_t.STOP
        lc.publish(prefix + "COMMAND", cmd.encode())
        time.sleep(3.0)
        rss_end = rss_kib(daemon.proc.pid)
        code = daemon.stop(signal.SIGTERM, timeout=30)
        time.sleep(1.0)
    finally:
        daemon.stop(signal.SIGKILL)
        running = False
        pumper.join(2)
    with books.lock:
        st = books.stats
        answers, ended, restarts, twice = books.tally()
        accepted, rejected = answers.count(status_t.ACCEPTED), answers.count(status_t.REJECTED)
        ends = {name: ended.count(code_) for code_, name in ENDS.items()}
        received_cycles = books.last_cycle - books.first_cycle + 1
        figures = {
            "duration_s": a.duration, "cycles": st.cycles, "overruns": st.overruns,
            "latency_max_us": books.latency_max_ns / 1000, "latency_max_at_s": round(books.latency_max_at_s, 1),
            "stats_windows": books.stats_windows, "windows_over_1ms": books.windows_over_1ms, "goals_sent": sent,
            "accepted": accepted,
            "rejected": rejected, "rejected_by_reason": dict(sorted(books.reject_reasons.items())),
            "servo_restarts": restarts, "answered_twice": twice, **ends, "out_of_order": books.out_of_order,
            "setpoints_received": books.setpoints, "setpoint_cycle_gaps": books.cycle_gaps,
            "cycles_seen": received_cycles, "daemon_dropped": st.msgs_dropped, "rss_start_kib": rss_start,
            "rss_end_kib": rss_end, "exit_code": code,
        }
    checks = [
        ("goals sent (+ servo restarts) = accepted + rejected", sent + restarts == accepted + rejected and twice == 0),
        ("completed + preempted + aborted = accepted, each after its answer",
         sum(ends.values()) == accepted and books.out_of_order == 0),
        ("setpoints received = cycles (none missing)",
         books.setpoints == received_cycles and books.cycle_gaps == 0 and st.msgs_dropped == 0),
        ("memory flat (end within 1 MiB of start)", rss_end - rss_start <= 1024),
        ("clean exit", code == 0),
    ]
    print(f"\nsoak: {a.duration:.0f} s, seed {a.seed}, log {log.name}")
    for k, v in figures.items():
        print(f"  {k:28s} {v}")
    for name, ok in checks:
        print(f"  {'PASS' if ok else 'FAIL'}  {name}")
    for gid in books.odd_ids:
        # The goal out of order and its neighbours: what was sent, what came back.
        print(f"\ngoal {gid} out of order:")
        for near in range(gid - 2, gid + 3):
            print(f"  {near}: sent {sent_log.get(near, '-')}")
            for utime, event, reason, state in books.history.get(near, []):
                print(f"      {utime / 1e6:.6f} {event} {reason!r} state {state}")
        t0 = min((u for u, *_ in books.history.get(gid, [])), default=0)
        print("  commands within 2 s: " + ", ".join(f"{u / 1e6:.6f} {c}" for u, c in commands if abs(u - t0) < 2e6))
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"figures": figures, "checks": {n: ok for n, ok in checks}}, f, indent=1)
    return 0 if all(ok for _, ok in checks) else 1


if __name__ == "__main__":
    sys.exit(main())
