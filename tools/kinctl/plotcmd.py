# SPDX-License-Identifier: BSD-3-Clause
"""`kinctl plot`: a run's setpoints drawn to a PNG or SVG file (kinctl.plot).

register() adds the subcommand to the CLI.
"""
import os

from kinctl.argtypes import add_command, say


def register(sub, parents):
    pl = add_command(sub, "plot", "plot a run's setpoints: q, qd, qdd of every joint against time (each goal's "
                                  "leading joint bold), the tool's speed along its path, the tool path in 3-D and "
                                  "on XY, XZ, YZ; one colour per goal_id",
                     "kinctl plot run.csv --events events.csv -o run.png --model puma560\n"
                     "  kinctl plot run.lcmlog -o run.svg          # an LCM event log (lcm-logger); SVG\n"
                     "  kinctl plot run.csv --model puma560 --zones-file kinctld.cfg --zone "
                     "box:0.6,0,0.3,0.05,0.4,0.3", parents)
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
    pl.set_defaults(run=cmd_plot)


def cmd_plot(args):
    from kinctl.plot import plot_run
    out = args.output or os.path.splitext(args.csv)[0] + ".png"
    info = plot_run(args.csv, out, events=args.events, title=args.title, prefix=args.prefix, progress=True,
                    model=args.model, model_file=args.model_file, zones_file=args.zones_file, zones=args.zone,
                    volumes=not args.no_volumes)
    say(f"plot: {out} ({info['rows']} setpoints, {len(info['goals'])} goals)")
    return 0
