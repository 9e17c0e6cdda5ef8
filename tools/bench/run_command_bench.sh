#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Command latency of kinctld idle and under load (issue 17's benchmark):
# tools/bench/command_bench.py against the build's kinctld, with the
# generated message classes and the kinctl package on PYTHONPATH. Real-time
# (SCHED_FIFO, mlockall) when run as root. Prints the table and exits 1 when
# a target is missed.
#
# Usage: tools/bench/run_command_bench.sh [--commands N] [--no-rt] ...
#        (BUILD_DIR: the build directory, default build)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="${BUILD_DIR:-$ROOT/build}"
PY="$ROOT/.venv/bin/python"
[ -x "$PY" ] || PY=python3
if [ ! -x "$BUILD/daemon/kinctld" ]; then
  echo "run_command_bench.sh: no $BUILD/daemon/kinctld (scripts/setup.sh build)" >&2
  exit 2
fi
export PYTHONPATH="$BUILD/lcmtypes/python:$ROOT/tools${PYTHONPATH:+:$PYTHONPATH}"
exec "$PY" "$ROOT/tools/bench/command_bench.py" --kinctld "$BUILD/daemon/kinctld" "$@"
