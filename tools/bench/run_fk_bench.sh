#!/usr/bin/env bash
# Builds and runs fk_bench: kinctl's FK and Jacobian against Orocos KDL and
# Pinocchio (issue 2), one table in one run.
#
# Installs what is missing: g++, cmake and liborocos-kdl-dev with apt-get
# (needs root), the pin wheel with pip into the project venv (.venv). Then
# configures build-bench (Release, -O2, KINCTL_BUILD_BENCH=ON), builds only
# the benchmark's targets and runs it. If Pinocchio cannot be had or built
# against, the benchmark still runs KDL and says why Pinocchio is missing.
#
# Usage: tools/bench/run_fk_bench.sh        (BUILD_DIR overrides build-bench)
set -euo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build-bench}
venv=$root/.venv
mkdir -p "$build"

# ---- system packages ----
missing=()
command -v g++ >/dev/null 2>&1 || missing+=(g++)
command -v cmake >/dev/null 2>&1 || missing+=(cmake)
dpkg-query -W -f='${Status}' liborocos-kdl-dev 2>/dev/null | grep -q "ok installed" || missing+=(liborocos-kdl-dev)
dpkg-query -W -f='${Status}' libeigen3-dev 2>/dev/null | grep -q "ok installed" || missing+=(libeigen3-dev)
if ((${#missing[@]})); then
    if [[ $(id -u) != 0 ]]; then
        echo "run_fk_bench: missing ${missing[*]}; run as root or install them" >&2
        exit 1
    fi
    echo "run_fk_bench: apt-get install ${missing[*]}"
    apt-get update -q >"$build/apt.log" 2>&1
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${missing[@]}" >>"$build/apt.log" 2>&1 ||
        { cat "$build/apt.log" >&2; exit 1; }
fi

# ---- Pinocchio from the pin wheel (optional) ----
pin_note=""
pin_prefix=""
if [[ ! -x $venv/bin/python ]] && ! python3 -m venv "$venv" >"$build/venv.log" 2>&1; then
    pin_note="cannot create the venv $venv (see $build/venv.log)"
elif ! "$venv/bin/pip" show pin >/dev/null 2>&1; then
    echo "run_fk_bench: pip install pin into $venv"
    "$venv/bin/pip" install -q pin >"$build/pip-pin.log" 2>&1 ||
        pin_note="pip install pin failed (see $build/pip-pin.log)"
fi
if [[ -z $pin_note ]]; then
    pin_prefix=$("$venv/bin/python" -c \
        'import os, sysconfig; print(os.path.join(sysconfig.get_paths()["purelib"], "cmeel.prefix"))')
fi

# ---- configure and build ----
configure() {
    cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_C_FLAGS_RELEASE="-O2 -DNDEBUG" -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" \
        -DKINCTL_BUILD_BENCH=ON -DKINCTL_BUILD_TESTS=OFF \
        -DKINCTL_PINOCCHIO_PREFIX="$pin_prefix" -DKINCTL_PINOCCHIO_NOTE="$pin_note" \
        >"$build/configure.log" 2>&1 || { cat "$build/configure.log" >&2; exit 1; }
}
build_bench() {
    # Only the benchmark and what it links: the rest of the tree is not ours
    # to hold hostage to a benchmark run.
    cmake --build "$build" --target fk_bench --parallel 2 >"$build/build.log" 2>&1
}
configure
if ! build_bench; then
    if [[ -n $pin_prefix ]]; then
        cp "$build/build.log" "$build/pinocchio-build.log"
        pin_note="building against the pin wheel in $pin_prefix failed (see $build/pinocchio-build.log)"
        pin_prefix=""
        echo "run_fk_bench: $pin_note; building without Pinocchio" >&2
        configure
        build_bench || { cat "$build/build.log" >&2; exit 1; }
    else
        cat "$build/build.log" >&2
        exit 1
    fi
fi

# ---- machine notes, then the benchmark ----
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $(nproc) CPUs, $(uname -sr)"
echo "kinctl $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo '(no git)');" \
    "KDL $(dpkg-query -W -f='${Version}' liborocos-kdl-dev 2>/dev/null);" \
    "pin $("$venv/bin/pip" show pin 2>/dev/null | sed -n 's/^Version: //p');" \
    "$(g++ --version | head -1); -O2 -ffp-contract=off"
"$build/tools/bench/fk_bench" | tee "$build/fk_bench.txt"
