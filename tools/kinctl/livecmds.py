# SPDX-License-Identifier: BSD-3-Clause
"""The `kinctl` commands that talk to a running kinctld besides goals: the
commands (stop, estop, pause, resume, reset), status and log.

register() adds them to the CLI.
"""
import json
import math
import signal
import threading

from kinctl.argtypes import add_command, err, positive, say
from kinctl.connection import connect, state_of


def register(sub, parents):
    for name, help_ in (("stop", "decelerate along the path to rest and clear the queue"),
                        ("estop", "stop as hard as the limits allow; latched until reset"),
                        ("pause", "decelerate to rest on the path and hold"),
                        ("resume", "carry on after pause"),
                        ("reset", "clear a fault or a latched e-stop")):
        example = f"kinctl {name}" + (" --wait" if name in ("stop", "estop", "pause") else "")
        c = add_command(sub, name, help_, example, parents)
        c.add_argument("--wait", action="store_true",
                       help="block until the command has taken effect and the arm is at rest")
        c.add_argument("--timeout", type=positive, default=30.0, metavar="S", help="with --wait (default 30 s)")
        c.set_defaults(run=cmd_command)

    st = add_command(sub, "status", "print one status of the daemon", "kinctl status --json", parents)
    st.add_argument("--json", action="store_true", help="as one JSON object")
    st.set_defaults(run=cmd_status)

    lg = add_command(sub, "log", "write every setpoint to a CSV file",
                     "kinctl log --csv run.csv --duration 10 --events events.csv", parents)
    lg.add_argument("--csv", required=True, metavar="FILE",
                    help="setpoints: utime,cycle,goal_id,state,q1..qn,qd1..qdn,qdd1..qddn,x,y,z,qw,qx,qy,qz")
    lg.add_argument("--duration", type=positive, default=None, metavar="S",
                    help="stop after S seconds (default: at Ctrl-C or SIGTERM)")
    lg.add_argument("--events", metavar="FILE", default=None,
                    help="also write status events: utime,cycle,goal_id,event,code,reason")
    lg.set_defaults(run=cmd_log)


def _fmt(values, deg=False, digits=4):
    """values in a row; deg: True (every value) or one flag per value, in
    degrees where set."""
    flags = deg if isinstance(deg, list) else [deg] * len(values)
    return " ".join(f"{math.degrees(v) if d else v:.{digits}f}" for v, d in zip(values, flags))


# Command -> (state reached without --wait, state and rest with --wait).
def _command_done(name, sp):
    s = state_of(sp)
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
    with connect(args) as c:
        c.command(name)

        def done(sp):
            if not _command_done(name, sp):
                return False
            if args.wait and name == "stop" and state_of(sp) != "IDLE":
                return False
            return not args.wait or all(v == 0.0 for v in sp.qd[:sp.n])
        sp = c.wait_setpoint(done, args.timeout if args.wait else args.connect_timeout)
        if sp is None:
            sp = c.setpoint
            msg = f"{name}: state {state_of(sp)} after " + \
                  (f"{args.timeout:g} s" if args.wait else f"{args.connect_timeout:g} s")
            if args.wait:
                err(msg + ": timed out")
                return 1
            say(msg)
            return 0
        say(f"{name}: state {state_of(sp)}" + (", at rest" if args.wait else ""))
        return 0


# status_t.drives (lcmtypes/status_t.lcm): the CiA 402 drives on CAN.
DRIVES = {0: "none", 1: "booting", 2: "enabling", 3: "enabled", 4: "disabled"}


def status_dict(st, sp):
    from kinctl.msgs import event_name, state_name
    d = {"state": state_name(st.state), "cycle": st.cycle, "active_goal_id": st.active_goal_id,
         "progress": st.progress, "queue_length": st.queue_length, "event": event_name(st.event),
         "event_goal_id": st.event_goal_id, "code": st.code, "reason": st.reason,
         "q": list(st.q_measured[:st.n]), "qd": list(st.qd_measured[:st.n]),
         "can": {0: "off", 1: "ok", 2: "lost"}.get(st.can_state, str(st.can_state)),
         "drives": DRIVES.get(st.drives, str(st.drives)),
         "prismatic": [bool(p) for p in st.prismatic[:st.n]]}
    if sp is not None:
        d["setpoint_cycle"] = sp.cycle
        d["position"] = list(sp.position)
        d["orientation"] = list(sp.orientation)
    return d


def cmd_status(args):
    with connect(args) as c:
        st = c.wait_status(max(args.connect_timeout, 0.5))
        if st is None:
            err(f"kinctld sends setpoints but no {args.prefix}STATUS arrived within {args.connect_timeout:g} s")
            return 1
        d = status_dict(st, c.setpoint)
    if args.json:
        print(json.dumps(d))
        return 0
    from kinctl.msgs import joint_degrees
    in_deg = joint_degrees(st, args.deg)
    prismatic = [str(j + 1) for j, p in enumerate(d["prismatic"]) if p]

    def unit(rate=""):
        u = ("deg" if args.deg else "rad") + rate
        return u + (f"; joint {','.join(prismatic)} in m{rate}" if prismatic else "")
    say(f"state     {d['state']}  (cycle {d['cycle']})")
    say(f"goal      {d['active_goal_id'] or '-'}  progress {100 * d['progress']:.0f} %  "
        f"queue {d['queue_length']}")
    if d["event"] != "NONE":
        say(f"event     {d['event']} goal {d['event_goal_id']}" + (f": {d['reason']}" if d["reason"] else ""))
    say(f"q         {_fmt(d['q'], in_deg)} {unit()}")
    say(f"qd        {_fmt(d['qd'], in_deg)} {unit('/s')}")
    if d["can"] != "off":
        say(f"can       {d['can']}, drives {d['drives']}")
    if "position" in d:
        say(f"tool      {_fmt(d['position'])} m   quat {_fmt(d['orientation'])}")
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
            c = connect(args, on_setpoint=writer.write, on_status=on_status if ev_w else None)
            with c:
                say(f"logging {args.prefix}SETPOINT to {args.csv}"
                    + (f" for {args.duration:g} s" if args.duration else " until Ctrl-C"))
                try:
                    stop.wait(args.duration)
                except KeyboardInterrupt:
                    pass
        finally:
            signal.signal(signal.SIGTERM, old)
            if ev_f:
                ev_f.close()
    say("log: " + writer.report())
    return 0
