# SPDX-License-Identifier: BSD-3-Clause
"""The CAN commands of `kinctl`: drivesim (simulated CiA 402 drives,
kinctl.drivesim) and candecode (frames decoded with kinctl's DBC,
kinctl.candecode).

register() adds them to the CLI; each runs its module's run(args).
"""
from kinctl.argtypes import add_command, nonneg, positive


def add_drive_bus(p):
    """The options every drive simulator (drivesim, drive402) takes: the
    interface and the drives' node ids."""
    p.add_argument("--interface", default="vcan0", help="SocketCAN interface (default vcan0)")
    p.add_argument("--nodes", default="1-6", help="drive node ids: 1-6 or 1,2,5 (default 1-6)")


def register(sub, parents):
    ds = add_command(sub, "drivesim", "simulate CiA 402 drives (cyclic synchronous position) on a CAN interface: "
                                      "they follow kinctld's RPDOs at each SYNC and answer with TPDOs and "
                                      "heartbeats; control lines on stdin: fault/clear/silent/talk N, lag N S, "
                                      "vmax N C, quit",
                     "kinctl drivesim --interface vcan0 --nodes 1-6 --period-ms 1 --lag 0.02\n"
                     "  (then type: fault 3, clear 3, silent 2, talk 2, lag 1 0.5, quit)", parents)
    add_drive_bus(ds)
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
    ds.set_defaults(run=cmd_drivesim)

    cd = add_command(sub, "candecode", "print CAN frames decoded with kinctl's DBC (kinctl.dbc): a candump "
                                       "log (candump -L, or its default format) or a live interface",
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
    cd.set_defaults(run=cmd_candecode)


def cmd_drivesim(args):
    from kinctl import drivesim
    return drivesim.run(args)


def cmd_candecode(args):
    from kinctl import candecode
    return candecode.run(args)
