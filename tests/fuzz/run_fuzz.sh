#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Builds the libFuzzer harnesses (clang, ASan + UBSan, coverage) in
# build-fuzz and runs each one, then prints executions, coverage and
# findings per harness.
#   tests/fuzz/run_fuzz.sh [--runs N] [--max-seconds S] [--fast] [--merge] [HARNESS...]
# --runs N         executions per harness (default 10000000)
# --max-seconds S  stop a harness after S seconds even if N is not reached
#                  (default 0: no limit)
# --fast           fuzz a build without sanitizers (build-fuzz-fast: the
#                  controller and calculator harnesses run about six times
#                  faster; their invariant checks still abort), then run
#                  every input of the working corpus once under ASan + UBSan
# --merge          minimise each harness's working corpus back into
#                  tests/fuzz/corpus/<harness> (new coverage only)
# Harnesses: msg config desc ctrl calc (default: all). The working corpus of
# a run (seeds plus what the fuzzer finds) is build-fuzz/corpus/<harness>; a
# crashing input is saved as build-fuzz/findings/<harness>/crash-*: fix the
# cause, then copy the input into tests/fuzz/corpus/<harness> so that ctest's
# fuzz.<harness> replays it on every run.
set -euo pipefail
cd "$(dirname "$0")/../.."

runs=10000000 max_seconds=0 merge=0 fast=0 harnesses=()
while (($#)); do
    case "$1" in
    --runs) runs=$2; shift 2 ;;
    --max-seconds) max_seconds=$2; shift 2 ;;
    --merge) merge=1; shift ;;
    --fast) fast=1; shift ;;
    -h|--help) sed -n '3,/^set /{/^#/p}' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    msg|config|desc|ctrl|calc) harnesses+=("$1"); shift ;;
    *) echo "run_fuzz.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
    esac
done
((${#harnesses[@]})) || harnesses=(msg config desc ctrl calc)

say() { printf '\033[1m[fuzz]\033[0m %s\n' "$*"; }

# libFuzzer's runtime is in Debian's libclang-rt-<version>-dev.
if ! clang -fsanitize=fuzzer -x c - -o /dev/null <<<'int LLVMFuzzerTestOneInput(const char *d, long n) { return 0; }' 2>/dev/null; then
    ver=$(clang --version | sed -n 's/.*clang version \([0-9]*\).*/\1/p')
    say "installing libclang-rt-$ver-dev (libFuzzer)"
    sudo_cmd=(); [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
    DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq "libclang-rt-$ver-dev" >/dev/null
fi

CC=clang scripts/setup.sh build-fuzz -DKINCTL_FUZZ=ON -DKINCTL_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build-fuzz --target $(printf 'fuzz_%s ' "${harnesses[@]}")
fuzz_build=build-fuzz
if ((fast)); then
    # Coverage instrumentation without a sanitizer runtime leaves nothing to
    # define its callbacks in kinctld and the tools: build the harnesses only.
    KINCTL_BUILD_TARGETS="$(printf 'fuzz_%s ' "${harnesses[@]}")" CC=clang \
        scripts/setup.sh build-fuzz-fast -DKINCTL_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
    fuzz_build=build-fuzz-fast
fi

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp
summary=()
status=0
for h in "${harnesses[@]}"; do
    work=build-fuzz/corpus/$h findings=build-fuzz/findings/$h log=build-fuzz/fuzz-$h.log
    mkdir -p "$work" "$findings"
    # The readers and the calculator print a complaint for every bad input:
    # their stderr is closed (libFuzzer keeps its own, and the invariant
    # checks of those harnesses abort with a core-dumping signal anyway).
    case "$h" in config|calc) mask=2 ;; *) mask=0 ;; esac
    say "$h: $runs runs (log: $log)"
    start=$(date +%s)
    set +e
    "$fuzz_build/tests/fuzz/fuzz_$h" -runs="$runs" -max_total_time="$max_seconds" -timeout=20 -rss_limit_mb=2048 \
        -print_final_stats=1 -close_fd_mask="$mask" -artifact_prefix="$findings/" "$work" "tests/fuzz/corpus/$h" >"$log" 2>&1 &
    pid=$!
    while kill -0 "$pid" 2>/dev/null; do
        sleep 10
        line=$(grep -a -E '^#[0-9]+' "$log" | tail -n 1 || true)
        [ -n "$line" ] && printf '\r  %s: %s ' "$h" "$(cut -c1-100 <<<"$line")"
    done
    wait "$pid"
    rc=$?
    set -e
    printf '\n'
    secs=$(( $(date +%s) - start ))
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    cov=$(grep -a -o 'cov: [0-9]*' "$log" | tail -n 1 | cut -d' ' -f2)
    ft=$(grep -a -o 'ft: [0-9]*' "$log" | tail -n 1 | cut -d' ' -f2)
    crashes=$(find "$findings" -type f | wc -l)
    rate=$(( ${execs:-0} / (secs > 0 ? secs : 1) ))
    summary+=("$(printf '%-7s %12s %8s %10s %7s %7s %8s %s' "$h" "${execs:-?}" "$secs" "$rate" "${cov:-?}" "${ft:-?}" \
        "$(find "$work" -type f | wc -l)" "$crashes")")
    if [ "$rc" -ne 0 ] || [ "$crashes" -ne 0 ]; then
        say "$h: FINDING (exit $rc): see $log and $findings"
        status=1
    fi
    if ((fast)); then
        # -runs=0: every input of the corpora once, no mutation.
        n=$(find "$work" "tests/fuzz/corpus/$h" -type f | wc -l)
        say "$h: running the $n inputs of the working corpus under ASan + UBSan (log: $log.asan)"
        if ! build-fuzz/tests/fuzz/fuzz_$h -runs=0 -timeout=20 -close_fd_mask="$mask" -artifact_prefix="$findings/" \
            "$work" "tests/fuzz/corpus/$h" >"$log.asan" 2>&1; then
            say "$h: FINDING under ASan + UBSan: see $log.asan and $findings"
            status=1
        fi
    fi
    if [ "$merge" -eq 1 ]; then
        build-fuzz/tests/fuzz/fuzz_$h -merge=1 "tests/fuzz/corpus/$h" "$work" >>"$log" 2>&1
        say "$h: corpus merged into tests/fuzz/corpus/$h ($(find "tests/fuzz/corpus/$h" -type f | wc -l) files)"
    fi
done
printf '\n%-7s %12s %8s %10s %7s %7s %8s %s\n' harness executions seconds exec/s cov ft corpus findings
printf '%s\n' "${summary[@]}"
exit $status
