#!/bin/bash
# Runs inside the booted root as kinctl-probe.service (test_unit.sh): waits
# for kinctld.service's cycle thread, writes what /proc says of each of its
# threads and of its memory, stops the unit, writes how it ended and the
# unit's journal, all into OUT (a directory of the host).
#   probe.sh OUT
out=$1
log() { echo "$1" >>"$out/probe"; }
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
systemctl stop kinctld.service
log "stop_result=$(systemctl show -p Result --value kinctld.service)"
# ExecMainCode: 1 is CLD_EXITED (an exit, not a signal)
log "stop_code=$(systemctl show -p ExecMainCode --value kinctld.service)"
log "stop_status=$(systemctl show -p ExecMainStatus --value kinctld.service)"
journalctl --sync
journalctl -u kinctld.service -o cat --no-pager >"$out/journal"
touch "$out/done"
