#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Builds and runs fk_bench: kinctl's FK and Jacobian against Orocos KDL and
# Pinocchio (issue 2), one table in one run.
#
# bench_setup.sh installs what is missing (g++, cmake, liborocos-kdl-dev
# with apt-get as root; the pin wheel into .venv), configures build-bench
# (Release, -O2, KINCTL_BUILD_BENCH=ON) and builds only the benchmark's
# targets. If Pinocchio cannot be had or built against, the benchmark still
# runs KDL and says why Pinocchio is missing.
#
# Usage: tools/bench/run_fk_bench.sh        (BUILD_DIR overrides build-bench)
set -euo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
. "$root/tools/bench/bench_setup.sh" # build, venv

bench_setup fk_bench
bench_machine_notes
"$build/tools/bench/fk_bench" | tee "$build/fk_bench.txt"
