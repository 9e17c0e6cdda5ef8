#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Builds and runs interp_bench: planning and per-tick cost of kinctl's joint
# move, lines, arcs and multi-point paths, beside Orocos KDL's
# VelocityProfile_Trap and Ruckig on the same 6-joint moves (issue 4); one
# table in one run.
#
# bench_setup.sh installs and builds as for fk_bench. Ruckig's PyPI wheel
# holds only its Python extension, so its C++ source comes from the sdist:
# pip download --no-binary :all: into build-bench/ruckig (once; never
# committed), compiled into the benchmark. If it cannot be downloaded or
# built, the rest runs and the output says why Ruckig is absent.
#
# Then interp_jerk_bench (issue 19): kinctl's jerk-limited profiles beside
# Ruckig on 6- and 7-joint moves, rest to rest and from moving states, with
# its targets checked; it needs Ruckig, and the script fails when a target
# is missed.
#
# Usage: tools/bench/run_interp_bench.sh [jerk]   (jerk: interp_jerk_bench
# alone; BUILD_DIR overrides build-bench)
set -euo pipefail
only=${1:-}
[[ -z $only || $only == jerk ]] || { echo "usage: $0 [jerk]" >&2; exit 2; }

root=$(cd "$(dirname "$0")/../.." && pwd)
. "$root/tools/bench/bench_setup.sh" # build, venv

# ---- Ruckig's C++ source (optional) ----
mkdir -p "$build/ruckig"
ruckig_src=$(find "$build/ruckig" -mindepth 1 -maxdepth 1 -type d -name 'ruckig-*' | sort | tail -1)
if [[ -z $ruckig_src ]]; then
    bench_log "pip download the ruckig sdist into $build/ruckig"
    if python3 -m pip download -q --no-binary :all: --no-deps ruckig -d "$build/ruckig" \
        >"$build/ruckig/download.log" 2>&1; then
        sdist=$(find "$build/ruckig" -maxdepth 1 -name 'ruckig-*.tar.gz' | sort | tail -1)
        if [[ -n $sdist ]] && tar -xzf "$sdist" -C "$build/ruckig" >>"$build/ruckig/download.log" 2>&1; then
            ruckig_src=${sdist%.tar.gz}
        else
            ruckig_note="the ruckig sdist did not unpack (see $build/ruckig/download.log)"
        fi
    else
        ruckig_note="pip download --no-binary :all: ruckig failed (see $build/ruckig/download.log)"
    fi
fi
[[ -z $ruckig_src || -f $ruckig_src/include/ruckig/ruckig.hpp ]] ||
    { ruckig_note="no include/ruckig/ruckig.hpp in $ruckig_src"; ruckig_src=""; }

bench_setup interp_bench
bench_machine_notes
if [[ -n $ruckig_src ]]; then
    echo "Ruckig $(basename "$ruckig_src" | sed 's/^ruckig-//') (sdist, community calculator, compiled with the flags above)"
else
    echo "Ruckig: left out: $ruckig_note"
fi
if [[ $only != jerk ]]; then
    "$build/tools/bench/interp_bench" | tee "$build/interp_bench.txt"
fi
if [[ -z $ruckig_src ]]; then
    echo "interp_jerk_bench: left out: it compares with Ruckig, which is absent"
    [[ $only != jerk ]] || exit 1
    exit 0
fi
bench_build interp_jerk_bench || { cat "$build/build.log" >&2; exit 1; }
"$build/tools/bench/interp_jerk_bench" | tee "$build/interp_jerk_bench.txt"
