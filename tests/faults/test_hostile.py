# SPDX-License-Identifier: BSD-3-Clause
"""Hostile goal ids and timestamps through the real daemon (the catalogue in
docs/hostile-inputs.md): an id in flight is refused, an ended id may be used
again, the sender's utime is never trusted (a goal stamped a day ago or a
day ahead is judged on receipt like any other), and a replayed datagram of
an active goal is refused, not run twice."""
import time

from kinctl_testing import EVENTS, N, QN, finished, go_nominal, goal_joint_t

FAR = [1.0, 0.5, -2.5, 0.5, 0.5, 0.5]


def test_duplicate_and_replayed_ids(kinctld):
    d = kinctld()
    go_nominal(d)
    g = d.bus.send_goal_joint(70, FAR, vel_scale=0.3)
    d.bus.wait_event(70, ("ACCEPTED",))
    # The same datagram again (a replay) and a different goal under the same id.
    d.bus.send_raw("GOAL_JOINT", g.encode())
    d.bus.send_goal_joint(70, QN, replace=True)
    d.bus.wait(lambda: len([s for s in d.bus.events(70) if s.event == EVENTS["REJECTED"]]) == 2, 5.0,
               "two refusals")
    for s in d.bus.events(70):
        if s.event == EVENTS["REJECTED"]:
            assert s.reason.startswith("duplicate_id: ") and s.code < 0, s.reason
    d.bus.wait_event(70, ("COMPLETED",), timeout=20.0)  # the first goal 70 ran undisturbed to its end
    d.bus.wait_idle()
    # Ended: the id is free again.
    d.bus.send_goal_joint(70, QN)
    d.bus.wait(lambda: len([s for s in d.bus.events(70) if s.event == EVENTS["COMPLETED"]]) == 2, 20.0,
               "the second goal 70 completed")
    assert d.stop() == 0


def test_sender_utime_is_not_trusted(kinctld):
    d = kinctld()
    go_nominal(d)
    for gid, utime in ((80, int((time.time() - 86400) * 1e6)), (81, int((time.time() + 86400) * 1e6)), (82, -1)):
        g = goal_joint_t()
        g.goal_id, g.mode, g.n = gid, goal_joint_t.QUEUE, N
        g.q = (FAR if gid % 2 == 0 else QN) + [0.0] * (goal_joint_t.MAX_JOINTS - N)
        g.utime = utime
        d.bus.send_raw("GOAL_JOINT", g.encode())
    for gid in (80, 81, 82):
        finished(d, gid)
    assert d.stop() == 0
