# SPDX-License-Identifier: BSD-3-Clause
"""Forged LCM fragment headers against a running kinctld (docs/hostile-inputs.md).

Each datagram is the first fragment of a message that claims 256 MiB in two
fragments and never completes. LCM's own receive path would allocate the
claimed size for every one (and under mlockall fault it in); kinctld's
receiver drops them in the kernel (daemon/lcm_rx.h). With the daemon in
real-time mode (mlockall) where this machine allows it, a flood of them
leaves its resident memory flat, every goal sent during the flood is
answered exactly once, and an ESTOP sent during the flood is taken by the
cycle (the setpoints after it in ESTOP). Behaviour is asserted, never
a clock."""
import os
import re
import threading

from kinctl_testing import EVENTS, QN, STATES, command_t, flood_fragments, go_nominal

N_FORGED = 3000


def rss_kib(pid):
    with open(f"/proc/{pid}/status") as f:
        return int(re.search(r"VmRSS:\s+(\d+) kB", f.read()).group(1))


def locked_kib(pid):
    with open(f"/proc/{pid}/status") as f:
        return int(re.search(r"VmLck:\s+(\d+) kB", f.read()).group(1))


def test_fragment_flood_leaves_memory_flat_and_commands_heard(kinctld):
    rt = os.geteuid() == 0 and not os.environ.get("KINCTLD_SANITIZED")
    d = kinctld(rt=rt)
    go_nominal(d)
    pid = d.proc.pid
    if rt:
        assert locked_kib(pid) > 0, "kinctld --rt locked no memory"
    before = rss_kib(pid)
    done = threading.Event()
    sender = threading.Thread(target=flood_fragments, args=(d.url, d.prefix, N_FORGED, done))
    sender.start()
    # Goals during the flood: each answered exactly once.
    ids = list(range(500, 520))
    for i, gid in enumerate(ids):
        d.bus.send_goal_joint(gid, [q + (0.02 if i % 2 else -0.02) for q in QN])
    done.wait(timeout=60.0)
    sender.join()
    # A second wave of forged fragments, and an ESTOP in the middle of it.
    done2 = threading.Event()
    sender = threading.Thread(target=flood_fragments, args=(d.url, d.prefix, N_FORGED, done2))
    sender.start()
    seen = d.bus.last_setpoint().cycle
    d.bus.send_command("ESTOP")
    sender.join()
    # This process's own LCM receiver is flooded too and may lose a
    # datagram: the ESTOP is judged by the state every later setpoint
    # carries, not by the one setpoint that names it as its input.
    estop = d.bus.wait(lambda: [s for s in d.bus.setpoints if s.cycle > seen and s.state == STATES["ESTOP"]],
                       5.0, "a setpoint in ESTOP after the ESTOP was sent")
    with d.bus.lock:
        took = [s for s in d.bus.setpoints if s.cycle > seen and s.input_command == command_t.ESTOP]
    assert len(took) <= 1
    if took:
        assert took[0].cycle == estop[0].cycle, "the ESTOP's setpoint is the first in ESTOP"
    answers = {EVENTS["ACCEPTED"], EVENTS["REJECTED"]}
    d.bus.wait(lambda: all(any(s.event in answers for s in d.bus.events(g)) for g in ids), 10.0,
               "an answer to every goal sent during the flood")
    with d.bus.lock:
        for g in ids:
            n = sum(1 for s in d.bus.statuses if s.event_goal_id == g and s.event in answers)
            assert n == 1, f"goal {g} answered {n} times"
    after = rss_kib(pid)
    assert after - before < 1024, f"kinctld's resident memory grew by {after - before} KiB under the flood"
    # None of the forged datagrams was read: they were dropped before the daemon.
    st = d.bus.wait_stats(lambda s: True)
    assert st.msgs_invalid == 0
    assert d.stop() == 0
