#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The demo: kinctld on the built-in puma560 (simulated, --no-rt, a private LCM
# URL with ttl=0) driven by the kinctl CLI: a joint move, a line, an arc, a
# blended multi-point path, a goal preempted by a --replace goal mid-motion,
# a stop mid-motion. Every setpoint is logged; out/ gets demo.csv,
# demo-events.csv, demo.png (q, qd, qdd and the tool path) and kinctld.log; a
# summary is printed and the daemon is shut down with SIGTERM.
# Installs and builds what it needs first (scripts/setup.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build >/dev/null
exec .venv/bin/python -m kinctl.demo --out out --kinctld build/daemon/kinctld "$@"
