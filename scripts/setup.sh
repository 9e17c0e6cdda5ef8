#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Installs what kinctl needs on a Debian 12 machine and builds it. Idempotent:
# a second run installs nothing and rebuilds only what changed.
#   scripts/setup.sh [BUILD_DIR [extra cmake args...]]
#   scripts/setup.sh --runtime-packages   the Debian packages a controller PC needs
# KINCTL_BUILD_TARGETS="t1 t2" builds only those targets (default: all).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${1:-build}
shift || true

say() { printf '\033[1m[setup]\033[0m %s\n' "$*"; }

# Debian packages, each with the step that needs it. A fresh Debian 12 root
# (minbase, as the debian:12 image) has none of them.
#
# Run time: what a controller PC needs beside the installed .deb (whose
# Depends bring libconfig9, libjansson4 and libglib2.0-0) and wheel
# (docs/deploy.md); `scripts/setup.sh --runtime-packages` prints the list.
runtime_packages=(
    # the kinctl wheel: a venv to pip install it into
    python3 python3-venv
    # CAN output: ip (bitrate, restart-ms, up), candump for a first look
    iproute2 can-utils
)
if [ "$build_dir" = --runtime-packages ]; then
    echo "${runtime_packages[*]}"
    exit 0
fi
# Development: building and every test (scripts/test.sh) and the demo; a
# controller PC needs none of these.
apt_packages=(
    "${runtime_packages[@]}"
    # build: compilers and build tools (build-essential brings dpkg-dev, whose
    # dpkg-shlibdeps the .deb needs, and binutils' readelf for the install test)
    build-essential cmake ninja-build pkg-config
    # build: clang for the ASan + UBSan and UBSan builds (scripts/test.sh) and
    # the fuzzers; its sanitizer and libFuzzer runtimes are a package of their
    # own; llvm's llvm-symbolizer names the functions in sanitizer reports, which
    # LeakSanitizer's suppressions (tests/fuzz/lsan.supp) match by name
    clang libclang-rt-14-dev llvm
    # build: libconfig (description and configuration files), jansson (JSON in
    # kinctl-calc), cmocka (the C unit tests)
    libconfig-dev libjansson-dev libcmocka-dev
    # build: the LCM wheel's lcm-gen and liblcm load GLib; kinctld links the
    # wheel's static liblcm, whose GLib is found with pkg-config
    libglib2.0-0 libglib2.0-dev
    # build: javac and jar make the message jar for lcm-spy (tests/msg, kinctl spy)
    default-jdk-headless
    # install.deb: CPack's DEB generator runs `file` for the shared-library
    # dependencies
    file
    # faults: stress-ng loads the CPUs
    stress-ng
    # viz: ffmpeg for `kinctl view --save FILE.mp4`; Tk for matplotlib's live
    # window (`kinctl view` without --save), xvfb and xauth (xvfb-run) give it a
    # display
    ffmpeg python3-tk xvfb xauth
    # vcan: candump and cangen (can-utils, above); User Mode Linux with kmod
    # (insmod) for a kernel with vcan where the host's has none
    # (tests/vcan/uml_run.sh), iproute2 (above; ip: vcan0, the multicast route)
    # and procps (sysctl: socket buffer limits) inside it and on a host with vcan
    user-mode-linux kmod procps
    # analysis: tests/analysis
    cppcheck clang-tidy valgrind
    # systemd.unit: a Debian 12 root (mmdebstrap) booted by systemd-nspawn
    # (systemd-container) runs the shipped unit under systemd (tests/systemd)
    mmdebstrap systemd-container
    # mcu: the Cortex-M4F build of the core (mcu/, tests/mcu) and QEMU's
    # mps2-an386 board that runs it (tools/bench/run_mcu_bench.sh too)
    gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm
)
missing=()
for p in "${apt_packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
    say "installing Debian packages: ${missing[*]}"
    sudo_cmd=()
    [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
    export DEBIAN_FRONTEND=noninteractive
    "${sudo_cmd[@]}" apt-get update -qq
    "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
    say "Debian packages present"
fi

# Python packages live in the project's own virtual environment.
if [ ! -x .venv/bin/python ]; then
    say "creating the Python environment .venv"
    python3 -m venv .venv
fi
req_stamp=.venv/.requirements.sha256
req_sum=$(sha256sum tools/requirements.txt | cut -d' ' -f1)
if [ "$(cat "$req_stamp" 2>/dev/null)" != "$req_sum" ]; then
    say "installing Python packages from tools/requirements.txt"
    .venv/bin/python -m pip install -q --upgrade pip
    .venv/bin/python -m pip install -q -r tools/requirements.txt
    echo "$req_sum" >"$req_stamp"
else
    say "Python packages present"
fi

# LCM comes from the `lcm` wheel: its prefix is site-packages, with bin/lcm-gen,
# lib/liblcm.so, include/lcm and the CMake package config in lib/lcm/cmake.
lcm_prefix=$(.venv/bin/python -c 'import lcm, os; print(os.path.dirname(os.path.dirname(lcm.__file__)))')
"$lcm_prefix/bin/lcm-gen" --version >/dev/null || { say "lcm-gen from the lcm wheel does not run"; exit 1; }

say "configuring and building in $build_dir"
cmake -S . -B "$build_dir" -G Ninja -DPython3_EXECUTABLE="$PWD/.venv/bin/python" \
    -Dlcm_DIR="$lcm_prefix/lib/lcm/cmake" "$@" >/dev/null
read -r -a targets <<<"${KINCTL_BUILD_TARGETS:-all}"
cmake --build "$build_dir" --target "${targets[@]}"

# The kinctl CLI and Python API (tools/kinctl), installed editable into .venv
# (.venv/bin/kinctl). It imports the message classes kinctl_msgs that the build
# generates into <build>/lcmtypes/python: a .pth file in the venv names that
# directory, for the default build dir `build` (or the first one built), so
# plain `.venv/bin/kinctl` works; ctest sets PYTHONPATH to each build's own.
site=$(.venv/bin/python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
if [ "$build_dir" = build ] || [ ! -e "$site/kinctl_msgs.pth" ]; then
    echo "$(cd "$build_dir" && pwd)/lcmtypes/python" >"$site/kinctl_msgs.pth"
fi
cli_stamp=.venv/.kinctl-cli.sha256
cli_sum=$(sha256sum tools/pyproject.toml | cut -d' ' -f1)
if [ ! -x .venv/bin/kinctl ] || [ "$(cat "$cli_stamp" 2>/dev/null)" != "$cli_sum" ]; then
    say "installing the kinctl CLI (pip install -e tools)"
    # (setuptools warns about editable installs on every run: shown on failure only)
    pip_log=$(.venv/bin/python -m pip install -q --no-deps -e tools 2>&1) || { printf '%s\n' "$pip_log"; exit 1; }
    echo "$cli_sum" >"$cli_stamp"
fi
