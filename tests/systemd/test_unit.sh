#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# systemd.unit: the deployment path of docs/deploy.md on a fresh Debian 12
# root, with the shipped kinctld.service started by a real systemd, and what
# it gives kinctld checked from the process itself.
#
# How: a Debian 12 root (mmdebstrap minbase + systemd, the .deb's run-time
# dependencies and scripts/setup.sh --runtime-packages, made once and kept in
# the build directory), a copy of it with this build's .deb installed by dpkg,
# booted with `systemd-nspawn --boot`: systemd 252 is the container's PID 1.
# A probe service in the container (probe.sh) installs the kinctl wheel the
# .deb carries into a fresh venv, imports a URDF (pybullet's KUKA iiwa) into
# the description file that the configuration includes (rt.priority 71,
# rt.cpu 0, so neither is the default), runs kinctld --check, starts the
# unit as the package installs it with a drop-in that only gives it that
# configuration, reads /proc for kinctld's threads, drives it with the
# installed kinctl (status, a joint goal, a log, spy's jar lookup), stops the
# unit and powers the container off; this script judges what it wrote:
#   - every step exits 0; the service runs the imported arm (7 joints);
#     kinctl and kinctl_msgs come from the venv, the jar from
#     /usr/share/kinctl/java; the log holds about a second of setpoints;
#   - the unit active, no restart, no warning from kinctld (a refused
#     SCHED_FIFO, affinity or mlockall is one);
#   - exactly one thread SCHED_FIFO, at rt.priority, allowed only rt.cpu;
#     the I/O thread SCHED_OTHER and kept off that CPU (kinctld pins both;
#     the unit sets no CPUAffinity);
#   - VmLck (/proc/PID/status) at least VmRSS: mlockall locked every page;
#   - `systemctl stop`: SIGTERM, a controlled stop, exit 0 (systemd's own
#     record at debug level), Result=success.
# Why nspawn: it runs the real systemd on the real kernel, so SCHED_FIFO,
# affinity, capabilities, the seccomp filter and mlockall are the kernel's
# own (User Mode Linux has one CPU and its own scheduler). nspawn needs a
# cgroup file system and "/" to be a mount point: it runs in a mount
# namespace of its own, in a bind mount of the whole tree, with a fresh
# cgroup2 at /sys/fs/cgroup, so it works the same on a host with systemd, on
# one without (this machine, a cgroup v1 layout), and in a chroot whose /sys
# was bind-mounted without its submounts (CI). --register=no --keep-unit:
# no systemd-machined or D-Bus on the host is needed; --uuid and
# --link-journal=no: neither needs the host's /etc/machine-id (a fresh root
# has an empty one). --capability: a
# machine's PID 1 holds every capability, nspawn's container by default not
# CAP_IPC_LOCK or CAP_SYS_RESOURCE, which the unit grants or uses (where the
# host's root lacks CAP_SYS_RESOURCE, as on these build machines, the unit's
# LimitMEMLOCK and LimitRTPRIO cannot be raised, and its ambient CAP_IPC_LOCK
# and CAP_SYS_NICE alone carry mlockall and SCHED_FIFO: the diagnostics
# printed below show which).
#
# The wheel's dependencies (lcm, tqdm, yourdfpy) are the build venv's,
# bound read-only into the container and named by a .pth file: the test
# needs no network once the root is made.
#
#   test_unit.sh BUILD_DIR PYTHON    exit 77 (skipped) when not root or without
#                                    systemd-nspawn (systemd-container) or mmdebstrap
set -euo pipefail
build=$(cd "$1" && pwd)
python=$2
here=$(cd "$(dirname "$0")" && pwd)

skip() { echo "SKIP: $*"; exit 77; }
fail() { echo "FAIL: $*" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] || skip "systemd-nspawn needs root"
for tool in systemd-nspawn mmdebstrap dpkg-deb unshare; do
    command -v "$tool" >/dev/null || skip "$tool is missing (scripts/setup.sh installs systemd-container and mmdebstrap)"
done

tmp=$(mktemp -d "${TMPDIR:-/var/tmp}/kinctl-systemd.XXXXXX")
mnt=""
# $mnt is only ever removed with rmdir: it held a bind mount of / inside the
# namespace, and must never be recursed into.
trap 'rm -rf "$tmp"; [ -z "$mnt" ] || rmdir "$mnt"' EXIT

cpack -G DEB --config "$build/CPackConfig.cmake" -B "$tmp/deb" >"$tmp/cpack.log" 2>&1 ||
    { cat "$tmp/cpack.log" >&2; fail "cpack -G DEB"; }
deb=$(ls "$tmp"/deb/kinctl_*.deb)

# The base root: systemd, the package's Depends (names only) and the
# run-time packages of a controller PC, made once per set of packages. Apt's
# sources: the host's, else Debian's default mirror.
depends=$(dpkg-deb -f "$deb" Depends | sed -E 's/\([^)]*\)//g; s/ //g')
runtime=$("$here/../../scripts/setup.sh" --runtime-packages | tr ' ' ,)
include="systemd,$depends,$runtime"
base=$build/tests/systemd/root-base
if [ "$(cat "$base.include" 2>/dev/null)" != "$include" ] || [ ! -x "$base/lib/systemd/systemd" ]; then
    rm -rf "$base" "$base.include"
    sources=/etc/apt/sources.list.d/debian.sources
    [ -f "$sources" ] || sources=/etc/apt/sources.list
    [ -f "$sources" ] || sources=""
    echo "making a Debian 12 root with $include (mmdebstrap, once)"
    mmdebstrap --variant=minbase --include="$include" bookworm "$base" $sources >"$tmp/mmdebstrap.log" 2>&1 ||
        { tail -20 "$tmp/mmdebstrap.log" >&2; fail "mmdebstrap"; }
    echo "$include" >"$base.include"
fi

root=$tmp/root
cp -a "$base" "$root"
cp "$deb" "$root/tmp/"
chroot "$root" dpkg -i "/tmp/$(basename "$deb")" >"$tmp/dpkg.log" 2>&1 || { cat "$tmp/dpkg.log" >&2; fail "dpkg -i"; }
cmp "$root/usr/lib/systemd/system/kinctld.service" "$here/../../daemon/kinctld.service" ||
    fail "the installed unit is not daemon/kinctld.service"

# The configuration and the drop-in a deployment writes (docs/deploy.md);
# the robot is the one import-urdf writes in the container.
ncpu=$(nproc)
prio=71 cpu=0
port=$((7700 + RANDOM % 200))
mkdir -p "$root/etc/kinctl" "$root/etc/systemd/system/kinctld.service.d" "$tmp/out"
cp "$("$python" -c 'import os, pybullet_data; print(os.path.join(pybullet_data.getDataPath(), "kuka_iiwa", "model.urdf"))')" \
    "$root/root/arm.urdf"
echo 0.3,0.4,-0.3,-0.8,0.2,0.5,0.1 >"$root/root/goal_q"
deps=$("$python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
cat >"$root/etc/kinctl/kinctld.cfg" <<EOF
@include "arm.cfg"
controller = {
  lcm_url = "udpm://239.255.76.67:$port?ttl=0";
  rt = { enable = true; priority = $prio; cpu = $cpu; mlock = true; };
};
EOF
cat >"$root/etc/systemd/system/kinctld.service.d/config.conf" <<'EOF'
[Service]
ExecStart=
ExecStart=kinctld --config /etc/kinctl/kinctld.cfg
EOF
install -m 755 "$here/probe.sh" "$root/usr/local/sbin/kinctl-probe"
cat >"$root/etc/systemd/system/kinctl-probe.service" <<'EOF'
[Unit]
Description=the deployment path, kinctld's threads, stop, power off
After=multi-user.target
[Service]
Type=oneshot
ExecStart=/usr/local/sbin/kinctl-probe /probe /opt/build-deps
ExecStopPost=/usr/bin/systemctl poweroff --no-block
EOF
mkdir -p "$root/etc/systemd/system/default.target.wants"
ln -s /etc/systemd/system/kinctl-probe.service "$root/etc/systemd/system/default.target.wants/"
# No getty on the container's console, no waiting for a network.
chroot "$root" systemctl mask console-getty.service systemd-networkd-wait-online.service >/dev/null 2>&1

echo "booting the root with systemd-nspawn (systemd $(chroot "$root" /lib/systemd/systemd --version | head -1 | cut -d' ' -f2))"
start=$(date +%s)
# In a mount namespace of its own: "/" made private where it is a mount
# point, then the whole tree bound onto $mnt and entered, so that "/" is a
# mount point there even when this runs in a chroot (nspawn needs one);
# there a fresh cgroup2 and a tmpfs /run for nspawn's own state.
mnt=$(mktemp -d "${TMPDIR:-/var/tmp}/kinctl-nspawn.XXXXXX")
timeout 150 unshare --mount --propagation unchanged sh -c '
    set -e
    if mountpoint -q /; then mount --make-rprivate /; fi
    mount --rbind / "$1"
    mount --make-rprivate "$1"
    exec chroot "$1" sh -c "
        umount -R /sys/fs/cgroup 2>/dev/null || true
        mount -t cgroup2 cgroup2 /sys/fs/cgroup
        mount -t tmpfs tmpfs /run
        exec systemd-nspawn --quiet --register=no --keep-unit --boot -D \"\$0\" --bind=\"\$1:/probe\" \
            --bind-ro=\"\$2:/opt/build-deps\" --console=pipe --link-journal=no \
            --uuid=\$(cat /proc/sys/kernel/random/uuid) --capability=CAP_IPC_LOCK,CAP_SYS_RESOURCE
    " "$2" "$3" "$4"' \
    sh "$mnt" "$root" "$tmp/out" "$deps" </dev/null >"$tmp/nspawn.log" 2>&1 || true
echo "container ran $(($(date +%s) - start)) s"
[ -f "$tmp/out/done" ] || { tail -30 "$tmp/nspawn.log" >&2; cat "$tmp/out/"* >&2 2>/dev/null; fail "the probe did not finish"; }

echo "--- deployment steps"
cat "$tmp/out/steps.log"
echo "--- kinctld's journal"
cat "$tmp/out/journal"
echo "--- probe"
cat "$tmp/out/probe"
echo "--- kinctld's limits, capabilities, seccomp"
cat "$tmp/out/diag"
get() { sed -n "s/^$1=//p" "$tmp/out/probe" | head -1; }

bad=$(grep '^step .* rc=[1-9]' "$tmp/out/probe" || true)
[ -z "$bad" ] || fail "deployment steps failed: $bad (above)"
[ "$(grep -c '^step .* rc=0$' "$tmp/out/probe")" = 10 ] || fail "not every deployment step ran"
grep -q 'robot lbr_iiwa (7 joints' "$tmp/out/journal" || fail "the service does not run the imported arm"
read -r kfile mfile <"$tmp/out/where"
[[ $kfile == /opt/kinctl/* && $mfile == /opt/kinctl/* ]] || fail "kinctl, kinctl_msgs not from the wheel: $kfile $mfile"
if grep -q '^KINCTL_LCM_JAVA:BOOL=ON' "$build/CMakeCache.txt"; then
    [ "$(cat "$tmp/out/jar")" = /usr/share/kinctl/java/kinctl_lcmtypes.jar ] ||
        fail "kinctl spy's jar lookup: $(cat "$tmp/out/jar")"
fi
"$python" - "$tmp/out/status.json" "$tmp/out/run.csv" "$(cat "$root/root/goal_q")" <<'EOF' ||
import csv, json, sys
st = json.load(open(sys.argv[1]))
rows = list(csv.DictReader(open(sys.argv[2])))
goal = [float(v) for v in sys.argv[3].split(",")]
print(f"kinctl status: {st.get('state')}, {len(st.get('q', []))} joints; kinctl log: {len(rows)} setpoints in 1 s")
assert len(st["q"]) == 7, st
assert 500 <= len(rows) <= 1500, len(rows)
# logged after the goal completed: the arm at rest at the goal
err = max(abs(float(rows[-1][f"q{i + 1}"]) - g) for i, g in enumerate(goal))
assert err < 1e-9, f"the arm is {err} rad from the goal"
print(f"kinctl goal joint: the logged arm within {err:.1e} rad of the goal")
EOF
    fail "kinctl status, goal or log (above)"
[ "$(get active)" = active ] || fail "kinctld.service was not active: $(get active)"
[ "$(get restarts)" = 0 ] || fail "kinctld.service restarted $(get restarts) times"
grep -q '^kinctld: warning' "$tmp/out/journal" && fail "kinctld warned (above)"

fifo=$(grep -c '^task .* policy=1 ' "$tmp/out/probe" || true)
[ "$fifo" = 1 ] || fail "$fifo threads are SCHED_FIFO, expected the cycle thread alone"
cycle=$(grep '^task .* policy=1 ' "$tmp/out/probe")
[[ $cycle == *" prio=$prio "* ]] || fail "the cycle thread's priority is not rt.priority $prio: $cycle"
if [ "$ncpu" -gt 1 ]; then
    [[ $cycle == *" cpus=$cpu" ]] || fail "the cycle thread is not pinned to rt.cpu $cpu: $cycle"
    # The I/O thread (lcm_io.c): allowed every CPU but the cycle's. The main
    # thread, which only waits for signals, is not pinned.
    python3 - "$tmp/out/probe" "$ncpu" "$cpu" <<'EOF' || fail "no SCHED_OTHER thread kept off the cycle's CPU $cpu (the I/O thread)"
import re, sys
ncpu, cpu = int(sys.argv[2]), int(sys.argv[3])
for line in open(sys.argv[1]):
    m = re.match(r"task \d+ policy=0 prio=0 cpus=(\S+)$", line)
    if not m:
        continue
    cpus = set()
    for part in m.group(1).split(","):
        a, _, b = part.partition("-")
        cpus.update(range(int(a), int(b or a) + 1))
    if cpus == set(range(ncpu)) - {cpu}:
        sys.exit(0)
sys.exit(1)
EOF
fi

vmlck=$(get VmLck) vmrss=$(get VmRSS)
[ "${vmlck:-0}" -gt 0 ] && [ "$vmlck" -ge "$vmrss" ] || fail "memory not locked: VmLck $vmlck kB, VmRSS $vmrss kB"

[ "$(get stop_result)" = success ] || fail "systemctl stop: Result=$(get stop_result)"
grep -q '^kinctld.service: Main process exited, code=exited, status=0/SUCCESS' "$tmp/out/journal" ||
    fail "kinctld did not exit 0 on SIGTERM"
grep -q 'kinctld: Terminated: stopping the arm' "$tmp/out/journal" || fail "no controlled stop (SIGTERM) in the journal"
grep -qE '^kinctld: [0-9]+ cycles, [0-9]+ overruns' "$tmp/out/journal" || fail "no exit summary in the journal"
grep -q 'kinctld: running (cycle SCHED_FIFO, pinned)' "$tmp/out/journal" || fail "kinctld did not say it runs SCHED_FIFO, pinned"
echo "PASS: kinctld.service under systemd: SCHED_FIFO $prio on CPU $cpu of $ncpu, VmLck $vmlck kB >= VmRSS $vmrss kB, stopped with exit 0"
