#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# cppcheck over kinctl's own C code (warning, performance and portability
# checks, each file with its flags from BUILD_DIR's compile_commands.json,
# the core in both precisions); fails on any finding. An exception is
# justified where it is: /* cppcheck-suppress <id> ; reason */.
#   tests/analysis/cppcheck.sh SOURCE_DIR BUILD_DIR [CPPCHECK]
set -euo pipefail
src=$(cd "$1" && pwd)
build=$(cd "$2" && pwd)
cppcheck=${3:-cppcheck}
command -v "$cppcheck" >/dev/null || { echo "$cppcheck not found (scripts/setup.sh installs cppcheck)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 "$src/tests/analysis/own_sources.py" "$src" "$build" "$work"

echo "cppcheck: $(wc -l <"$work/files") files, $("$cppcheck" --version)"
cd "$src"
# -q leaves only the findings; the whole-program (ctu) ones do not set the
# exit code, so any line printed is a failure.
status=0
"$cppcheck" --project="$work/compile_commands.json" --enable=warning,performance,portability --inline-suppr \
    --error-exitcode=1 -q --template='{file}:{line}: {severity} {id}: {message}' \
    --cppcheck-build-dir="$work" >"$work/out" 2>&1 || status=$?
if [ "$status" -ne 0 ] || [ -s "$work/out" ]; then
    cat "$work/out"
    echo "cppcheck: $(grep -c ': ' "$work/out") findings (exit $status)" >&2
    exit 1
fi
echo "cppcheck: no findings"
