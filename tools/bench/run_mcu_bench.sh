#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The core's budgets on a Cortex-M4F, printed beside their targets (issue
# 20): code size per module (and what an image links of it, from its map
# with mcu_linked.py), worst-case stack per public entry point (from
# GCC's call graphs, checked against the high-water mark measured on the
# board), and instructions per call on QEMU's mps2-an386 with -icount
# shift=0 beside callgrind's count of the same program on this host.
# Both configurations of mcu/CMakeLists.txt: the header defaults and the
# small one (KINCTL_MCU_SMALL_*).
#   tools/bench/run_mcu_bench.sh [MCU_BUILD_DIR [HOST_BENCH [MCU_M3_BUILD_DIR]]]
# defaults: build/mcu, build/tests/mcu/mcu_bench_host and build/mcu-m3 (built
# by `cmake --build build --target kinctl_mcu kinctl_mcu_m3 mcu_bench_host`).
# Last, the fixed-point FK and Jacobian (kinctl/fx.h) beside the float ones
# on the M4F (mps2-an386) and the Cortex-M3 (mps2-an385, soft float).
# Exit status 1 when a measurement fails (a program fails, or a measured
# stack exceeds its static bound); a missed target is printed, not fatal.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
mcu=${1:-build/mcu}
host_bench=${2:-build/tests/mcu/mcu_bench_host}
mcu_m3=${3:-build/mcu-m3}
qemu=(qemu-system-arm -M mps2-an386 -nographic -semihosting-config enable=on,target=native -icount shift=0)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0

# Targets (issue 20).
text_target=65536        # .text of the float core at -Os (below: without the fixed-point modules)
ctrl_target=32768        # sizeof(kc_ctrl), small configuration
tick_line_target=10000   # instructions of a controller tick on a line (worst tick)
tick_stack_target=4096   # stack of a controller tick on a line
ik_target=5000           # instructions of an IK step (worst call)

# The fixed-point modules (kinctl/fx.h) are built into every core but are
# for cores without an FPU: a float firmware never calls them and
# --gc-sections drops them. The issue's size target is the float core's,
# so they are listed apart and not in its total.
fx_modules=" fx fx_chain fx_interp "

verdict() { # measured target
    if [ "$1" -le "$2" ]; then echo "met"; else echo "MISSED"; fi
}

declare -A core_dir=([default]="$mcu/core/CMakeFiles/kinctl_core_float.dir"
                     [small]="$mcu/CMakeFiles/kinctl_core_small.dir")
declare -A bench_dir=([default]="$mcu/CMakeFiles/mcu_bench.dir" [small]="$mcu/CMakeFiles/mcu_bench_small.dir")
declare -A image=([default]="$mcu/mcu_bench.elf" [small]="$mcu/mcu_bench_small.elf")

for cfg in default small; do
    if [ -z "$(find "${core_dir[$cfg]}" -name '*.c.obj' -print -quit 2>/dev/null)" ]; then
        echo "run_mcu_bench.sh: no core objects in ${core_dir[$cfg]}: is $mcu an mcu/ build?" >&2
        exit 2
    fi
done
echo "== code size per module (arm-none-eabi-size of each object, $(basename "$mcu") build type MinSizeRel: -Os)"
for cfg in default small; do
    printf '%-10s %-10s %8s %6s %6s\n' config module .text .data .bss
    total=0 fx_total=0
    for obj in $(find "${core_dir[$cfg]}" -name "*.c.obj" | sort); do
        read -r text data bss _ < <(arm-none-eabi-size "$obj" | tail -1)
        module=$(basename "$obj" .c.obj)
        if [[ $fx_modules == *" $module "* ]]; then
            printf '%-10s %-10s %8d %6d %6d  (fixed point)\n' "$cfg" "$module" "$text" "$data" "$bss"
            fx_total=$((fx_total + text))
        else
            printf '%-10s %-10s %8d %6d %6d\n' "$cfg" "$module" "$text" "$data" "$bss"
            total=$((total + text))
        fi
    done
    printf '%-10s %-10s %8d   float core, target <= %d: %s\n' "$cfg" total "$total" "$text_target" \
        "$(verdict "$total" "$text_target")"
    printf '%-10s %-10s %8d   fixed point (fx, fx_chain, fx_interp), for cores without an FPU; with them %d\n' \
        "$cfg" fx_all "$fx_total" "$((total + fx_total))"
    # What a firmware carries: the core's sections kept in the bench image,
    # which calls FK, the Jacobian, the IK step, the controller with every
    # goal kind and the dry run (the totals above count every function of
    # every module, e.g. the path methods and conversions the controller
    # never calls).
    linked=$("$here/mcu_linked.py" "${image[$cfg]%.elf}.map" | awk '$2 == "total" {print $3}')
    printf '%-10s %-10s %8d   linked into %s (--gc-sections): what a firmware running the controller carries\n' \
        "$cfg" linked "$linked" "$(basename "${image[$cfg]}")"
done

echo
echo "== the board (mps2-an386, -icount shift=0)"
for cfg in default small; do
    "${qemu[@]}" -kernel "${image[$cfg]}" >"$tmp/board.$cfg" || { cat "$tmp/board.$cfg"; echo "FAIL: the $cfg bench failed on the board"; exit 1; }
done
for cfg in default small; do
    printf 'sizeof(kc_ctrl) %-8s %7d B' "$cfg" "$(awk '$1 == "sizeof" && $2 == "kc_ctrl" {print $3}' "$tmp/board.$cfg")"
    [ "$cfg" = small ] && printf '   target <= %d: %s' "$ctrl_target" \
        "$(verdict "$(awk '$1 == "sizeof" && $2 == "kc_ctrl" {print $3}' "$tmp/board.$cfg")" "$ctrl_target")"
    echo
done

echo
echo "== stack (bytes): static worst case from -fcallgraph-info (libm frames not included) vs measured high-water"
printf '%-8s %-16s %8s %10s %10s  %s\n' config entry static bench_fn measured "unknown callees"
for cfg in default small; do
    # With link-time optimisation (KINCTL_MCU_LTO) the core's code is
    # generated at the link: its call graph is the image's (the objects'
    # own graphs are those of machine code the image does not use). The
    # image's symbols give the functions LTO folded into others (one body,
    # two names) their frames, by address.
    core_graph=${core_dir[$cfg]}
    if grep -Eq '\.ltrans[0-9]+\.ltrans\.o' "${image[$cfg]%.elf}.map"; then
        core_graph=$(ls "${image[$cfg]}".ltrans*.ci)
    fi
    arm-none-eabi-nm "${image[$cfg]}" >"$tmp/nm.$cfg"
    "$here/mcu_stack.py" --symbols "$tmp/nm.$cfg" $core_graph "${bench_dir[$cfg]}" -- \
        kc_fk_eval kc_fk_jacobian kc_ik_step kc_ctrl_step kc_check_from \
        bench_fk bench_jacobian bench_ik_step bench_ctrl_step bench_ctrl_check >"$tmp/stack.$cfg"
    for pair in fk_eval:fk fk_jacobian:jacobian ik_step:ik_step ctrl_step:ctrl_step check_from:ctrl_check; do
        entry=kc_${pair%%:*} fn=bench_${pair#*:}
        static=$(awk -v f="$entry" '$2 == f {print $3}' "$tmp/stack.$cfg")
        bound=$(awk -v f="$fn" '$2 == f {print $3}' "$tmp/stack.$cfg")
        unknown=$(awk -v f="$entry" '$2 == f {for (i = 4; i <= NF; i++) printf "%s ", $i}' "$tmp/stack.$cfg")
        measured=$(awk -v f="$fn" '$1 == "stack" && $2 == f && $3 > m {m = $3} END {print m + 0}' "$tmp/board.$cfg")
        check=ok
        if [ "$measured" -gt "$bound" ]; then check="EXCEEDS the static bound $bound of $fn"; status=1; fi
        printf '%-8s %-16s %8d %10d %10d  %s(%s)\n' "$cfg" "$entry" "$static" "$bound" "$measured" "$unknown" "$check"
    done
done
# The target is a line's tick. The call graph cannot tell a line's tick
# from a path's: the static bound is every goal kind's (planning a
# Cartesian path is the deepest), printed beside it; the line's own tick is
# measured (its first tick, which plans the segment, the deepest).
for cfg in default small; do
    tick_static=$(awk '$1 == "stack" && $2 == "kc_ctrl_step" {print $3}' "$tmp/stack.$cfg")
    tick_line=$(awk '$1 == "stack" && $2 == "bench_ctrl_step" {n++} n == 2 {print $3; exit}' "$tmp/board.$cfg")
    echo "controller tick stack ($cfg): a line, measured $tick_line B (target <= $tick_stack_target: $(verdict "$tick_line" "$tick_stack_target"));" \
         "every goal kind, static $tick_static B ($(verdict "$tick_static" "$tick_stack_target") <= $tick_stack_target)"
done

echo
echo "== instructions per call: board (SysTick under -icount: +-40 per call) and x86 callgrind (host float core)"
have_valgrind=1
command -v valgrind >/dev/null && command -v callgrind_annotate >/dev/null || have_valgrind=0
declare -A x86
callgrind() { # out-file args...: inclusive Ir of every bench_ function
    local out=$1
    shift
    valgrind --tool=callgrind --callgrind-out-file="$out" "$host_bench" "$@" >"$out.stdout" 2>/dev/null
    callgrind_annotate --inclusive=yes "$out" 2>/dev/null | awk 'match($0, /bench\.c:bench_[a-z_]+/) {
        f = substr($0, RSTART + 8, RLENGTH - 8); n = $1; gsub(",", "", n)
        if (!(f in seen)) { seen[f] = 1; print f, n } }'
}
if [ "$have_valgrind" = 1 ] && [ -x "$host_bench" ]; then
    callgrind "$tmp/cg.all" >"$tmp/cg.all.ir"
    for what in fk jacobian ik_step ctrl_check; do
        calls=$(awk -v w="$what" '$1 == "calls" && ($2 == w || $2 == w "_line") {print $3}' "$tmp/cg.all.stdout")
        ir=$(awk -v f="bench_$what" '$1 == f {print $2}' "$tmp/cg.all.ir")
        [ -n "$ir" ] && [ -n "$calls" ] && x86[$what]=$(((ir + calls / 2) / calls))
    done
    k=0
    for kind in joint line arc path path_cart servo; do
        callgrind "$tmp/cg.$kind" ctrl "$k" >"$tmp/cg.$kind.ir"
        calls=$(awk '$1 == "calls" {print $3}' "$tmp/cg.$kind.stdout")
        ir=$(awk '$1 == "bench_ctrl_step" {print $2}' "$tmp/cg.$kind.ir")
        [ -n "$ir" ] && [ -n "$calls" ] && x86[ctrl_tick_$kind]=$(((ir + calls / 2) / calls))
        k=$((k + 1))
    done
fi
printf '%-8s %-20s %7s %10s %10s %12s  %s\n' config call calls "mean" "max" "x86 mean" target
for cfg in default small; do
    while read -r _ what _ calls _ mean _ max; do
        key=$what
        [ "$what" = ctrl_check_line ] && key=ctrl_check
        target=""
        case "$what" in
        ctrl_tick_line) target="max <= $tick_line_target: $(verdict "$max" "$tick_line_target")" ;;
        ik_step) target="max <= $ik_target: $(verdict "$max" "$ik_target")" ;;
        esac
        printf '%-8s %-20s %7d %10d %10d %12s  %s\n' "$cfg" "$what" "$calls" "$mean" "$max" "${x86[$key]:-n/a}" "$target"
    done < <(awk '$1 == "icount"' "$tmp/board.$cfg")
done
[ "$have_valgrind" = 1 ] || echo "(valgrind not found: no x86 counts)"

echo
echo "== fixed point (kinctl/fx.h) beside float, PUMA 560, instructions per call"
printf '%-28s %-24s %10s %10s\n' board call mean max
for board in "mps2-an386 (M4F, FPU):$mcu" "mps2-an385 (M3, soft float):$mcu_m3"; do
    name=${board%%:*} dir=${board#*:}
    machine=${name%% *}
    qemu-system-arm -M "$machine" -nographic -semihosting-config enable=on,target=native -icount shift=0 \
        -kernel "$dir/mcu_fx_bench.elf" >"$tmp/fx" || { cat "$tmp/fx"; echo "FAIL: the fixed-point bench failed on $machine"; exit 1; }
    while read -r _ what _ _ _ mean _ max; do
        printf '%-28s %-24s %10d %10d\n' "$name" "$what" "$mean" "$max"
    done < <(awk '$1 == "icount"' "$tmp/fx")
done
exit $status
