# SPDX-License-Identifier: BSD-3-Clause
"""A flood of goals: 10,000 joint goals in about a second. The setpoint
stream stays unbroken (a setpoint every cycle, consecutive counters, within
the limits) and every goal is answered exactly once, accepted or rejected."""
import collections
import time

from kinctl_testing import EVENTS, QN, assert_smooth, go_nominal, setpoints_since

N_GOALS = 10000


def test_flood_every_goal_answered_once(kinctld):
    d = kinctld()
    s0 = go_nominal(d)
    targets = [[q + (0.05 if i % 2 else -0.05) for q in QN] for i in range(2)]
    t0 = time.monotonic()
    for i in range(N_GOALS):
        d.bus.send_goal_joint(1000 + i, targets[i % 2])
    sent_in = time.monotonic() - t0
    answers = {"ACCEPTED", "REJECTED"}
    codes = {EVENTS[k] for k in answers}

    def answered():
        return sum(1 for s in d.bus.statuses if s.event in codes and s.event_goal_id >= 1000)
    # However long the machine takes, as long as answers keep coming.
    d.bus.wait_count(answered, N_GOALS, stall=10.0, what=f"answers to {N_GOALS} goals")

    with d.bus.lock:
        per_goal = collections.Counter(s.event_goal_id for s in d.bus.statuses
                                       if s.event in codes and s.event_goal_id >= 1000)
        accepted = sum(1 for s in d.bus.statuses if s.event == EVENTS["ACCEPTED"] and s.event_goal_id >= 1000)
    assert len(per_goal) == N_GOALS, f"{N_GOALS - len(per_goal)} goals never answered"
    assert max(per_goal.values()) == 1, "a goal was answered twice"
    assert accepted >= 1
    print(f"flood: {N_GOALS} goals sent in {sent_in:.2f} s, {accepted} accepted, {N_GOALS - accepted} rejected")
    # Nothing dropped on the way out either: from before the flood to after
    # its last answer the stream is continuous (consecutive cycles) and smooth.
    d.bus.wait_setpoints(200)
    sps = setpoints_since(d, s0.cycle)
    assert_smooth(sps)
    assert d.stop() == 0
