#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# kinctld's bus cycle (issue 18's benchmark): SYNC period jitter measured
# from the kernel's receive timestamps on vcan (p50, p99, max of the
# SYNC-to-SYNC interval minus the bus cycle) beside the cycle thread's
# wake-up latency from kinctld's stats_t in the same run, with kinctld
# booting, configuring and enabling simulated CiA 402 drives (kinctl
# drivesim) and moving them. See tools/bench/can_bench.py for how each is
# measured.
#
# Where this host has vcan (or can make vcan0: root, the vcan module) it runs
# here, kinctld with --rt, cyclictest (rt-tests) at the same period first for
# the ratio. Where the kernel has no AF_CAN it runs inside User Mode Linux
# (tests/vcan/uml_run.sh): there the boot and the frame counts are real, but
# every figure of time is UML's (one virtual CPU, every system call trapped
# by ptrace), printed with that warning, not a real machine's.
#
# Uses the build in BUILD_DIR (default build; scripts/setup.sh makes it).
# Usage: tools/bench/run_can_bench.sh [--duration S] [--period-us N] [can_bench.py options]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build}
duration=10
period=1000
extra=()
while (($#)); do
    case $1 in
    --duration) duration=$2; shift 2 ;;
    --period-us) period=$2; shift 2 ;;
    -h | --help) sed -n '3,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) extra+=("$1"); shift ;;
    esac
done
[ -x "$build/daemon/kinctld" ] || "$root/scripts/setup.sh" "$(basename "$build")"
py=$root/.venv/bin/python
export PYTHONPATH="$build/lcmtypes/python:$root/tools"
bench=("$py" "$root/tools/bench/can_bench.py" --kinctld "$build/daemon/kinctld" --duration "$duration"
       --period-us "$period" "${extra[@]}")
if "$py" -c 'import socket; socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)' 2>/dev/null &&
    { ip link show vcan0 >/dev/null 2>&1 || { modprobe vcan && ip link add vcan0 type vcan; } 2>/dev/null; }; then
    ip link set up vcan0
    exec "${bench[@]}" --rt --cyclictest
fi
note="MEASURED INSIDE USER MODE LINUX (this kernel has no AF_CAN): the boot, the SYNC and frame counts are real; the
SYNC jitter and the wake-up latency are UML's (ptrace on every system call, one virtual CPU), NOT a real machine's."
PYTHON=$py "$root/tests/vcan/uml_run.sh" --exec "${bench[@]}" --note "$note"
