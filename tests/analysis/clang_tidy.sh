#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# clang-tidy over kinctl's own C code with the repository's .clang-tidy
# (tests/.clang-tidy for the test harnesses); fails on any finding.
#   tests/analysis/clang_tidy.sh SOURCE_DIR BUILD_DIR [CLANG_TIDY]
# BUILD_DIR's compile_commands.json gives each file's flags (own_sources.py
# keeps our files). The core is checked in both precisions; the test
# harnesses, alike in both, once. One clang-tidy process a file (clang-tidy
# 14 checking several files in one process reports false uninitialised
# va_lists in all but the first), one at a time (tests/analysis/CMakeLists.txt
# says why).
set -euo pipefail
src=$(cd "$1" && pwd)
build=$(cd "$2" && pwd)
tidy=${3:-clang-tidy}
command -v "$tidy" >/dev/null || { echo "$tidy not found (scripts/setup.sh installs clang-tidy)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 "$src/tests/analysis/own_sources.py" "$src" "$build" "$work" --tests-once

echo "clang-tidy: $(wc -l <"$work/files") files, $("$tidy" --version | grep -o 'version [0-9.]*')"
cd "$src"
status=0
xargs -a "$work/files" -n 1 "$tidy" -p "$work" --quiet >"$work/out" 2>"$work/err" || status=$?
if [ "$status" -ne 0 ] || grep -qE '(warning|error):' "$work/out"; then
    cat "$work/out"
    # (stderr also carries clang-tidy's "N warnings generated" counts)
    grep -vE 'warnings? (and [0-9]+ errors? )?generated\.$|^Suppressed|^Use -header-filter|^$' "$work/err" >&2 || true
    echo "clang-tidy: $(grep -cE '(warning|error):' "$work/out") findings (exit $status)" >&2
    exit 1
fi
echo "clang-tidy: no findings"
