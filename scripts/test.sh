#!/usr/bin/env bash
# Runs every test suite: the gcc build, then a clang build with AddressSanitizer
# and UndefinedBehaviorSanitizer. Installs and builds what it needs first.
set -euo pipefail
cd "$(dirname "$0")/.."

say() { printf '\033[1m[test]\033[0m %s\n' "$*"; }

scripts/setup.sh build
say "gcc build: all suites"
ctest --test-dir build --output-on-failure -j2

say "clang build with ASan + UBSan: all suites"
CC=clang scripts/setup.sh build-asan -DKINCTL_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build-asan --output-on-failure -j2
say "all suites passed in both builds"
