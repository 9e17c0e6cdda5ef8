# SPDX-License-Identifier: BSD-3-Clause
"""The CAN commands of `kinctl`: drivesim (simulated CiA 402 drives,
kinctl.drive402) and candecode (frames decoded with kinctl's DBC,
kinctl.candecode).

register() adds them to the CLI; each runs its module's run(args).
"""
from kinctl.argtypes import add_command, nonneg, positive
from kinctl.drive402 import CONTROL_USAGE


def register(sub, parents):
    ds = add_command(sub, "drivesim", "simulate CiA 402 drives in cyclic synchronous position on a CANopen stack "
                                      "(python canopen, an EDS; kinctl.drive402): boot-up into pre-operational, "
                                      "SDO server, NMT, heartbeat producer and consumer, EMCY, PDO mapping, SYNC "
                                      "(0x1019), RPDOs applied and TPDOs sent at SYNC, the CiA 402 power state "
                                      "machine; kinctld boots, configures and enables them. Control lines on stdin: "
                                      + CONTROL_USAGE,
                     "kinctl drivesim --interface vcan0 --nodes 1-6 --start 1=1000,2=-20000 --lag 0.02\n"
                     "  (then type: fault 3 0x5530, state 3, reboot 2, silent 4, talk 4, lag 1 0.5, quit)\n"
                     "  kinctl drivesim --configured --heartbeat-ms 100 --period-ms 1   "
                     "# ready without SDO (kinctld boot = false)", parents)
    ds.add_argument("--interface", default="vcan0", help="SocketCAN interface (default vcan0)")
    ds.add_argument("--nodes", default="1-6", help="drive node ids: 1-6 or 1,2,5 (default 1-6)")
    ds.add_argument("--eds", default=None, metavar="FILE",
                    help="the drives' EDS (default: kinctl's data/kinctl-drive.eds)")
    ds.add_argument("--start", default="", metavar="N=COUNTS,...",
                    help="actual positions at power-on (default 1000 N + 123 counts)")
    ds.add_argument("--lag", type=nonneg, default=0.0, metavar="S",
                    help="first-order lag of the actual position behind the target (s); 0: none (default)")
    ds.add_argument("--period-ms", type=positive, default=None, metavar="MS",
                    help="power-on interpolation period 0x60C2 (default: the EDS's, 1 ms; "
                         "kinctld's boot writes it)")
    ds.add_argument("--heartbeat-ms", type=nonneg, default=None, metavar="MS",
                    help="power-on heartbeat producer time 0x1017; 0: none (default: the EDS's, 0; kinctld's boot "
                         "writes drive_heartbeat_ms)")
    ds.add_argument("--window", type=nonneg, default=None, metavar="COUNTS",
                    help="power-on following-error window 0x6065: statusword bit 13 beyond it (default: the EDS's, "
                         "none)")
    ds.add_argument("--configured", action="store_true",
                    help="power on configured as kinctld's boot leaves a drive (RPDO1 controlword + target, TPDO1 "
                         "statusword + actual, both every SYNC; mode 8), for a master that does not configure "
                         "the drives (kinctld's boot = false; give --heartbeat-ms too)")
    ds.add_argument("--no-stdin", action="store_true",
                    help="ignore stdin, run until SIGINT or SIGTERM (a background job: &)")
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
    from kinctl import drive402
    return drive402.run(args)


def cmd_candecode(args):
    from kinctl import candecode
    return candecode.run(args)
