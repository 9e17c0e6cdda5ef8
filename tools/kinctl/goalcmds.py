# SPDX-License-Identifier: BSD-3-Clause
"""`kinctl goal`: joint moves, lines, arcs, multi-point paths and servo
streams sent to kinctld, each waited for as the options ask.

register() adds the subcommand to the CLI; the exit status is 0 when the
goal was accepted (with --wait: completed), 1 when it was rejected,
preempted or aborted, or a wait timed out.
"""
import math
import time

from kinctl.argtypes import add_command, err, fraction, goal_id, nonneg, numbers, points, positive, say, vector
from kinctl.connection import connect, state_of

STALE_MIN_S, STALE_MAX_S = 0.05, 0.1


def register(sub, parents):
    goal = add_command(sub, "goal", "send a goal: joint, line, arc, path or servo",
                       "kinctl goal joint --q 0,0.7854,-3.1416,0,0.7854,0 --wait", parents)
    gsub = goal.add_subparsers(dest="kind", metavar="KIND", required=True)

    j = add_command(gsub, "joint", "joint move: every joint to --q, synchronised to the slowest",
                    "kinctl goal joint --q 0,0.7854,-3.1416,0,0.7854,0 --speed 0.5 --wait\n"
                    "  kinctl --deg goal joint --q 0,45,-180,0,45,0", parents)
    j.add_argument("--q", type=numbers, required=True, metavar="A,B,...",
                   help="target joint values (rad, or deg with --deg; m for prismatic joints)")
    j.add_argument("--profile", choices=("jerk", "trapezoid"), default=None,
                   help="motion law: jerk-limited or seed 001's trapezoid (default: the controller's profile)")
    _goal_options(j, cartesian=False)

    ln = add_command(gsub, "line", "Cartesian straight line of the tool to a pose",
                     "kinctl goal line --to 0.6,0,0.55,0.7071,0,0.7071,0 --speed 0.2 --wait", parents)
    ln.add_argument("--to", type=vector(7, "x,y,z,qw,qx,qy,qz"), required=True, metavar="X,Y,Z,QW,QX,QY,QZ",
                    help="end pose in the base frame: position (m), unit quaternion w,x,y,z")
    ln.add_argument("--slerp", action="store_true", help="orientation by quaternion slerp "
                                                          "(default: the two-rotation method)")
    _angular_options(ln)
    _goal_options(ln, cartesian=True)

    arc = add_command(gsub, "arc", "circular arc of the tool through --via to a pose",
                      "kinctl goal arc --via 0.6,0.1,0.65 --to 0.6,0,0.75,0.7071,0,0.7071,0 --wait", parents)
    arc.add_argument("--via", type=vector(3, "x,y,z"), required=True, metavar="X,Y,Z",
                     help="a point the arc passes through, base frame (m)")
    arc.add_argument("--to", type=vector(7, "x,y,z,qw,qx,qy,qz"), required=True, metavar="X,Y,Z,QW,QX,QY,QZ",
                     help="end pose in the base frame: position (m), unit quaternion w,x,y,z")
    _angular_options(arc)
    _goal_options(arc, cartesian=True)

    path = add_command(gsub, "path", "multi-point path in joint or Cartesian space",
                       "kinctl goal path --space joint --method blend --blend-time 0.3 \\\n"
                       "      --points '0.2,0.9,-3,0.1,0.7,0.1;0.4,0.7,-2.9,0,0.9,0.2;0.1,0.6,-3.1,-0.1,0.8,0' "
                       "--wait", parents)
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

    servo = add_command(gsub, "servo", "stream servo messages: track a pose or follow a twist, then let go",
                        "kinctl goal servo --twist 0,0.05,0,0,0,0 --rate 100 --duration 2 --replace --wait",
                        parents)
    what = servo.add_mutually_exclusive_group(required=True)
    what.add_argument("--pose", type=vector(7, "x,y,z,qw,qx,qy,qz"), metavar="X,Y,Z,QW,QX,QY,QZ",
                      help="target pose to track, base frame: approached jerk-limited within the daemon's "
                           "Cartesian limits (with the trapezoid profile followed at once); the arm stops "
                           "where it is when the stream ends, so stream long enough (--duration) to arrive")
    what.add_argument("--twist", type=vector(6, "vx,vy,vz,wx,wy,wz"), metavar="VX,VY,VZ,WX,WY,WZ",
                      help="tool twist to follow, base frame: m/s and rad/s (deg/s with --deg), capped at "
                           "the daemon's Cartesian speed and omega and reached within its Cartesian "
                           "acceleration and jerk limits")
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

    goal.set_defaults(run=cmd_goal)


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
        g.add_argument("--jerk", type=nonneg, default=0.0, metavar="M_S3",
                       help="tool jerk (m/s^3); 0 or absent: the controller's default"
                            + (" (Cartesian paths only)" if cartesian == "path" else ""))
        g.add_argument("--angular-jerk", type=nonneg, default=0.0, metavar="J",
                       help="tool angular jerk limit (rad/s^3, deg/s^3 with --deg); 0: default"
                            + (" (Cartesian paths only)" if cartesian == "path" else ""))
        g.add_argument("--joint-speed", type=fraction, default=0.0, metavar="SCALE",
                       help="fraction of the joint velocity limits the motion may use, (0, 1]")
        g.add_argument("--joint-accel", type=fraction, default=0.0, metavar="SCALE",
                       help="fraction of the joint acceleration limits, (0, 1]")
    else:
        g.add_argument("--speed", type=fraction, default=0.0, metavar="SCALE",
                       help="fraction of the joint velocity limits, (0, 1] (default 1)")
        g.add_argument("--accel", type=fraction, default=0.0, metavar="SCALE",
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


def _answer(c, gid, kind, args):
    """Waits for the goal's answer (and with --wait, its end). Returns the exit code."""
    from kinctl.msgs import reason_text
    st = c.wait_answer(gid, args.connect_timeout)
    if st is None:
        err(f"goal {gid} ({kind}): no answer from kinctld within {args.connect_timeout:g} s "
            f"(is the daemon overloaded, or another client using the same --prefix?)")
        return 1
    ev = c.event(st)
    if ev == "REJECTED":
        err(f"goal {gid} ({kind}) REJECTED: {reason_text(st, args.deg)}")
        return 1
    if not args.wait:
        note = ""
        if ev == "ACCEPTED":  # a replacing goal that waits for a stop says so (stop_first)
            note = f" ({st.reason})" if st.reason else " (replacing)" if args.replace else ""
        say(f"goal {gid} ({kind}) {ev}{note}")
        return 0 if ev in ("ACCEPTED", "COMPLETED") else 1
    say(f"goal {gid} ({kind}) ACCEPTED" + (f" ({st.reason})" if st.reason else "") + ", waiting")
    t0 = time.monotonic()
    st = c.wait_end(gid, args.timeout)
    if st is None:
        sp = c.setpoint
        err(f"goal {gid}: timed out after {args.timeout:g} s (state {state_of(sp)}, active goal {sp.goal_id})")
        return 1
    ev = c.event(st)
    if ev == "COMPLETED":
        say(f"goal {gid} ({kind}) COMPLETED after {time.monotonic() - t0:.2f} s")
        return 0
    err(f"goal {gid} ({kind}) {ev}" + (f": {reason_text(st, args.deg)}" if st.reason else ""))
    return 1



def cmd_goal(args):
    from kinctl import client as kc
    deg = math.radians(1.0) if args.deg else 1.0
    if args.kind == "servo":
        return cmd_servo(args, deg)
    # Build (and check) the message before looking for the daemon: bad input is exit 2.
    common = dict(goal_id=args.id, replace=args.replace)
    joint_msg = None
    if args.kind == "joint":
        def joint_msg(to_si):
            return kc.make_goal_joint(to_si(args.q), vel_scale=args.speed, acc_scale=args.accel,
                                      profile=args.profile, **common)
        kind = "joint"
    elif args.kind in ("line", "arc"):
        cart = dict(speed=args.speed, accel=args.accel, angular_speed=args.angular_speed * deg,
                    angular_accel=args.angular_accel * deg, jerk=args.jerk, angular_jerk=args.angular_jerk * deg,
                    vel_scale=args.joint_speed, acc_scale=args.joint_accel)
        if args.kind == "line":
            msg = kc.make_goal_line(args.to, slerp=args.slerp, **cart, **common)
        else:
            msg = kc.make_goal_arc(args.via, args.to, **cart, **common)
        kind = args.kind
    else:
        if args.space == "joint":
            # A joint path has no Cartesian speed: --speed/--accel are the joint scales, as for a joint move.
            rates = dict(speed=0.0, accel=0.0, vel_scale=args.joint_speed or args.speed,
                         acc_scale=args.joint_accel or args.accel)
        else:
            rates = dict(speed=args.speed, accel=args.accel, jerk=args.jerk, angular_jerk=args.angular_jerk * deg,
                         vel_scale=args.joint_speed, acc_scale=args.joint_accel)

        def path_msg(to_si):
            return kc.make_goal_path([to_si(p) for p in args.points], space=args.space, method=args.method,
                                     times=args.times, blend_time=args.blend_time, shape=args.shape,
                                     ends=args.ends, **rates, **common)
        if args.space == "joint":
            joint_msg = path_msg
        else:
            msg = path_msg(list)
        kind = f"{args.space} {args.method} path"
    if joint_msg is not None:
        # Checked with every joint revolute; sent once the daemon says which are.
        msg = joint_msg(lambda values: [v * deg for v in values])
    with connect(args) as c:
        if joint_msg is not None and args.deg:
            to_si = _joint_units(c, args)
            if to_si is None:
                return 1
            msg = joint_msg(to_si)
        return _answer(c, c.send(msg), kind, args)


def _joint_units(c, args):
    """With --deg: the conversion of joint values to SI for the daemon's arm
    (degrees for its revolute joints, m for its prismatic ones), from its
    status; None, said on stderr, when no status comes."""
    from kinctl.msgs import joint_degrees
    st = c.status or c.wait_status(max(args.connect_timeout, 0.5))
    if st is None:
        err(f"--deg: no {args.prefix}STATUS arrived within {args.connect_timeout:g} s to tell the arm's "
            "revolute joints from its prismatic ones")
        return None
    in_deg = joint_degrees(st, True)
    return lambda values: [math.radians(v) if j >= len(in_deg) or in_deg[j] else v for j, v in enumerate(values)]


def cmd_servo(args, deg):
    from kinctl.client import make_servo_message, new_goal_id
    from kinctl.msgs import reason_text
    period = 1.0 / args.rate
    stale = args.stale_ms / 1e3 if args.stale_ms else min(max(3 * period, STALE_MIN_S), STALE_MAX_S)
    twist = None if args.twist is None else args.twist[:3] + [v * deg for v in args.twist[3:]]
    gid = args.id or new_goal_id()
    msg = make_servo_message(gid, pose=args.pose, twist=twist, replace=args.replace, timeout_s=stale)
    with connect(args) as c:
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
            err(f"servo {gid}: no answer from kinctld within {args.connect_timeout:g} s")
            return 1
        if c.event(st) == "REJECTED":
            err(f"servo {gid} REJECTED: {reason_text(st, args.deg)}")
            return 1
        say(f"servo {gid}: {sent} messages in {time.monotonic() - t0:.2f} s "
            f"(stale after {stale * 1e3:.0f} ms without one)")
        if not args.wait:
            return 0
        st = c.wait_end(gid, args.timeout)
        if st is None:
            err(f"servo {gid}: timed out after {args.timeout:g} s")
            return 1
        ev = c.event(st)
        # The stream's normal end: it went quiet and the daemon brought the arm to rest.
        if ev == "COMPLETED" or (ev == "ABORTED" and st.reason.startswith("servo_timeout")):
            c.wait_setpoint(lambda sp: sp.goal_id != gid and all(v == 0.0 for v in sp.qd[:sp.n]), args.timeout)
            say(f"servo {gid}: stream ended, arm at rest ({ev.lower()}: {st.reason or 'done'})")
            return 0
        err(f"servo {gid} {ev}: {st.reason}")
        return 1

