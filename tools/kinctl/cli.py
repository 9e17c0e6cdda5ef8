# SPDX-License-Identifier: BSD-3-Clause
"""`kinctl`: send goals and commands to kinctld, read its status, log its setpoints.

The entry point: the top-level parser, built from the command modules (each
registers its own subcommands with register(subparsers, parents) and sets
`run` to its handler), and the dispatch with its exit status.

Exit status: 0 success; 1 the goal was rejected, preempted, aborted or
faulted, a wait timed out, or no daemon answered; 2 bad command line.
"""
import argparse
import sys

from kinctl import cancmds, connection, datacmds, goalcmds, livecmds, plotcmd, viewcmd
from kinctl.argtypes import Formatter, UsageError, err, glue_negative_values

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

# In the order `kinctl --help` lists their commands.
COMMAND_MODULES = (goalcmds, livecmds, plotcmd, viewcmd, datacmds, cancmds)


def build_parser():
    glob = argparse.ArgumentParser(add_help=False)
    connection.add_options(glob, suppress=True)
    parents = [glob]
    p = argparse.ArgumentParser(
        prog="kinctl", formatter_class=Formatter,
        description="Client of kinctld, kinctl's motion controller daemon: goals and commands out, "
                    "status and setpoints in, over LCM.",
        epilog=EXAMPLES + "\nexit status: 0 ok; 1 goal rejected/preempted/aborted, timeout or no daemon; "
                          "2 bad command line")
    connection.add_options(p, suppress=False)
    from kinctl import __version__
    p.add_argument("-V", "--version", action="version", version=f"kinctl {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module in COMMAND_MODULES:
        module.register(sub, parents)
    return p


def _no_messages(e):
    """The generated message classes are missing (kinctl.msgs says how to get
    them): the reason, not a traceback; anything else goes on up."""
    if "kinctl_msgs" not in str(e):
        raise e
    err("error:", e)
    return 1


def main(argv=None):
    argv = glue_negative_values(sys.argv[1:] if argv is None else list(argv))
    args = build_parser().parse_args(argv)
    try:
        from kinctl.client import DaemonNotFound
    except ImportError as e:
        return _no_messages(e)
    try:
        return args.run(args)
    except DaemonNotFound as e:
        err(str(e))
        return 1
    except (ValueError, UsageError) as e:
        err("error:", e)
        return 2
    except ImportError as e:
        return _no_messages(e)
    except OSError as e:
        err("error:", e)
        return 1
    except KeyboardInterrupt:
        return 130
