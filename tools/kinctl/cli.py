"""`kinctl`: send goals and commands to kinctld, read its status, log its setpoints.

Exit status: 0 success; 1 the goal was rejected, preempted, aborted or
faulted, a wait timed out, or no daemon answered; 2 bad command line.
"""
import argparse
import json
import math
import os
import re
import signal
import sys
import threading
import time

EXAMPLES = """\
examples (start a daemon first: build/daemon/kinctld --no-rt):
  kinctl status
  kinctl --deg goal joint --q 0,45,-180,0,45,0 --wait
  kinctl goal line --to 0.6,0,0.55,0.7071,0,0.7071,0 --speed 0.2 --wait
  kinctl goal arc --via 0.6,0.1,0.65 --to 0.6,0,0.75,0.7071,0,0.7071,0 --wait
  kinctl goal path --space joint --method blend --points "0,0.8,-3,0,0.8,0;0.3,0.6,-2.8,0,0.9,0" --wait
  kinctl goal servo --twist 0,0.05,0,0,0,0 --rate 100 --duration 1 --wait
  kinctl stop --wait
  kinctl log --csv run.csv --duration 5
  kinctl record run.lcmlog --duration 5 && kinctl replay run.lcmlog
  kinctl import-urdf arm.urdf -o arm.cfg
  kinctl plot run.csv -o run.png
  kinctl view --save arm.gif --duration 5
"""

STALE_MIN_S, STALE_MAX_S = 0.05, 0.1


class UsageError(Exception):
    """Bad input found after parsing: exit 2."""


def numbers(text):
    """'a,b,c' -> [a, b, c] as floats; argparse reports a bad one."""
    out = []
    for part in text.split(","):
        part = part.strip()
        try:
            v = float(part)
        except ValueError:
            raise argparse.ArgumentTypeError(f"'{part}' is not a number (in '{text}')") from None
        if not math.isfinite(v):
            raise argparse.ArgumentTypeError(f"'{part}' is not a finite number (in '{text}')")
        out.append(v)
    return out


def vector(count, what):
    def parse(text):
        v = numbers(text)
        if len(v) != count:
            raise argparse.ArgumentTypeError(f"needs {count} numbers ({what}), got {len(v)} in '{text}'")
        return v
    parse.__name__ = f"{count} numbers"
    return parse


def points(text):
    """'p;p;...' -> a list of number lists."""
    pts = [p for p in text.split(";") if p.strip()]
    if not pts:
        raise argparse.ArgumentTypeError("no points given (format: 'a,b,c;d,e,f;...')")
    return [numbers(p) for p in pts]


def positive(text):
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"{text} must be > 0")
    return v


def nonneg(text):
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not (math.isfinite(v) and v >= 0):
        raise argparse.ArgumentTypeError(f"{text} must be >= 0")
    return v


def goal_id(text):
    try:
        v = int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not an integer") from None
    if v == 0 or not -2 ** 63 <= v < 2 ** 63:
        raise argparse.ArgumentTypeError(f"{text}: a goal id is a non-zero 64-bit integer (0 means no goal)")
    return v


# Options whose value may start with '-' (a negative number): argparse would
# take "-0.5,1" for an option, so such values are glued on: --q=-0.5,1.
VALUE_OPTIONS = {"--q", "--to", "--via", "--points", "--times", "--pose", "--twist"}
NEGATIVE = re.compile(r"^-[0-9.]")


def _glue_negative_values(argv):
    out, i = [], 0
    while i < len(argv):
        a = argv[i]
        if a in VALUE_OPTIONS and i + 1 < len(argv) and NEGATIVE.match(argv[i + 1]):
            out.append(f"{a}={argv[i + 1]}")
            i += 2
        else:
            out.append(a)
            i += 1
    return out


class Formatter(argparse.RawDescriptionHelpFormatter):
    pass


def _global_options(p, suppress):
    d = (lambda v: argparse.SUPPRESS) if suppress else (lambda v: v)
    g = p.add_argument_group("connection")
    g.add_argument("--lcm-url", default=d(os.environ.get("LCM_DEFAULT_URL") or None), metavar="URL",
                   help="LCM URL of the daemon (default: $LCM_DEFAULT_URL, then LCM's default "
                        "udpm://239.255.76.67:7667?ttl=0)")
    g.add_argument("--prefix", default=d("KINCTL_"), help="channel prefix (default KINCTL_)")
    g.add_argument("--deg", action="store_true", default=d(False),
                   help="joint values and angular rates in degrees (revolute joints)")
    g.add_argument("--connect-timeout", type=positive, default=d(2.0), metavar="S",
                   help="how long to wait for the daemon's first setpoint and for an answer (default 2 s)")


def _sub(subparsers, name, help_, example, parents):
    return subparsers.add_parser(name, help=help_, description=help_, epilog="example:\n  " + example,
                                 formatter_class=Formatter, parents=parents)


def _goal_options(p, cartesian):
    g = p.add_argument_group("goal")
    if cartesian:
        both = ""
        if cartesian == "path":
            both = " (a joint-space path: the fraction of the joint limits, as --joint-speed)"
        g.add_argument("--speed", type=nonneg, default=0.0, metavar="M_S",
                       help="tool speed (m/s); 0 or absent: the controller's default" + both)
        g.add_argument("--accel", type=nonneg, default=0.0, metavar="M_S2",
                       help="tool acceleration (m/s^2); 0 or absent: the controller's default"
                            + both.replace("speed", "accel"))
        g.add_argument("--joint-speed", type=nonneg, default=0.0, metavar="SCALE",
                       help="fraction of the joint velocity limits the motion may use, (0, 1]")
        g.add_argument("--joint-accel", type=nonneg, default=0.0, metavar="SCALE",
                       help="fraction of the joint acceleration limits, (0, 1]")
    else:
        g.add_argument("--speed", type=nonneg, default=0.0, metavar="SCALE",
                       help="fraction of the joint velocity limits, (0, 1] (default 1)")
        g.add_argument("--accel", type=nonneg, default=0.0, metavar="SCALE",
                       help="fraction of the joint acceleration limits, (0, 1] (default 1)")
    g.add_argument("--replace", action="store_true",
                   help="replace the motion in progress and the queue (default: queue behind them)")
    g.add_argument("--id", type=goal_id, default=None, help="goal id (default: a random one)")
    g.add_argument("--wait", action="store_true",
                   help="block until the goal completes (exit 0) or is rejected, preempted or aborted (exit 1)")
    g.add_argument("--timeout", type=positive, default=120.0, metavar="S",
                   help="with --wait: give up after S seconds (exit 1; default 120)")


def _angular_options(p):
    p.add_argument("--angular-speed", type=nonneg, default=0.0, metavar="W",
                   help="tool angular speed limit (rad/s, deg/s with --deg); 0: default")
    p.add_argument("--angular-accel", type=nonneg, default=0.0, metavar="A",
                   help="tool angular acceleration limit (rad/s^2, deg/s^2 with --deg); 0: default")


def build_parser():
    glob = argparse.ArgumentParser(add_help=False)
    _global_options(glob, suppress=True)
    parents = [glob]
    p = argparse.ArgumentParser(
        prog="kinctl", formatter_class=Formatter,
        description="Client of kinctld, kinctl's motion controller daemon: goals and commands out, "
                    "status and setpoints in, over LCM.",
        epilog=EXAMPLES + "\nexit status: 0 ok; 1 goal rejected/preempted/aborted, timeout or no daemon; "
                          "2 bad command line")
    _global_options(p, suppress=False)
    sub = p.add_subparsers(dest="command", metavar="COMMAND", required=True)

    goal = _sub(sub, "goal", "send a goal: joint, line, arc, path or servo",
                "kinctl goal joint --q 0,0.7854,-3.1416,0,0.7854,0 --wait", parents)
    gsub = goal.add_subparsers(dest="kind", metavar="KIND", required=True)

    j = _sub(gsub, "joint", "joint move: every joint to --q, synchronised to the slowest",
             "kinctl goal joint --q 0,0.7854,-3.1416,0,0.7854,0 --speed 0.5 --wait\n"
             "  kinctl --deg goal joint --q 0,45,-180,0,45,0", parents)
    j.add_argument("--q", type=numbers, required=True, metavar="A,B,...",
                   help="target joint values (rad, or deg with --deg; m for prismatic joints)")
    _goal_options(j, cartesian=False)

    ln = _sub(gsub, "line", "Cartesian straight line of the tool to a pose",
              "kinctl goal line --to 0.6,0,0.55,0.7071,0,0.7071,0 --speed 0.2 --wait", parents)
    ln.add_argument("--to", type=vector(7, "x,y,z,qw,qx,qy,qz"), required=True, metavar="X,Y,Z,QW,QX,QY,QZ",
                    help="end pose in the base frame: position (m), unit quaternion w,x,y,z")
    ln.add_argument("--slerp", action="store_true", help="orientation by quaternion slerp "
                                                          "(default: the two-rotation method)")
    _angular_options(ln)
    _goal_options(ln, cartesian=True)

    arc = _sub(gsub, "arc", "circular arc of the tool through --via to a pose",
               "kinctl goal arc --via 0.6,0.1,0.65 --to 0.6,0,0.75,0.7071,0,0.7071,0 --wait", parents)
    arc.add_argument("--via", type=vector(3, "x,y,z"), required=True, metavar="X,Y,Z",
                     help="a point the arc passes through, base frame (m)")
    arc.add_argument("--to", type=vector(7, "x,y,z,qw,qx,qy,qz"), required=True, metavar="X,Y,Z,QW,QX,QY,QZ",
                     help="end pose in the base frame: position (m), unit quaternion w,x,y,z")
    _angular_options(arc)
    _goal_options(arc, cartesian=True)

    path = _sub(gsub, "path", "multi-point path in joint or Cartesian space",
                "kinctl goal path --space joint --method blend --blend-time 0.3 \\\n"
                "      --points '0.2,0.9,-3,0.1,0.7,0.1;0.4,0.7,-2.9,0,0.9,0.2;0.1,0.6,-3.1,-0.1,0.8,0' --wait",
                parents)
    path.add_argument("--space", choices=("joint", "cartesian"), default="joint",
                      help="knots are joint vectors or poses x,y,z,qw,qx,qy,qz (default joint)")
    path.add_argument("--method", choices=("blend", "spline", "quintic", "lagrange"), default="blend",
                      help="lines with blends, cubic spline, quintic pieces, one Lagrange polynomial "
                           "(default blend)")
    path.add_argument("--points", type=points, required=True, metavar="P;P;...",
                      help="knots separated by ';', each comma-separated")
    path.add_argument("--times", type=numbers, default=None, metavar="T1,T2,...",
                      help="time of each knot after the start (s), increasing; default: from the limits")
    path.add_argument("--blend-time", type=nonneg, default=0.0, metavar="T",
                      help="blend time around each knot (s); blend only; 0: from the limits")
    path.add_argument("--shape", choices=("quartic", "parabolic"), default="quartic",
                      help="blend shape (blend only; default quartic)")
    path.add_argument("--ends", choices=("clamped", "natural"), default="clamped",
                      help="spline ends (spline only; default clamped)")
    _goal_options(path, cartesian="path")

    servo = _sub(gsub, "servo", "stream servo messages: track a pose or follow a twist, then let go",
                 "kinctl goal servo --twist 0,0.05,0,0,0,0 --rate 100 --duration 2 --replace --wait", parents)
    what = servo.add_mutually_exclusive_group(required=True)
    what.add_argument("--pose", type=vector(7, "x,y,z,qw,qx,qy,qz"), metavar="X,Y,Z,QW,QX,QY,QZ",
                      help="target pose to track, base frame")
    what.add_argument("--twist", type=vector(6, "vx,vy,vz,wx,wy,wz"), metavar="VX,VY,VZ,WX,WY,WZ",
                      help="tool twist to follow, base frame: m/s and rad/s (deg/s with --deg)")
    servo.add_argument("--rate", type=positive, default=100.0, metavar="HZ", help="messages per second (100)")
    servo.add_argument("--duration", type=positive, default=1.0, metavar="S", help="stream length (1 s)")
    servo.add_argument("--stale-ms", type=positive, default=None, metavar="MS",
                       help="the daemon stops the arm when no message came for this long "
                            "(default 3 periods, 50 .. 100 ms)")
    g = servo.add_argument_group("goal")
    g.add_argument("--replace", action="store_true", help="take over from the motion in progress "
                                                          "(default: queue behind it)")
    g.add_argument("--id", type=goal_id, default=None, help="stream's goal id (default: a random one)")
    g.add_argument("--wait", action="store_true", help="after the stream, wait until the arm is at rest; "
                                                       "exit 0 unless rejected or aborted otherwise")
    g.add_argument("--timeout", type=positive, default=30.0, metavar="S",
                   help="with --wait: give up after S seconds (default 30)")

    for name, help_ in (("stop", "decelerate along the path to rest and clear the queue"),
                        ("estop", "stop as hard as the limits allow; latched until reset"),
                        ("pause", "decelerate to rest on the path and hold"),
                        ("resume", "carry on after pause"),
                        ("reset", "clear a fault or a latched e-stop")):
        c = _sub(sub, name, help_, f"kinctl {name}" + (" --wait" if name in ("stop", "estop", "pause") else ""),
                 parents)
        c.add_argument("--wait", action="store_true",
                       help="block until the command has taken effect and the arm is at rest")
        c.add_argument("--timeout", type=positive, default=30.0, metavar="S", help="with --wait (default 30 s)")

    st = _sub(sub, "status", "print one status of the daemon", "kinctl status --json", parents)
    st.add_argument("--json", action="store_true", help="as one JSON object")

    lg = _sub(sub, "log", "write every setpoint to a CSV file",
              "kinctl log --csv run.csv --duration 10 --events events.csv", parents)
    lg.add_argument("--csv", required=True, metavar="FILE",
                    help="setpoints: utime,cycle,goal_id,state,q1..qn,qd1..qdn,qdd1..qddn,x,y,z,qw,qx,qy,qz")
    lg.add_argument("--duration", type=positive, default=None, metavar="S",
                    help="stop after S seconds (default: at Ctrl-C or SIGTERM)")
    lg.add_argument("--events", metavar="FILE", default=None,
                    help="also write status events: utime,cycle,goal_id,event,code,reason")

    pl = _sub(sub, "plot", "plot a run's setpoints: q, qd, qdd of every joint against time (each goal's "
                           "leading joint bold), the tool's speed along its path, the tool path in 3-D and "
                           "on XY, XZ, YZ; one colour per goal_id",
              "kinctl plot run.csv --events events.csv -o run.png --model puma560\n"
              "  kinctl plot run.lcmlog -o run.svg          # an LCM event log (lcm-logger); SVG\n"
              "  kinctl plot run.csv --model puma560 --zones-file kinctld.cfg --zone box:0.6,0,0.3,0.05,0.4,0.3",
              parents)
    pl.add_argument("csv", metavar="LOG", help="a setpoint CSV written by kinctl log --csv, or an LCM event log "
                                               "(lcm-logger format) holding <prefix>SETPOINT and <prefix>STATUS")
    pl.add_argument("--events", metavar="FILE", default=None,
                    help="with a CSV: the status events of kinctl log --events, to name how goals ended")
    pl.add_argument("-o", "--output", metavar="FILE", default=None,
                    help="output, .png or .svg by its extension (default: LOG with .png)")
    pl.add_argument("--title", default=None, help="figure title")
    arm = pl.add_mutually_exclusive_group()
    arm.add_argument("--model", default=None, metavar="NAME",
                     help="the daemon's built-in arm: a joint move's leading joint is then the planner's, from "
                          "each joint's limits (default: the joint that travels farthest)")
    arm.add_argument("--model-file", default=None, metavar="PATH", help="the daemon's robot description file, "
                                                                        "as --model")
    from kinctl.zonedraw import add_options
    add_options(pl)
    from kinctl.view import add_view_parser
    add_view_parser(sub, _sub, parents)

    from kinctl import datacmds
    datacmds.add_parsers(sub, _sub, parents, positive)

    ds = _sub(sub, "drivesim", "simulate CiA 402 drives (cyclic synchronous position) on a CAN interface: they "
                               "follow kinctld's RPDOs at each SYNC and answer with TPDOs and heartbeats; control "
                               "lines on stdin: fault/clear/silent/talk N, lag N S, vmax N C, quit",
              "kinctl drivesim --interface vcan0 --nodes 1-6 --period-ms 1 --lag 0.02\n"
              "  (then type: fault 3, clear 3, silent 2, talk 2, lag 1 0.5, quit)", parents)
    ds.add_argument("--interface", default="vcan0", help="SocketCAN interface (default vcan0)")
    ds.add_argument("--nodes", default="1-6", help="drive node ids: 1-6 or 1,2,5 (default 1-6)")
    ds.add_argument("--period-ms", type=positive, default=1.0, metavar="MS",
                    help="bus cycle: kinctld's period times sync_every (default 1 ms)")
    ds.add_argument("--heartbeat-ms", type=nonneg, default=100.0, metavar="MS",
                    help="each drive's heartbeat period; 0: none (default 100)")
    ds.add_argument("--lag", type=nonneg, default=0.0, metavar="S", help="first-order lag (s); 0: none (default)")
    ds.add_argument("--vmax", type=nonneg, default=0.0, metavar="COUNTS_S", help="speed limit; 0: none")
    ds.add_argument("--amax", type=nonneg, default=0.0, metavar="COUNTS_S2", help="acceleration limit; 0: none")
    ds.add_argument("--window", type=nonneg, default=0.0, metavar="COUNTS",
                    help="following error window: statusword bit 13 beyond it; 0: never (default)")
    ds.add_argument("--no-stdin", action="store_true", help="ignore stdin (run until SIGINT)")

    from kinctl import drive402
    drive402.add_parser(sub, _sub, parents, nonneg)

    cd = _sub(sub, "candecode", "print CAN frames decoded with kinctl's DBC (kinctl.dbc): a candump log "
                                "(candump -L, or its default format) or a live interface",
              "candump -L vcan0 | kinctl candecode\n  kinctl candecode --interface vcan0 --count 20\n"
              "  kinctl candecode run.log --json", parents)
    cd.add_argument("log", nargs="?", default=None, metavar="LOG", help="candump log file ('-' or absent: stdin)")
    cd.add_argument("--interface", default=None, help="read this interface live instead of a log")
    cd.add_argument("--count", type=int, default=None, metavar="N", help="stop after N frames")
    cd.add_argument("--duration", type=positive, default=None, metavar="S", help="live: stop after S seconds")
    cd.add_argument("--dbc", default=None, metavar="FILE", help="another DBC file (default: kinctl.dbc)")
    cd.add_argument("--nodes", default=None, help="decode for these drive node ids instead (e.g. 1-6)")
    cd.add_argument("--master", type=int, default=None, help="... and this master id (default 127)")
    cd.add_argument("--json", action="store_true", help="one JSON object per frame")
    cd.add_argument("--strict", action="store_true", help="exit 1 when a frame is not in the DBC")
    return p


def _say(*a):
    print(*a, flush=True)


def _err(*a):
    print("kinctl:", *a, file=sys.stderr, flush=True)


def _connect(args, **kw):
    from kinctl.client import Client
    c = Client(url=args.lcm_url, prefix=args.prefix, **kw)
    try:
        c.wait_daemon(args.connect_timeout)
    except Exception:
        c.close()
        raise
    return c


def _fmt(values, deg=False, digits=4):
    return " ".join(f"{math.degrees(v) if deg else v:.{digits}f}" for v in values)


def _answer(c, gid, kind, args):
    """Waits for the goal's answer (and with --wait, its end). Returns the exit code."""
    st = c.wait_answer(gid, args.connect_timeout)
    if st is None:
        _err(f"goal {gid} ({kind}): no answer from kinctld within {args.connect_timeout:g} s "
             f"(is the daemon overloaded, or another client using the same --prefix?)")
        return 1
    ev = c.event(st)
    if ev == "REJECTED":
        _err(f"goal {gid} ({kind}) REJECTED: {st.reason}")
        return 1
    if not args.wait:
        _say(f"goal {gid} ({kind}) {ev}" + ("" if ev != "ACCEPTED" else " (replacing)" if args.replace else ""))
        return 0 if ev in ("ACCEPTED", "COMPLETED") else 1
    _say(f"goal {gid} ({kind}) ACCEPTED, waiting")
    t0 = time.monotonic()
    st = c.wait_end(gid, args.timeout)
    if st is None:
        sp = c.setpoint
        _err(f"goal {gid}: timed out after {args.timeout:g} s (state {_state(sp)}, active goal {sp.goal_id})")
        return 1
    ev = c.event(st)
    if ev == "COMPLETED":
        _say(f"goal {gid} ({kind}) COMPLETED after {time.monotonic() - t0:.2f} s")
        return 0
    _err(f"goal {gid} ({kind}) {ev}" + (f": {st.reason}" if st.reason else ""))
    return 1


def _state(sp):
    from kinctl.msgs import state_name
    return state_name(sp.state) if sp is not None else "?"


def cmd_goal(args):
    from kinctl import client as kc
    deg = math.radians(1.0) if args.deg else 1.0
    if args.kind == "servo":
        return cmd_servo(args, deg)
    # Build (and check) the message before looking for the daemon: bad input is exit 2.
    common = dict(goal_id=args.id, replace=args.replace)
    if args.kind == "joint":
        msg = kc.make_goal_joint([v * deg for v in args.q], vel_scale=args.speed, acc_scale=args.accel, **common)
        kind = "joint"
    elif args.kind in ("line", "arc"):
        cart = dict(speed=args.speed, accel=args.accel, angular_speed=args.angular_speed * deg,
                    angular_accel=args.angular_accel * deg, vel_scale=args.joint_speed, acc_scale=args.joint_accel)
        if args.kind == "line":
            msg = kc.make_goal_line(args.to, slerp=args.slerp, **cart, **common)
        else:
            msg = kc.make_goal_arc(args.via, args.to, **cart, **common)
        kind = args.kind
    else:
        if args.space == "joint":
            # A joint path has no Cartesian speed: --speed/--accel are the joint scales, as for a joint move.
            pts = [[v * deg for v in p] for p in args.points]
            rates = dict(speed=0.0, accel=0.0, vel_scale=args.joint_speed or args.speed,
                         acc_scale=args.joint_accel or args.accel)
        else:
            pts = args.points
            rates = dict(speed=args.speed, accel=args.accel, vel_scale=args.joint_speed, acc_scale=args.joint_accel)
        msg = kc.make_goal_path(pts, space=args.space, method=args.method, times=args.times,
                                blend_time=args.blend_time, shape=args.shape, ends=args.ends, **rates, **common)
        kind = f"{args.space} {args.method} path"
    with _connect(args) as c:
        return _answer(c, c.send(msg), kind, args)


def cmd_servo(args, deg):
    from kinctl.client import make_servo_message, new_goal_id
    period = 1.0 / args.rate
    stale = args.stale_ms / 1e3 if args.stale_ms else min(max(3 * period, STALE_MIN_S), STALE_MAX_S)
    twist = None if args.twist is None else args.twist[:3] + [v * deg for v in args.twist[3:]]
    gid = args.id or new_goal_id()
    msg = make_servo_message(gid, pose=args.pose, twist=twist, replace=args.replace, timeout_s=stale)
    with _connect(args) as c:
        sent, t0 = 0, time.monotonic()
        try:
            while time.monotonic() - t0 < args.duration:
                c.publish(msg)
                sent += 1
                if c.wait_event(gid, ("REJECTED",), 0) is not None:
                    break
                next_t = t0 + sent * period
                time.sleep(max(0.0, next_t - time.monotonic()))
        except KeyboardInterrupt:
            pass
        st = c.wait_answer(gid, args.connect_timeout)
        if st is None:
            _err(f"servo {gid}: no answer from kinctld within {args.connect_timeout:g} s")
            return 1
        if c.event(st) == "REJECTED":
            _err(f"servo {gid} REJECTED: {st.reason}")
            return 1
        _say(f"servo {gid}: {sent} messages in {time.monotonic() - t0:.2f} s "
             f"(stale after {stale * 1e3:.0f} ms without one)")
        if not args.wait:
            return 0
        st = c.wait_end(gid, args.timeout)
        if st is None:
            _err(f"servo {gid}: timed out after {args.timeout:g} s")
            return 1
        ev = c.event(st)
        # The stream's normal end: it went quiet and the daemon brought the arm to rest.
        if ev == "COMPLETED" or (ev == "ABORTED" and st.reason.startswith("servo_timeout")):
            c.wait_setpoint(lambda sp: sp.goal_id != gid and all(v == 0.0 for v in sp.qd[:sp.n]), args.timeout)
            _say(f"servo {gid}: stream ended, arm at rest ({ev.lower()}: {st.reason or 'done'})")
            return 0
        _err(f"servo {gid} {ev}: {st.reason}")
        return 1


# Command -> (state reached without --wait, state and rest with --wait).
def _command_done(name, sp):
    s = _state(sp)
    if name == "stop":
        return s in ("STOPPING", "IDLE")
    if name == "estop":
        return s == "ESTOP"
    if name == "pause":
        return s in ("PAUSED", "IDLE")
    if name == "resume":
        return s != "PAUSED"
    return s not in ("ESTOP", "FAULT")


def cmd_command(args):
    name = args.command
    with _connect(args) as c:
        c.command(name)

        def done(sp):
            if not _command_done(name, sp):
                return False
            if args.wait and name == "stop" and _state(sp) != "IDLE":
                return False
            return not args.wait or all(v == 0.0 for v in sp.qd[:sp.n])
        sp = c.wait_setpoint(done, args.timeout if args.wait else args.connect_timeout)
        if sp is None:
            sp = c.setpoint
            msg = f"{name}: state {_state(sp)} after " + \
                  (f"{args.timeout:g} s" if args.wait else f"{args.connect_timeout:g} s")
            if args.wait:
                _err(msg + ": timed out")
                return 1
            _say(msg)
            return 0
        _say(f"{name}: state {_state(sp)}" + (", at rest" if args.wait else ""))
        return 0


def status_dict(st, sp):
    from kinctl.msgs import event_name, state_name
    d = {"state": state_name(st.state), "cycle": st.cycle, "active_goal_id": st.active_goal_id,
         "progress": st.progress, "queue_length": st.queue_length, "event": event_name(st.event),
         "event_goal_id": st.event_goal_id, "code": st.code, "reason": st.reason,
         "q": list(st.q_measured[:st.n]), "qd": list(st.qd_measured[:st.n]),
         "can": {0: "off", 1: "ok", 2: "lost"}.get(st.can_state, str(st.can_state))}
    if sp is not None:
        d["setpoint_cycle"] = sp.cycle
        d["position"] = list(sp.position)
        d["orientation"] = list(sp.orientation)
    return d


def cmd_status(args):
    with _connect(args) as c:
        st = c.wait_status(max(args.connect_timeout, 0.5))
        if st is None:
            _err(f"kinctld sends setpoints but no {args.prefix}STATUS arrived within {args.connect_timeout:g} s")
            return 1
        d = status_dict(st, c.setpoint)
    if args.json:
        print(json.dumps(d))
        return 0
    unit = "deg" if args.deg else "rad"
    _say(f"state     {d['state']}  (cycle {d['cycle']})")
    _say(f"goal      {d['active_goal_id'] or '-'}  progress {100 * d['progress']:.0f} %  "
         f"queue {d['queue_length']}")
    if d["event"] != "NONE":
        _say(f"event     {d['event']} goal {d['event_goal_id']}" + (f": {d['reason']}" if d["reason"] else ""))
    _say(f"q         {_fmt(d['q'], args.deg)} {unit}")
    _say(f"qd        {_fmt(d['qd'], args.deg)} {unit}/s")
    if d["can"] != "off":
        _say(f"can       {d['can']}")
    if "position" in d:
        _say(f"tool      {_fmt(d['position'])} m   quat {_fmt(d['orientation'])}")
    return 0


def cmd_log(args):
    from kinctl.logcsv import EVENT_HEADER, SetpointWriter, event_row
    import csv
    stop = threading.Event()
    old = signal.signal(signal.SIGTERM, lambda *a: stop.set())
    with open(args.csv, "w", newline="") as f:
        ev_f = open(args.events, "w", newline="") if args.events else None
        try:
            writer = SetpointWriter(f)
            ev_w = None
            if ev_f:
                ev_w = csv.writer(ev_f, lineterminator="\n")
                ev_w.writerow(EVENT_HEADER)

            def on_status(st):
                if st.event != 0:
                    ev_w.writerow(event_row(st))
            c = _connect(args, on_setpoint=writer.write, on_status=on_status if ev_w else None)
            with c:
                _say(f"logging {args.prefix}SETPOINT to {args.csv}"
                     + (f" for {args.duration:g} s" if args.duration else " until Ctrl-C"))
                try:
                    stop.wait(args.duration)
                except KeyboardInterrupt:
                    pass
        finally:
            signal.signal(signal.SIGTERM, old)
            if ev_f:
                ev_f.close()
    _say("log: " + writer.report())
    return 0


def cmd_plot(args):
    from kinctl.plot import plot_run
    out = args.output or os.path.splitext(args.csv)[0] + ".png"
    info = plot_run(args.csv, out, events=args.events, title=args.title, prefix=args.prefix, progress=True,
                    model=args.model, model_file=args.model_file, zones_file=args.zones_file, zones=args.zone,
                    volumes=not args.no_volumes)
    _say(f"plot: {out} ({info['rows']} setpoints, {len(info['goals'])} goals)")
    return 0


def main(argv=None):
    argv = _glue_negative_values(sys.argv[1:] if argv is None else list(argv))
    args = build_parser().parse_args(argv)
    from kinctl.client import DaemonNotFound
    try:
        if args.command == "goal":
            return cmd_goal(args)
        if args.command in ("stop", "estop", "pause", "resume", "reset"):
            return cmd_command(args)
        if args.command == "status":
            return cmd_status(args)
        if args.command == "log":
            return cmd_log(args)
        from kinctl import datacmds
        if args.command in datacmds.NAMES:
            return datacmds.run(args)
        if args.command == "view":
            from kinctl.view import cmd_view
            return cmd_view(args)
        if args.command == "drivesim":
            from kinctl import drivesim
            return drivesim.run(args)
        if args.command == "drive402":
            from kinctl import drive402
            return drive402.run(args)
        if args.command == "candecode":
            from kinctl import candecode
            return candecode.run(args)
        return cmd_plot(args)
    except DaemonNotFound as e:
        _err(str(e))
        return 1
    except (ValueError, UsageError) as e:
        _err("error:", e)
        return 2
    except OSError as e:
        _err("error:", e)
        return 1
    except KeyboardInterrupt:
        return 130
