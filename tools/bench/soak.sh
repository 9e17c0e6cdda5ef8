#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Soak: kinctld (built in build/) for a long time under a random goal stream
# with the other CPU loaded by stress-ng, then the books (tools/bench/soak.py).
#   tools/bench/soak.sh [--duration S] [--seed N] [--no-rt] [--json FILE]
# Default 600 s, SCHED_FIFO on the last CPU when run as root; stress-ng runs
# on the other CPUs for the whole run. Needs scripts/setup.sh first.
set -euo pipefail
cd "$(dirname "$0")/../.."
args=() rt=1
while (($#)); do
    case "$1" in
    --no-rt) rt=0; shift ;;
    -h|--help) sed -n '3,7p' "$0" | sed 's/^# \{0,1\}//'; exec .venv/bin/python tools/bench/soak.py --help ;;
    *) args+=("$1"); shift ;;
    esac
done
[ -x build/daemon/kinctld ] || { echo "soak.sh: build/daemon/kinctld is missing: run scripts/setup.sh" >&2; exit 2; }
command -v stress-ng >/dev/null || { echo "soak.sh: stress-ng is missing (scripts/setup.sh installs it)" >&2; exit 2; }
((rt && $(id -u) == 0)) && args+=(--rt)
cpus=$(nproc)
others=$(seq -s, 0 $((cpus > 1 ? cpus - 2 : 0)))
taskset -c "$others" stress-ng --cpu "$((cpus > 1 ? cpus - 1 : 1))" --timeout 0 --quiet &
load=$!
trap 'kill $load 2>/dev/null; wait $load 2>/dev/null' EXIT
PYTHONPATH="$PWD/build/lcmtypes/python:$PWD/tools" .venv/bin/python tools/bench/soak.py --kinctld build/daemon/kinctld "${args[@]}"
