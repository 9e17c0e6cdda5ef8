#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Builds and runs ik_bench: kinctl's kc_ik_solve against Orocos KDL (LMA,
# NR_JL), Pinocchio's CLIK loop and the Robotics Toolbox's ik_LM on the same
# 1000 targets per arm, plus the cost of kc_ik_step (issue 3); one table.
#
# bench_setup.sh installs and builds as for fk_bench; here also
# roboticstoolbox-python with pip into .venv. If the toolbox cannot be
# installed or imported, the rest runs and the table says why rtb is absent.
# The IK set files (targets and starts) are written to build-bench/ik_set.
#
# Usage: tools/bench/run_ik_bench.sh        (BUILD_DIR overrides build-bench)
set -euo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
. "$root/tools/bench/bench_setup.sh" # build, venv

bench_setup ik_bench

# ---- the Robotics Toolbox (optional) ----
rtb_note=""
if [[ ! -x $venv/bin/python ]]; then
    rtb_note="no venv at $venv"
elif ! "$venv/bin/python" -c 'import roboticstoolbox' >/dev/null 2>&1; then
    bench_log "pip install roboticstoolbox-python into $venv"
    "$venv/bin/pip" install -q roboticstoolbox-python >"$build/pip-rtb.log" 2>&1 ||
        rtb_note="pip install roboticstoolbox-python failed (see $build/pip-rtb.log)"
    [[ -n $rtb_note ]] || "$venv/bin/python" -c 'import roboticstoolbox' >>"$build/pip-rtb.log" 2>&1 ||
        rtb_note="roboticstoolbox installed but does not import (see $build/pip-rtb.log)"
fi
export KC_BENCH_RTB="" KC_BENCH_RTB_NOTE="$rtb_note"
[[ -n $rtb_note ]] || KC_BENCH_RTB="$venv/bin/python $root/tools/bench/ik_bench_rtb.py"

bench_machine_notes
[[ -n $rtb_note ]] ||
    echo "rtb $("$venv/bin/pip" show roboticstoolbox-python 2>/dev/null | sed -n 's/^Version: //p');" \
        "$("$venv/bin/python" --version)"
mkdir -p "$build/ik_set"
"$build/tools/bench/ik_bench" "$build/ik_set" | tee "$build/ik_bench.txt"
