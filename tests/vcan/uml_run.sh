#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Runs the vcan suite (pytest on tests/vcan) on a real SocketCAN interface:
#   1. directly, where this kernel has AF_CAN and vcan0 exists or can be made
#      (root: modprobe vcan, ip link add vcan0 type vcan);
#   2. otherwise inside User Mode Linux (Debian user-mode-linux, kmod): UML
#      boots as a normal process with the host's / as its root (hostfs), its
#      init loads can, can-raw, can-bcm (python-can's periodic frames), can-dev
#      and vcan from /usr/lib/uml/modules,
#      brings up vcan0 and lo with multicast (a route for 224.0.0.0/4: LCM),
#      runs the same pytest command in the same directory with the same
#      environment, and writes its exit code to a file UML leaves behind;
#   3. neither: says so loudly and exits 77 (ctest's SKIP_RETURN_CODE).
#
#   tests/vcan/uml_run.sh [pytest arguments]     (PYTHON: the interpreter)
#   tests/vcan/uml_run.sh --exec CMD [ARGS...]   # another command (a benchmark)
#   KINCTL_VCAN_FORCE_UML=1 tests/vcan/uml_run.sh   # UML even with vcan here
#   KINCTL_VCAN_HOST_ONLY=1 tests/vcan/uml_run.sh   # never UML (ASan builds:
#       ASan's x86-64 shadow needs a 47-bit address space, a UML 6.1 process
#       has 39), exit 77 where the host has no vcan
#
# Timing inside UML is poor (one virtual CPU, ptrace on every system call):
# the suite checks function, never timing.
set -u
here=$(cd "$(dirname "$0")" && pwd)
python=${PYTHON:-python3}
if [ "${1:-}" = --exec ]; then
    shift
    pytest_cmd=("$@")
else
    pytest_cmd=("$python" -m pytest -q -rs -p no:cacheprovider "$here" "$@")
fi

host_vcan() {
    "$python" - <<'EOF' 2>/dev/null || return 1
import socket
socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW).close()
EOF
    if ! ip link show vcan0 >/dev/null 2>&1; then
        [ "$(id -u)" -eq 0 ] || return 1
        modprobe vcan 2>/dev/null || true
        ip link add dev vcan0 type vcan 2>/dev/null || return 1
    fi
    ip link set up vcan0 2>/dev/null || true
    ip link show vcan0 | grep -q UP
}

if [ "${KINCTL_VCAN_FORCE_UML:-0}" != 1 ] && host_vcan; then
    echo "vcan suite: on this host's vcan0"
    exec "${pytest_cmd[@]}"
fi

if [ "${KINCTL_VCAN_HOST_ONLY:-0}" = 1 ]; then
    echo "************************************************************************"
    echo "vcan suite SKIPPED in this build: this kernel has no AF_CAN/vcan, and"
    echo "this build's kinctld (ASan) cannot run inside User Mode Linux; in UML"
    echo "the UBSan-only build runs the suite (scripts/test.sh), and the plain"
    echo "build's vcan.memcheck runs it under valgrind memcheck"
    echo "************************************************************************"
    exit 77
fi

uml_modules=$(ls -d /usr/lib/uml/modules/*/ 2>/dev/null | head -n 1)
if ! command -v linux >/dev/null 2>&1 || [ -z "$uml_modules" ] || ! command -v insmod >/dev/null 2>&1; then
    echo "************************************************************************"
    echo "vcan suite SKIPPED: this kernel has no AF_CAN/vcan and User Mode Linux"
    echo "is not installed (Debian: user-mode-linux kmod; scripts/setup.sh does it)"
    echo "************************************************************************"
    exit 77
fi

work=$(mktemp -d /tmp/kinctl-uml.XXXXXX)
trap '[ -n "${KINCTL_UML_KEEP:-}" ] || rm -rf "$work"' EXIT
echo 255 >"$work/rc"
# The environment and the command, for the init inside.
export -p | grep -v -E '^declare -x (BASH_|SHLVL|OLDPWD|_=)' >"$work/env.sh"
printf '%q ' "${pytest_cmd[@]}" >"$work/cmd"
cat >"$work/init.sh" <<EOF
#!/bin/bash
# PID 1 inside UML.
# UML keeps only the FXSAVE part of the FPU state (uml_seccomp.py): no AVX
# in glibc, from this very process on (it starts again with the setting).
if [ -z "\${GLIBC_TUNABLES:-}" ]; then
    export GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX,-AVX2,-AVX512F,-AVX512VL,-AVX512BW,-AVX512DQ,-AVX512CD,-FMA,-FMA4,-AVX_Fast_Unaligned_Load
    exec /bin/bash "\$0"
fi
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t tmpfs tmp /dev/shm 2>/dev/null
for m in net/can/can.ko net/can/can-raw.ko net/can/can-bcm.ko drivers/net/can/dev/can-dev.ko drivers/net/can/vcan.ko; do
    insmod "${uml_modules}kernel/\$m" || echo "uml: insmod \$m failed"
done
sysctl -q -w net.core.rmem_max=16777216 net.core.wmem_max=16777216
ip link set lo up
ip link set lo multicast on
ip route add 224.0.0.0/4 dev lo
ip link add dev vcan0 type vcan
ip link set up vcan0
saved_tunables=\$GLIBC_TUNABLES
. "$work/env.sh"
export GLIBC_TUNABLES=\$saved_tunables
export KINCTL_IN_UML=1 KINCTL_VCAN_REQUIRED=1
export KINCTLD_TEST_SLOWDOWN=\${KINCTLD_TEST_SLOWDOWN:-3}
cd "$PWD"
echo "vcan suite: inside User Mode Linux \$(uname -r), vcan0 up"
bash -c "\$(cat "$work/cmd")" </dev/null 2>&1 | tee "$work/log"
echo \${PIPESTATUS[0]} >"$work/rc"
sync
# Power off (reboot(2), LINUX_REBOOT_CMD_POWER_OFF) without halt(8), which a
# minimal root lacks: PID 1 must never exit, or UML panics.
exec "$python" -c 'import ctypes; ctypes.CDLL(None, use_errno=True).reboot(0x4321FEDC); raise SystemExit("uml: reboot(2) failed")'
EOF
chmod +x "$work/init.sh"
echo "vcan suite: no AF_CAN here; booting User Mode Linux ($(basename "$uml_modules"))"
"$python" "$here/uml_seccomp.py" linux mem=1536M rootfstype=hostfs rw init="$work/init.sh" \
    umid="kinctl-$$" con=null con0=null,fd:1 quiet </dev/null 2>&1 |
    grep --line-buffered -v -E '^(\s*\[<|Stack:|Call Trace:|epollctl|Checking|Core dump|\s+(soft|hard) - )'
rc=$(cat "$work/rc")
echo "vcan suite: User Mode Linux exited, the command's exit code $rc"
exit "$rc"
