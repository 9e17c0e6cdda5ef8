# SPDX-License-Identifier: BSD-3-Clause
"""kinctl's demo: the real daemon, driven by the real CLI.

    python -m kinctl.demo [--out out] [--kinctld build/daemon/kinctld]

Starts kinctld (--no-rt) on the built-in puma560 on a private LCM URL, logs
every setpoint and status event to CSV, runs a scripted sequence of `kinctl`
commands (a joint move, a line, an arc, a blended multi-point path, a goal
preempted by a --replace goal mid-motion, a stop mid-motion), shuts the
daemon down with SIGTERM, plots the log to a PNG and prints a summary.
scripts/demo.sh builds the tree and runs this.
"""
import argparse
import csv
import os
import re
import shlex
import subprocess
import sys
import time

from kinctl import logcsv
from kinctl.local import MULTICAST_HELP, Kinctld, ensure_multicast, unique_url
from kinctl.programs import SOURCE_DIR

# The sequence: (goal id or None, label for the plot, kinctl arguments, seconds to sleep after).
QN_DEG = "0,45,-180,0,45,0"  # puma560's nominal pose: elbow up, wrist not singular
TOOL_DOWN = "0.7071068,0,0.7071068,0"  # the tool orientation at that pose (w, x, y, z)
SEQUENCE = [
    (1, "joint move", ["--deg", "goal", "joint", "--q", QN_DEG, "--id", "1", "--wait"], 0),
    (2, "line", ["goal", "line", "--to", f"0.6,0.05,0.5,{TOOL_DOWN}", "--speed", "0.25", "--id", "2", "--wait"], 0),
    (3, "arc", ["goal", "arc", "--via", "0.65,0.2,0.62", "--to", f"0.6,0.05,0.74,{TOOL_DOWN}", "--id", "3",
                "--wait"], 0),
    (4, "blended path", ["goal", "path", "--space", "joint", "--method", "blend", "--blend-time", "0.3", "--points",
                         "0.3,0.9,-3.0,0.2,0.6,0.3;0.6,0.6,-2.8,0.0,0.9,0.6;0.2,0.5,-3.1,-0.3,0.8,0.0;"
                         "-0.2,0.8,-2.9,0.0,0.7,-0.3", "--id", "4", "--wait"], 0),
    (5, "move", ["goal", "joint", "--q", "1.2,0.4,-2.6,0.8,0.4,0.8", "--speed", "0.3", "--id", "5"], 0.7),
    (6, "--replace move", ["goal", "joint", "--q", "-0.5,0.9,-2.9,0.0,0.6,-0.5", "--replace", "--id", "6",
                           "--wait"], 0),
    (7, "move, then stop", ["goal", "joint", "--q", "0.9,0.5,-2.7,0.5,0.9,0.5", "--speed", "0.4", "--id", "7"], 0.6),
    (None, None, ["stop", "--wait"], 0),
    (None, None, ["status"], 0),
]


def joint_rate_limits(model_file):
    """qd limits in order from a description file (models/<arm>.cfg), or None."""
    try:
        with open(model_file) as f:
            text = f.read()
    except OSError:
        return None
    return [float(v) for v in re.findall(r"\bqd\s*=\s*([-+0-9.eE]+)\s*;", text)] or None


def run_cli(args, url, echo=True, timeout=120.0):
    """Runs `kinctl args...` with LCM_DEFAULT_URL=url; returns (exit code, output)."""
    env = dict(os.environ, LCM_DEFAULT_URL=url)
    if echo:
        print(f"\n\033[1m$ kinctl {' '.join(shlex.quote(a) for a in args)}\033[0m", flush=True)
    r = subprocess.run([sys.executable, "-m", "kinctl"] + args, env=env, capture_output=True, text=True,
                       timeout=timeout)
    out = r.stdout + r.stderr
    if echo:
        sys.stdout.write(out)
        sys.stdout.flush()
    return r.returncode, out


def run_demo(out_dir="out", kinctld=None, echo=True, small_png=None, slow=1.0):
    """Runs the demo; returns the summary (a dict, see summarize) with the plot's info under "plot"."""
    from kinctl.client import Client
    from kinctl.plot import plot_run

    os.makedirs(out_dir, exist_ok=True)
    if not ensure_multicast():
        raise RuntimeError(MULTICAST_HELP)
    url = unique_url()
    csv_path, ev_path = os.path.join(out_dir, "demo.csv"), os.path.join(out_dir, "demo-events.csv")
    png_path = os.path.join(out_dir, "demo.png")
    say = print if echo else (lambda *a, **k: None)
    say(f"kinctl demo: kinctld on the built-in puma560 at 1 kHz, LCM_DEFAULT_URL={url}", flush=True)

    d = Kinctld("--model", "puma560", binary=kinctld, url=url, stderr=os.path.join(out_dir, "kinctld.log"))
    results = []
    try:
        d.wait_ready(10.0 * slow)
        with open(csv_path, "w", newline="") as f, open(ev_path, "w", newline="") as fe:
            writer = logcsv.SetpointWriter(f)
            ev_writer = csv.writer(fe, lineterminator="\n")
            ev_writer.writerow(logcsv.EVENT_HEADER)
            events = []

            def on_status(st):
                if st.event != 0:
                    ev_writer.writerow(logcsv.event_row(st))
                    events.append(st)
            with Client(url, on_setpoint=writer.write, on_status=on_status) as rec:
                rec.wait_daemon(5.0 * slow)
                time.sleep(0.2)
                for gid, label, args, pause in SEQUENCE:
                    if "--timeout" not in args and "--wait" in args:
                        args = args + (["--timeout", f"{60 * slow:g}"] if slow != 1.0 else [])
                    rc, out = run_cli(args, url, echo, timeout=120.0 * slow)
                    results.append((gid, label, args, rc))
                    time.sleep(pause)
                time.sleep(0.3)  # the last setpoints at rest
        say("\n\033[1m$ kill -TERM kinctld\033[0m", flush=True)
    finally:
        rc_daemon = d.stop()
    say(d.stderr.strip())

    labels = {gid: f"{gid}: {label}" for gid, label, _, _ in results if gid}
    info = plot_run(csv_path, png_path, events=ev_path, labels=labels, model="puma560",
                    title="kinctl demo: kinctld on puma560 driven by the kinctl CLI (1 kHz setpoints)")
    if small_png:
        plot_run(csv_path, small_png, events=ev_path, labels=labels, dpi=60, model="puma560",
                 title="kinctl demo: kinctld on puma560 driven by the kinctl CLI (1 kHz setpoints)")
    summary = summarize(csv_path, ev_path, results, rc_daemon)
    summary["plot"] = info
    summary["files"] = {"csv": csv_path, "events": ev_path, "png": png_path}
    return summary


def summarize(csv_path, ev_path, results, rc_daemon):
    cols = logcsv.read(csv_path)
    events = logcsv.read_events(ev_path)
    sent = [gid for gid, _, _, _ in results if gid]
    count = {}
    for e in events:
        if e["goal_id"] in sent:
            count[e["event"]] = count.get(e["event"], 0) + 1
    n = sum(1 for k in cols if re.fullmatch(r"qd\d+", k))
    cycles = cols["cycle"]
    span = cycles[-1] - cycles[0] + 1
    limits = joint_rate_limits(os.path.join(SOURCE_DIR, "models", "puma560.cfg"))
    max_qd = [max(abs(v) for v in cols[f"qd{j}"]) for j in range(1, n + 1)]
    return {
        "goals_sent": len(sent),
        "accepted": count.get("ACCEPTED", 0), "rejected": count.get("REJECTED", 0),
        "completed": count.get("COMPLETED", 0), "preempted": count.get("PREEMPTED", 0),
        "aborted": count.get("ABORTED", 0), "faults": count.get("FAULT", 0),
        "cli_exit_codes": [rc for _, _, _, rc in results],
        "setpoints": len(cycles), "cycle_span": span, "missing": span - len(cycles),
        "max_qd": max_qd, "qd_limits": limits,
        "final_q": [cols[f"q{j}"][-1] for j in range(1, n + 1)],
        "final_position": [cols[k][-1] for k in ("x", "y", "z")],
        "final_orientation": [cols[k][-1] for k in ("qw", "qx", "qy", "qz")],
        "daemon_exit": rc_daemon,
    }


def print_summary(s):
    print("\n\033[1mSummary\033[0m")
    print(f"  goals      {s['goals_sent']} sent, {s['accepted']} accepted, {s['completed']} completed, "
          f"{s['preempted']} preempted, {s['aborted']} aborted, {s['rejected']} rejected")
    print(f"  cycles     {s['setpoints']} setpoints logged over a span of {s['cycle_span']} cycles "
          f"({s['missing']} missing)")
    if s["qd_limits"]:
        ratios = [m / l for m, l in zip(s["max_qd"], s["qd_limits"])]
        print("  max |qd|   " + "  ".join(f"q{j + 1} {m:.2f}/{l:g}" for j, (m, l) in
                                         enumerate(zip(s["max_qd"], s["qd_limits"])))
              + f" rad/s (highest {max(ratios) * 100:.0f} % of its limit)")
    else:
        print("  max |qd|   " + " ".join(f"{m:.2f}" for m in s["max_qd"]) + " rad/s")
    p, o = s["final_position"], s["final_orientation"]
    print(f"  final pose x,y,z = {p[0]:.4f}, {p[1]:.4f}, {p[2]:.4f} m; "
          f"q(w,x,y,z) = {o[0]:.4f}, {o[1]:.4f}, {o[2]:.4f}, {o[3]:.4f}")
    print(f"  kinctld    exit {s['daemon_exit']} after SIGTERM")
    f = s["files"]
    print(f"  files      {f['csv']}, {f['events']}, {f['png']}")


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m kinctl.demo", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default="out", help="output directory (default out)")
    p.add_argument("--kinctld", default=None, help="the daemon (default: $KINCTLD, build/daemon/kinctld)")
    p.add_argument("--small-png", default=None, metavar="PNG", help="also a small copy of the plot (for docs/)")
    args = p.parse_args(argv)
    try:
        s = run_demo(args.out, args.kinctld, small_png=args.small_png)
    except (RuntimeError, FileNotFoundError) as e:
        print(f"demo: {e}", file=sys.stderr)
        return 1
    print_summary(s)
    ok = (s["daemon_exit"] == 0 and s["missing"] == 0 and s["cli_exit_codes"].count(0) == len(s["cli_exit_codes"]))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
