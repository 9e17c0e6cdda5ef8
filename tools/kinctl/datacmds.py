# SPDX-License-Identifier: BSD-3-Clause
"""The data commands of the kinctl CLI: record, play, replay, spy, import-urdf.

register() adds them to the CLI. Bad input raises UsageError or ValueError
(exit 2).
"""
import os
import signal
import threading

from kinctl.argtypes import UsageError, add_command, positive, say


def register(sub, parents):
    rec = add_command(sub, "record", "record every kinctl channel to an LCM event log (lcm-logger format)",
                      "kinctl record run.lcmlog --duration 10\n"
                      "  kinctl --prefix ARM2_ record arm2.lcmlog          (until Ctrl-C)", parents)
    rec.add_argument("log", metavar="LOG", help="the event log to write")
    rec.add_argument("--duration", type=positive, default=None, metavar="S",
                     help="stop after S seconds (default: at Ctrl-C or SIGTERM)")
    rec.add_argument("--inputs-only", action="store_true",
                     help="only the goal and command channels (default: every <prefix>* channel)")
    rec.add_argument("--force", action="store_true", help="overwrite LOG if it exists")
    rec.set_defaults(run=cmd_record)

    pl = add_command(sub, "play", "publish a recorded LCM event log with its original timing",
                     "kinctl play run.lcmlog --speed 2\n"
                     "  kinctl play run.lcmlog --inputs-only      (its goals and commands, to a live daemon)",
                     parents)
    pl.add_argument("log", metavar="LOG", help="an event log (kinctl record, lcm-logger)")
    pl.add_argument("--speed", type=positive, default=1.0, metavar="F",
                    help="play F times faster than recorded (default 1)")
    pl.add_argument("--inputs-only", action="store_true",
                    help="only the goal and command channels under --prefix (drive a live daemon with them)")
    pl.add_argument("--channels", default=None, metavar="REGEX",
                    help="only channels matching REGEX (a full match; default: every channel)")
    pl.set_defaults(run=cmd_play)

    rp = add_command(sub, "replay", "run a recorded log's goals and commands through the controller offline "
                                    "and check that every setpoint reproduces bit for bit",
                     "kinctl replay run.lcmlog\n"
                     "  kinctl replay run.lcmlog --model panda --period-us 500", parents)
    rp.add_argument("log", metavar="LOG", help="an event log recorded from kinctld (kinctl record)")
    rp.add_argument("--config", metavar="FILE", default=None, help="the daemon's --config")
    rp.add_argument("--model", metavar="NAME", default=None, help="the daemon's --model")
    rp.add_argument("--period-us", metavar="US", default=None, help="the daemon's --period-us")
    rp.set_defaults(run=cmd_replay)

    sp = add_command(sub, "spy", "start lcm-spy with kinctl's message types, so every channel decodes field "
                                 "by field", "kinctl spy\n  kinctl --lcm-url 'udpm://239.255.76.67:7667?ttl=0' spy",
                     parents)
    sp.add_argument("--jar", metavar="JAR", default=None,
                    help="the message jar (default: build/lcmtypes/kinctl_lcmtypes.jar, $KINCTL_JAR)")
    sp.add_argument("--print", action="store_true", help="print the command instead of running it")
    sp.set_defaults(run=cmd_spy)

    iu = add_command(sub, "import-urdf", "write a robot description file (models/README.md) from a URDF",
                     "kinctl import-urdf panda.urdf -o panda.cfg --tip panda_link8\n"
                     "  kinctl-calc fk --model-file panda.cfg --q 0,0,0,-1.57,0,1.57,0.78\n"
                     "  kinctld --config panda.cfg --check", parents)
    iu.add_argument("urdf", metavar="FILE.urdf", help="the URDF")
    iu.add_argument("-o", "--output", metavar="FILE", default=None,
                    help="the description file to write (default: FILE with .cfg; '-' for stdout)")
    iu.add_argument("--base", metavar="LINK", default=None, help="base link (default: the URDF's root)")
    iu.add_argument("--tip", metavar="LINK", default=None,
                    help="tool link (default: the end of the chain when there is only one)")
    iu.add_argument("--name", default=None, help="robot name (default: the URDF's)")
    iu.add_argument("--vel", type=positive, default=None, metavar="V",
                    help="velocity limit for joints whose URDF gives none (rad/s or m/s)")
    iu.add_argument("--acc", type=positive, default=None, metavar="A",
                    help="acceleration limit for every joint (URDF has none; default: 5 x each joint's velocity "
                         "limit, in 1/s)")
    iu.add_argument("--force", action="store_true", help="overwrite the output if it exists")
    iu.set_defaults(run=cmd_import_urdf)


def cmd_record(args):
    from kinctl.eventlog import channel_regex, record_until
    if os.path.exists(args.log) and not args.force:
        raise UsageError(f"{args.log} exists (give --force to overwrite)")
    where = os.path.dirname(os.path.abspath(args.log))
    if not os.path.isdir(where):
        raise UsageError(f"cannot write {args.log}: no directory {where}")
    stop = threading.Event()
    old = signal.signal(signal.SIGTERM, lambda *a: stop.set())
    regex = channel_regex(args.prefix, args.inputs_only)

    def ready(rec):
        say(f"recording {regex} to {args.log}" + (f" for {args.duration:g} s" if args.duration else
                                                    " until Ctrl-C"))
    try:
        rec = record_until(args.log, args.lcm_url, regex, args.prefix + "SETPOINT", args.duration, stop,
                           overwrite=args.force, ready=ready)
    except KeyboardInterrupt:
        rec = None
    finally:
        signal.signal(signal.SIGTERM, old)
    if rec is not None:
        say("record: " + rec.report())
    return 0


def cmd_play(args):
    from kinctl.eventlog import channel_regex, play
    import re
    if args.inputs_only and args.channels:
        raise ValueError("give --inputs-only or --channels, not both")
    regex = channel_regex(args.prefix, True) if args.inputs_only else args.channels
    if regex:
        try:
            re.compile(regex)
        except re.error as e:
            raise ValueError(f"--channels '{regex}': {e}") from None
    stop = threading.Event()
    old = signal.signal(signal.SIGTERM, lambda *a: stop.set())
    try:
        sent, took = play(args.log, args.lcm_url, args.speed, regex, stop=stop)
    finally:
        signal.signal(signal.SIGTERM, old)
    say(f"play: {sent} events in {took:.2f} s")
    return 0


def cmd_replay(args):
    from kinctl import replay
    from kinctl.eventlog import check_log
    check_log(args.log)
    daemon_args = ["--prefix", args.prefix]
    for opt, v in (("--config", args.config), ("--model", args.model), ("--period-us", args.period_us)):
        if v is not None:
            daemon_args += [opt, v]
    rc, _ = replay.run(args.log, daemon_args)
    return rc


def cmd_spy(args):
    from kinctl import spy
    argv, env = spy.command(args.lcm_url, args.jar)
    if args.print:
        say(f"CLASSPATH={env['CLASSPATH']} " + " ".join(argv))
        return 0
    import subprocess
    return subprocess.call(argv, env=env)


def cmd_import_urdf(args):
    from kinctl import urdf
    out = args.output or os.path.splitext(args.urdf)[0] + ".cfg"
    if out != "-" and os.path.exists(out) and not args.force:
        raise UsageError(f"{out} exists (give --force to overwrite)")
    text, info = urdf.convert(args.urdf, base=args.base, tip=args.tip, name=args.name, vel=args.vel, acc=args.acc)
    if out == "-":
        print(text, end="")
    else:
        with open(out, "w") as f:
            f.write(text)
        say(f"import-urdf: {out}: {info}")
    return 0

