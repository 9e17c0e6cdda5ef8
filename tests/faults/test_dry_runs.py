# SPDX-License-Identifier: BSD-3-Clause
"""Goals' dry runs apart from the receive path (daemon/checker.h), against a
running kinctld: a goal whose dry run takes long (a line at a crawl, as
long as check_max_s allows) delays neither an ESTOP sent right behind it
nor a servo stream; a flood of goals is answered exactly once each, in the
order sent, and so are goals still waiting at shutdown; a dry run longer
than controller.check_budget_ms is rejected for it. In real-time mode (mlockall, SCHED_FIFO) where this machine allows
it. Behaviour is asserted (which setpoint took the command, the order of
answers, the staleness flag the cycle gave the controller), never a clock."""
import os
import time

from kinctl_testing import EVENTS, MODELS, QN, STATES, command_t, go_nominal, goal_joint_t, goal_line_t, servo_twist

ANSWERS = (EVENTS["ACCEPTED"], EVENTS["REJECTED"])
RT = os.geteuid() == 0 and not os.environ.get("KINCTLD_SANITIZED")


def config(tmp_path, budget_ms, extra=""):
    # libconfig resolves @include beside the including file
    (tmp_path / "puma560.cfg").write_text(open(os.path.join(MODELS, "puma560.cfg")).read())
    cfg = tmp_path / "checker.cfg"
    cfg.write_text('@include "puma560.cfg"\n'
                   f"controller = {{\n  check_max_s = 3600.0;\n  check_budget_ms = {budget_ms};\n{extra}}};\n")
    return str(cfg)


def crawl(goal_id, s0, replace=False, back=False):
    """A 0.3 m line at 0.1 mm/s: 3000 s of motion, whose dry run steps
    half a million ticks (hundreds of ms); back: the line the other way,
    from the end of one to where it started."""
    g = goal_line_t()
    g.goal_id = goal_id
    g.mode = goal_line_t.REPLACE if replace else goal_line_t.QUEUE
    p = list(s0.position)
    g.position = [p[0], p[1] + (0.0 if back else 0.3), p[2] - 0.05]
    g.orientation = list(s0.orientation)
    g.speed = 1e-4
    return g


def answers(d, ids):
    """(goal_id, status) of every answer to one of ids, in arrival order."""
    with d.bus.lock:
        return [(s.event_goal_id, s) for s in d.bus.statuses if s.event_goal_id in ids and s.event in ANSWERS]


def test_estop_behind_the_longest_dry_run_takes_effect_first(kinctld, tmp_path):
    d = kinctld("--config", config(tmp_path, 60000), rt=RT)
    s0 = go_nominal(d)
    seen = d.bus.last_setpoint().cycle
    d.bus.send("GOAL_LINE", crawl(2, s0))
    d.bus.send_command("ESTOP")
    estop = d.bus.wait(lambda: [s for s in d.bus.setpoints if s.cycle > seen and s.input_command == command_t.ESTOP],
                       10.0, "the setpoint that took the ESTOP")[0]
    assert estop.state == STATES["ESTOP"]
    answer = d.bus.wait_event(2, ("ACCEPTED", "REJECTED"), 60.0)
    # The ESTOP was taken before the dry run of the goal sent ahead of it
    # ended: the goal's answer comes from a later tick.
    assert estop.cycle < answer.cycle, (estop.cycle, answer.cycle)
    assert not answer.reason.startswith("check_budget"), answer.reason
    # The dry run did judge it (the controller, in ESTOP, refuses it).
    assert answer.event == EVENTS["REJECTED"] and answer.reason.startswith("state: "), answer.reason
    assert len(answers(d, {2})) == 1
    assert d.stop() == 0


def test_servo_stream_not_stale_while_a_long_goal_is_checked(kinctld, tmp_path):
    d = kinctld("--config", config(tmp_path, 60000, "  servo_timeout_ms = 300.0;\n"), rt=RT)
    s0 = go_nominal(d)
    g = servo_twist(7, [0.0, 0.0, 0.0, 0.0, 0.0, 0.0], 300000)
    d.bus.send("GOAL_SERVO", g)
    first = d.bus.wait(lambda: [s for s in d.bus.setpoints if s.input_goal_id == 7], 5.0, "the servo taken")[0]
    d.bus.send("GOAL_LINE", crawl(8, s0))
    # The stream goes on, every 10 ms, until the long goal is answered.
    n = 0
    while not answers(d, {8}):
        d.bus.send("GOAL_SERVO", g)
        n += 1
        time.sleep(0.01)
        assert n < 6000, "no answer to the long goal"
    answer = answers(d, {8})[0][1]
    assert not answer.reason.startswith("check_budget"), answer.reason
    # Sent while the dry run ran, and each taken at once: the stream
    # never went stale for the cycle, and the servo was never stopped for it.
    assert n >= 10, f"only {n} servo messages sent during the dry run"
    with d.bus.lock:
        during = [s for s in d.bus.setpoints if first.cycle <= s.cycle <= answer.cycle]
        aborted = [s for s in d.bus.statuses if s.event_goal_id == 7 and s.event == EVENTS["ABORTED"]]
    assert during and all(s.input_servo_stale == 0 for s in during), \
        [s.cycle for s in during if s.input_servo_stale][:5]
    assert not aborted, aborted[0].reason
    assert d.stop() == 0


def test_goal_flood_answered_once_each_in_order(kinctld, tmp_path):
    d = kinctld("--config", config(tmp_path, 60000), rt=RT)
    s0 = go_nominal(d)
    # A long dry run first, then a flood of joint moves behind it: some are
    # judged, some refused (the dry runs' queue, the controller's queue).
    ids = [100] + list(range(1000, 3000))
    d.bus.send("GOAL_LINE", crawl(100, s0))
    for i, gid in enumerate(ids[1:]):
        d.bus.send_goal_joint(gid, [q + (0.01 if i % 2 else -0.01) for q in QN])
        if i % 50 == 49:
            time.sleep(0.005)
    d.bus.wait(lambda: len(answers(d, set(ids))) >= len(ids), 60.0, "an answer to every goal")
    time.sleep(0.2)
    got = answers(d, set(ids))
    assert [g for g, _ in got] == ids, "answers not exactly once each, in the order sent"
    # the flood was refused in part, for the queues' room, and taken in part
    kinds = {s.event for _, s in got}
    assert kinds == set(ANSWERS), kinds
    assert d.stop() == 0


def test_dry_run_over_budget_is_rejected_for_it(kinctld, tmp_path):
    d = kinctld("--config", config(tmp_path, 20), rt=RT)
    s0 = go_nominal(d)
    d.bus.send("GOAL_LINE", crawl(3, s0))
    st = d.bus.wait_event(3, ("ACCEPTED", "REJECTED"), 30.0)
    assert st.event == EVENTS["REJECTED"]
    assert st.reason.startswith("check_budget: dry run stopped after "), st.reason
    assert "% of the motion" in st.reason and "controller.check_budget_ms = 20" in st.reason, st.reason
    assert st.code == -5  # KC_E_CAPACITY
    # The checker goes on: a short goal next is judged and runs.
    d.bus.send_goal_joint(4, [q + 0.05 for q in QN])
    st = d.bus.wait_event(4, ("COMPLETED", "REJECTED", "ABORTED"), 20.0)
    assert st.event == EVENTS["COMPLETED"], st.reason
    assert d.stop() == 0


def test_goals_waiting_at_shutdown_answered_once_in_order(kinctld, tmp_path):
    d = kinctld("--config", config(tmp_path, 60000), rt=RT)
    s0 = go_nominal(d)
    # Six long dry runs (each hundreds of ms: there and back, each from
    # where the one before ends), then joint moves behind them.
    crawls, joints = list(range(2, 8)), list(range(8, 13))
    for gid in crawls:
        d.bus.send("GOAL_LINE", crawl(gid, s0, back=gid % 2 == 1))
    for gid in joints:
        d.bus.send_goal_joint(gid, [q + 0.01 * gid for q in QN])
    d.bus.wait_stats(lambda s: s.msgs_in >= 1 + len(crawls) + len(joints), 5.0)
    # SIGTERM while the dry runs are under way and the joint moves wait
    # behind them: each goal is answered, once, in the order sent, before
    # the end; those never judged as refused for the shutdown.
    assert d.stop() == 0
    got = answers(d, set(crawls + joints))
    assert [g for g, _ in got] == crawls + joints, [g for g, _ in got]
    for _, s in got[len(crawls):]:
        assert s.event == EVENTS["REJECTED"] and s.reason.startswith("shutdown: "), s.reason
    assert got[-len(joints) - 1][1].reason.startswith("shutdown: ")  # the last long one too
