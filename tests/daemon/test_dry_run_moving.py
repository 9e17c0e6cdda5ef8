# SPDX-License-Identifier: BSD-3-Clause
"""kinctld judges a replacing goal from the controller's moving state
(kinctl/check.h kc_check_snapshot, daemon/checker.h): a joint goal sent
while the waist sweeps at full speed, to the waist angle it has reached
with the elbow opened, is taken over by a jerk-limited retarget that
carries the waist on past that angle while the elbow opens. A ball where
that retarget passes, and where neither the sweep (elbow closed) nor the
same goal from rest (the elbow opening in place) comes, refuses the
replacement, naming the zone: the arm keeps its sweep to its end. From
rest at the same joints the same goal is accepted and runs.

The ball's place is measured, not assumed: a first daemon without zones
runs the replacement, and the ball goes on its tool path where the elbow
has opened 0.5 rad (the waist then well past where it is to return)."""
import os

from kinctl_testing import EVENTS, END, MODELS, QN, finished

WAIST_FROM, WAIST_TO = -0.8, 0.8
SEND_AT = -0.1   # the waist angle (rad) past which the replacement is sent
OPEN = 0.9       # the elbow's opening (rad) the replacement asks for
BALL_AT = 0.5    # ... and where along it the ball sits
RADIUS = 0.05


def config(tmp_path, ball):
    (tmp_path / "puma560.cfg").write_text(open(os.path.join(MODELS, "puma560.cfg")).read())
    cfg = tmp_path / "zones.cfg"
    p = ball
    cfg.write_text('@include "puma560.cfg"\n'
                   "controller = {\n  zones = {\n    margin = 0.02;\n    list = (\n"
                   f'      {{ name = "ball"; shape = "sphere"; xyz = [{p[0]!r}, {p[1]!r}, {p[2]!r}]; '
                   f"radius = {RADIUS}; }}\n    );\n  }};\n}};\n")
    return str(cfg)


def sweep_start():
    return [WAIST_FROM] + QN[1:]


def sweep_then_replace(d):
    """The arm to the sweep's start, the sweep (2), and once its waist is
    past SEND_AT the replacement (3): the waist back to where it is, the
    elbow opened. Returns the replacement's target."""
    d.bus.send_goal_joint(1, sweep_start())
    assert d.bus.wait_event(1, END).event == EVENTS["COMPLETED"]
    d.bus.wait_idle()
    d.bus.send_goal_joint(2, [WAIST_TO] + QN[1:])
    s = d.bus.wait(lambda: next((s for s in d.bus.setpoints[-3:] if s.goal_id == 2 and s.q[0] >= SEND_AT), None),
                   10.0, "the sweep past SEND_AT")
    target = [s.q[0], QN[1], QN[2] + OPEN] + QN[3:]
    d.bus.send_goal_joint(3, target, replace=True)
    return target


def test_replacement_refused_for_its_moving_transition(kinctld, tmp_path):
    # Where the retarget goes, measured on a daemon without zones.
    d = kinctld()
    sweep_then_replace(d)
    accepted = d.bus.wait_event(3, ("ACCEPTED", "REJECTED"))
    assert accepted.event == EVENTS["ACCEPTED"] and accepted.reason == "", accepted.reason
    s_end = finished(d, 3)
    with d.bus.lock:
        path = [s for s in d.bus.setpoints if s.goal_id == 3]
    taken = path[0]
    at = next(s for s in path if s.q[2] >= QN[2] + BALL_AT)
    # a retarget from the sweep: the waist goes on well past where it
    # returns to while the elbow opens
    assert at.q[0] > s_end.q[0] + 0.2, (at.q[0], s_end.q[0])
    assert taken.qd[0] > 1.5, taken.qd[0]
    ball = list(at.position)
    assert d.stop() == 0

    d = kinctld("--config", config(tmp_path, ball))
    target = sweep_then_replace(d)
    st = d.bus.wait_event(3, ("ACCEPTED", "REJECTED"))
    assert st.event == EVENTS["REJECTED"], st.reason
    assert st.reason.startswith("zone: ") and 'zone "ball"' in st.reason, st.reason
    # the sweep goes on to its end, never preempted
    st = d.bus.wait_event(2, END + ("PREEMPTED",), 20.0)
    assert st.event == EVENTS["COMPLETED"], st.reason
    s = d.bus.wait_idle()
    assert abs(s.q[0] - WAIST_TO) < 1e-9, s.q

    # The same goal from rest where the sweep was when it was sent: the
    # elbow opens in place, clear of the ball.
    d.bus.send_goal_joint(4, [target[0]] + QN[1:])
    assert d.bus.wait_event(4, END).event == EVENTS["COMPLETED"]
    d.bus.wait_idle()
    d.bus.send_goal_joint(5, target, replace=True)
    s = finished(d, 5)
    assert max(abs(a - b) for a, b in zip(s.q, target)) < 1e-9, s.q
    assert d.stop() == 0
