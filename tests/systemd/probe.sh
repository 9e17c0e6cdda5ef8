#!/bin/bash
# SPDX-License-Identifier: BSD-3-Clause
# Runs inside the booted root as kinctl-probe.service (test_unit.sh): the
# deployment path of docs/deploy.md with what the packages installed, then
# what /proc says of the running service, into OUT (a directory of the host):
#   1. the kinctl wheel (/usr/share/kinctl/python) into a fresh venv; its
#      dependencies (lcm, tqdm, yourdfpy) from DEPS, a read-only directory
#      named by a .pth file (no network here);
#   2. kinctl import-urdf of /root/arm.urdf into /etc/kinctl/arm.cfg, which
#      /etc/kinctl/kinctld.cfg includes; kinctld --config ... --check;
#   3. systemctl start kinctld; each thread's policy, priority and CPUs, the
#      memory locked;
#   4. the installed kinctl drives it: status, a joint goal --wait, a log;
#      kinctl spy's jar lookup;
#   5. systemctl stop kinctld; how it ended; the unit's journal.
# Each step's exit status goes to OUT/probe as "step NAME rc=N".
#   probe.sh OUT DEPS
out=$1 deps=$2
log() { echo "$1" >>"$out/probe"; }
step() {
    local name=$1
    shift
    echo "== $name: $*" >>"$out/steps.log"
    "$@" >>"$out/steps.log" 2>&1
    log "step $name rc=$?"
}

venv=/opt/kinctl
step venv python3 -m venv "$venv"
site=$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
echo "$deps" >"$site/build-deps.pth"
step wheel "$venv/bin/python" -m pip install -q --no-deps --no-index /usr/share/kinctl/python/kinctl-*-py3-none-any.whl
step import "$venv/bin/kinctl" import-urdf /root/arm.urdf -o /etc/kinctl/arm.cfg
step check kinctld --config /etc/kinctl/kinctld.cfg --check
step start systemctl start kinctld.service

pid=0
for _ in $(seq 150); do
    pid=$(systemctl show -p MainPID --value kinctld.service)
    if [ "$pid" -gt 0 ] && grep -qs ' 1$' <(for t in /proc/"$pid"/task/*; do
        sed 's/.*) //' "$t/stat" | awk '{print $39}'; done); then
        break
    fi
    sleep 0.1
done
sleep 1
log "active=$(systemctl is-active kinctld.service)"
log "restarts=$(systemctl show -p NRestarts --value kinctld.service)"
log "pid=$pid"
for t in /proc/"$pid"/task/*; do
    # stat fields 40 and 41 (rt_priority, policy) after the comm's ')'
    read -r prio policy < <(sed 's/.*) //' "$t/stat" | awk '{print $38, $39}')
    cpus=$(sed -n 's/^Cpus_allowed_list:[[:space:]]*//p' "$t/status")
    log "task $(basename "$t") policy=$policy prio=$prio cpus=$cpus"
done
log "VmLck=$(awk '/^VmLck:/ {print $2}' /proc/"$pid"/status)"
log "VmRSS=$(awk '/^VmRSS:/ {print $2}' /proc/"$pid"/status)"
# For the reader of a failure: limits, capabilities, seccomp mode
{ grep -E '^(Cap|Seccomp|NoNewPrivs)' /proc/"$pid"/status; grep -E 'locked|realtime' /proc/"$pid"/limits
  systemctl show -p LimitMEMLOCK -p LimitRTPRIO -p CapabilityBoundingSet -p AmbientCapabilities kinctld.service
  grep -E '^Cap(Bnd|Eff)' /proc/1/status; } >"$out/diag"

# The installed kinctl against the service, on the configuration's URL.
export LCM_DEFAULT_URL
LCM_DEFAULT_URL=$(sed -n 's/^ *lcm_url = "\(.*\)";/\1/p' /etc/kinctl/kinctld.cfg)
step status sh -c "$venv/bin/kinctl status --json >$out/status.json"
step goal "$venv/bin/kinctl" goal joint --q "$(cat /root/goal_q)" --wait
step log "$venv/bin/kinctl" log --csv "$out/run.csv" --duration 1
step jar sh -c "$venv/bin/python -c 'from kinctl import spy; print(spy.find_jar())' >$out/jar"
step where sh -c "$venv/bin/python -c 'import kinctl, kinctl_msgs; print(kinctl.__file__, kinctl_msgs.__file__)' >$out/where"

# systemd counts death by SIGTERM as success too: at debug level it logs how
# the main process ended ("code=exited, status=0/SUCCESS" for an exit 0).
systemctl log-level debug
systemctl stop kinctld.service
systemctl log-level info
log "stop_result=$(systemctl show -p Result --value kinctld.service)"
journalctl --sync
journalctl -u kinctld.service -o cat --no-pager >"$out/journal"
touch "$out/done"
