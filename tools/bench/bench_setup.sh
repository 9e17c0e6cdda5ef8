# SPDX-License-Identifier: BSD-3-Clause
# bench_setup.sh - sourced by run_fk_bench.sh, run_ik_bench.sh and
# run_interp_bench.sh: installs what the benchmarks need, configures
# build-bench and builds the given targets, so all scripts set up the same
# way.
#
# Installs what is missing: g++, cmake and liborocos-kdl-dev with apt-get
# (needs root), tools/requirements.txt (the lcm wheel, which the tree's
# CMake needs) and the pin wheel with pip into the project venv (.venv). Then
# configures $build (Release, -O2, KINCTL_BUILD_BENCH=ON) and builds only the
# targets asked for. If Pinocchio cannot be had or built against, the
# benchmarks are built without it and pin_note says why; likewise Ruckig,
# whose source a script may fetch first (ruckig_src, or ruckig_note saying
# why not).
#
# Expects root (the repository); build (default $BUILD_DIR, else
# build-bench) and venv (default .venv) unless the script set them; sets
# pin_note, pin_prefix.
build=${build:-${BUILD_DIR:-$root/build-bench}}
venv=${venv:-$root/.venv}
ruckig_src=${ruckig_src:-}
ruckig_note=${ruckig_note:-}

bench_log() { echo "$(basename "$0"): $*" >&2; }

bench_install() {
    local missing=()
    command -v g++ >/dev/null 2>&1 || missing+=(g++)
    command -v cmake >/dev/null 2>&1 || missing+=(cmake)
    dpkg-query -W -f='${Status}' liborocos-kdl-dev 2>/dev/null | grep -q "ok installed" || missing+=(liborocos-kdl-dev)
    dpkg-query -W -f='${Status}' libeigen3-dev 2>/dev/null | grep -q "ok installed" || missing+=(libeigen3-dev)
    if ((${#missing[@]})); then
        if [[ $(id -u) != 0 ]]; then
            bench_log "missing ${missing[*]}; run as root or install them"
            exit 1
        fi
        bench_log "apt-get install ${missing[*]}"
        apt-get update -q >"$build/apt.log" 2>&1
        DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${missing[@]}" >>"$build/apt.log" 2>&1 ||
            { cat "$build/apt.log" >&2; exit 1; }
    fi

    # ---- the project's own Python requirements: the tree's CMake needs the
    # lcm wheel (lcmtypes/CMakeLists.txt) ----
    if [[ ! -x $venv/bin/python ]] && ! python3 -m venv "$venv" >"$build/venv.log" 2>&1; then
        cat "$build/venv.log" >&2
        exit 1
    fi
    if ! "$venv/bin/python" -c 'import lcm' >/dev/null 2>&1; then
        bench_log "pip install -r tools/requirements.txt into $venv"
        "$venv/bin/pip" install -q -r "$root/tools/requirements.txt" >"$build/pip-requirements.log" 2>&1 ||
            { cat "$build/pip-requirements.log" >&2; exit 1; }
    fi

    # ---- Pinocchio from the pin wheel (optional) ----
    pin_note=""
    pin_prefix=""
    if ! "$venv/bin/pip" show pin >/dev/null 2>&1; then
        bench_log "pip install pin into $venv"
        "$venv/bin/pip" install -q pin >"$build/pip-pin.log" 2>&1 ||
            pin_note="pip install pin failed (see $build/pip-pin.log)"
    fi
    if [[ -z $pin_note ]]; then
        pin_prefix=$("$venv/bin/python" -c \
            'import os, sysconfig; print(os.path.join(sysconfig.get_paths()["purelib"], "cmeel.prefix"))')
    fi
}

bench_configure() {
    cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE="$venv/bin/python" \
        -DCMAKE_C_FLAGS_RELEASE="-O2 -DNDEBUG" -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" \
        -DKINCTL_BUILD_BENCH=ON -DKINCTL_BUILD_TESTS=OFF \
        -DKINCTL_PINOCCHIO_PREFIX="$pin_prefix" -DKINCTL_PINOCCHIO_NOTE="$pin_note" \
        -DKINCTL_RUCKIG_SOURCE="$ruckig_src" -DKINCTL_RUCKIG_NOTE="$ruckig_note" \
        >"$build/configure.log" 2>&1 || { cat "$build/configure.log" >&2; exit 1; }
}

# Builds only the given targets and what they link: the rest of the tree is
# not ours to hold hostage to a benchmark run.
bench_build() {
    cmake --build "$build" --target "$@" --parallel 2 >"$build/build.log" 2>&1
}

# After a failed build, leaves out one optional library (Ruckig first, then
# Pinocchio) and says why; false when none is left to leave out.
bench_drop_optional() {
    local log note
    if [[ -n $ruckig_src ]]; then
        log=$build/ruckig-build.log
        note="building Ruckig from $ruckig_src failed (see $log)"
        ruckig_note=$note
        ruckig_src=""
    elif [[ -n $pin_prefix ]]; then
        log=$build/pinocchio-build.log
        note="building against the pin wheel in $pin_prefix failed (see $log)"
        pin_note=$note
        pin_prefix=""
    else
        return 1
    fi
    cp "$build/build.log" "$log"
    bench_log "$note; building without it"
}

# Install, configure, build "$@"; without an optional library when building
# with it fails.
bench_setup() {
    mkdir -p "$build"
    bench_install
    bench_configure
    until bench_build "$@"; do
        bench_drop_optional || { cat "$build/build.log" >&2; exit 1; }
        bench_configure
    done
}

bench_machine_notes() {
    echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $(nproc) CPUs, $(uname -sr)"
    echo "kinctl $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo '(no git)')$(git -C "$root" diff --quiet HEAD -- core 2>/dev/null || echo ' + uncommitted core changes');" \
        "KDL $(dpkg-query -W -f='${Version}' liborocos-kdl-dev 2>/dev/null);" \
        "pin $("$venv/bin/pip" show pin 2>/dev/null | sed -n 's/^Version: //p');" \
        "$(g++ --version | head -1); -O2 -ffp-contract=off"
}
