#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# kinctld's CAN output (issue 6's benchmark): frames per second sustained on
# vcan at 1 kHz for 6 and 12 joints, the CAN path's compute per bus cycle
# (p50, p99, max) and cycle deadline to frame on the bus (p50, p99, max).
# See tools/bench/can_bench.py for how each is measured.
#
# Where this host has vcan (or can make vcan0: root, the vcan module) it runs
# here, kinctld with --rt. Where the kernel has no AF_CAN it runs inside User
# Mode Linux (tests/vcan/uml_run.sh): there the frame counts and the dropped
# frames are real, but UML's timing is not (one virtual CPU, every system
# call trapped by ptrace), so the path cost and the deadline-to-frame times
# are printed with that warning and are not figures of a real machine.
#
# Uses the build in BUILD_DIR (default build; scripts/setup.sh makes it).
# Usage: tools/bench/run_can_bench.sh [--duration S] [--period-us N]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build}
duration=10
period=1000
while (($#)); do
    case $1 in
    --duration) duration=$2; shift 2 ;;
    --period-us) period=$2; shift 2 ;;
    -h | --help) sed -n '3,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "run_can_bench: unknown argument $1 (--help)" >&2; exit 2 ;;
    esac
done
[ -x "$build/daemon/kinctld" ] || "$root/scripts/setup.sh" "$(basename "$build")"
py=$root/.venv/bin/python
export PYTHONPATH="$build/lcmtypes/python:$root/tools"
bench=("$py" "$root/tools/bench/can_bench.py" --kinctld "$build/daemon/kinctld" --duration "$duration"
       --period-us "$period")
if "$py" -c 'import socket; socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)' 2>/dev/null &&
    { ip link show vcan0 >/dev/null 2>&1 || { modprobe vcan && ip link add vcan0 type vcan; } 2>/dev/null; }; then
    ip link set up vcan0
    exec "${bench[@]}" --rt
fi
note="MEASURED INSIDE USER MODE LINUX (this kernel has no AF_CAN): frames/s and drops are real; the path cost and
deadline->frame times are UML's (ptrace on every system call, one virtual CPU), NOT a real machine's figures."
PYTHON=$py "$root/tests/vcan/uml_run.sh" --exec "${bench[@]}" --note "$note"
