# SPDX-License-Identifier: BSD-3-Clause
"""kinctld given a random mix of joint moves, lines and arcs over LCM, each
replacing the one before after a random 0-300 ms (so it often arrives
while the motion before is moving, accelerating or stopping), on the
puma560 and the panda, from rest at a pose where lines and arcs reach.
Every goal is answered once, ACCEPTED or REJECTED (the dry run may refuse
a line or arc out of reach or through a singularity); an accepted goal
ends once, preempted, aborted or completed; no FAULT; the last accepted
goal completes on its target. The whole stream, from the cycle before
the first goal to the rest after the last, every takeover included, has
no missing cycle and stays within qd_max and qdd_max with qdd changing
by at most qddd_max dt a cycle (Arm.check_limits), joint paths and their
stops included; each joint move, from
the setpoint it took over, integrates q and qd as a jerk-limited motion
does (Arm.check_stream: a Cartesian goal's qdd is the IK step's
difference quotient, which that check does not describe). A failure
names the goal, the goal it took over from, the cycle, the joint, its
values and the limits; each run prints a summary (with -s). Limits and
slack: tests/pylib/kinctl_arms.py. The same with every goal kind in the
mix (joint and Cartesian paths: blends, splines, quintics; servo twist
streams), on the Panda and the PUMA 560: a STOP of a joint path
superposed on a joint move's stop faulted (unit.ctrl_pathstop), a servo
stream sent right after a goal overtook it (answered twice), and the
PUMA's Cartesian goals stopped on their path went beyond their joints'
jerk limits (unit.ctrl_cartstop)."""
import math
import random
import time

import pytest

from kinctl import client as kc
from kinctl_arms import HOMES, Arm
from kinctl_testing import DT, END, EVENT_NAMES, EVENTS, fast_cart_limits, finished, random_offset, setpoints_since

GOALS = 20
FIRST = 100
# Each goal is sent this long (s) after the one before, drawn uniformly.
DELAY = (0.0, 0.3)
# Joint moves go near the arm's home (kinctl_arms.HOMES), SPREAD rad
# about it on every joint (inside either arm's limits), or one in three
# anywhere (Arm.random_target).
SPREAD = 0.5
CHANNELS = {"joint": "GOAL_JOINT", "line": "GOAL_LINE", "arc": "GOAL_ARC", "path": "GOAL_PATH",
            "cpath": "GOAL_PATH", "servo": "GOAL_SERVO"}
# The mixes: the three kinds of the first test, and every kind (joint and
# Cartesian paths and servo streams besides).
MIX = ("joint", "line", "arc")
EVERY = MIX + ("path", "cpath", "servo")
# Path methods (a clamped spline on kinctld's jerk-limited ramps, the
# others on their own law; Lagrange's in test_blend.py).
METHODS = ("blend", "spline", "quintic")
# A servo stream's messages: one every SERVO_PERIOD s, a twist of up to
# SERVO_SPEED m/s, stale after SERVO_TIMEOUT s (above kinctld's default
# cap, controller.servo_timeout_ms = 100, raised for it: this test's
# sender, stalled over 100 ms on a loaded machine, ended a stream it was
# still sending, whose next message then started it again).
SERVO_PERIOD = 0.01
SERVO_SPEED = 0.1
SERVO_TIMEOUT = 0.5
ANSWERS = (EVENTS["ACCEPTED"], EVENTS["REJECTED"])
ENDINGS = (EVENTS["PREEMPTED"], EVENTS["ABORTED"], EVENTS["COMPLETED"])


def near_home(rng, a):
    """Joints near a.name's home (SPREAD rad on every joint)."""
    return [h + rng.uniform(-SPREAD, SPREAD) for h in HOMES[a.name]]


def random_goal(rng, a, here, goal_id, kinds):
    """A goal of one of kinds (each as likely), replacing what runs:
    - a joint move near the home, or one in three anywhere;
    - a line or an arc 3 to 20 cm from here's position (the latest
      setpoint) in here's orientation, the arc's via point off the chord's
      middle by up to 0.3 of its length on each axis;
    - a joint path through two knots near the home, or a Cartesian path
      through two points 3 to 15 cm apart from here's position on, in
      here's orientation (blend, spline or quintic);
    - a servo stream of a twist of up to SERVO_SPEED m/s in a random
      direction (its messages sent by send_for);
    a Cartesian goal one in four at speed, accel and jerk drawn up to fast
    ones, else at the defaults. Returns the kind, the target (q, the pose,
    or None for a stream) and the message."""
    kind = rng.choice(kinds)
    if kind == "joint":
        q = a.random_target(rng) if rng.random() < 1 / 3 else near_home(rng, a)
        return kind, q, kc.make_goal_joint(q, goal_id=goal_id, replace=True)
    if kind == "path":
        points = [near_home(rng, a), near_home(rng, a)]
        return kind, points[-1], kc.make_goal_path(points, method=rng.choice(METHODS), goal_id=goal_id,
                                                   replace=True)
    if kind == "servo":
        twist = [x * rng.uniform(0.0, SERVO_SPEED) for x in random_offset(rng, [0.0] * 3, 1.0, 1.0)] + [0.0] * 3
        return kind, None, kc.make_servo_message(goal_id, twist=twist, replace=True, timeout_s=SERVO_TIMEOUT)
    if kind == "cpath":
        via = random_offset(rng, here.position, 0.03, 0.15)
        to = random_offset(rng, via, 0.03, 0.15) + list(here.orientation)
        limits = fast_cart_limits(rng) if rng.random() < 0.25 else {}
        return kind, to, kc.make_goal_path([via + list(here.orientation), to], space="cartesian",
                                           method=rng.choice(METHODS), goal_id=goal_id, replace=True,
                                           **limits)
    to = random_offset(rng, here.position, 0.03, 0.2) + list(here.orientation)
    length = math.dist(here.position, to[:3])
    limits = fast_cart_limits(rng) if rng.random() < 0.25 else {}
    if kind == "arc":
        via = [0.5 * (p + t) + rng.uniform(-0.3, 0.3) * length for p, t in zip(here.position, to)]
        return kind, to, kc.make_goal_arc(via, to, goal_id=goal_id, replace=True, **limits)
    return kind, to, kc.make_goal_line(to, goal_id=goal_id, replace=True, slerp=True, **limits)


def send_for(d, kind, msg, seconds):
    """Sends msg, and for a servo stream sends it again every SERVO_PERIOD
    for seconds (the stream then goes on until the next goal replaces
    it); otherwise waits seconds."""
    end = time.monotonic() + seconds
    d.bus.send(CHANNELS[kind], msg)
    while kind == "servo" and time.monotonic() + SERVO_PERIOD < end:
        time.sleep(SERVO_PERIOD)
        d.bus.send(CHANNELS[kind], msg)
    time.sleep(max(0.0, end - time.monotonic()))


def goal_name(gid, goals):
    return f"goal {gid} ({goals[gid][0]})" if gid in goals else f"goal {gid}"


def explain(a, stream, where, goals):
    """The setpoint that failed a check of kinctl_arms (its `where`: cycle,
    goal id, joint index): its goal, the goal before it, and the joint's
    values beside the arm's limits."""
    cycle, gid, j = where
    i = next(k for k, s in enumerate(stream) if s.cycle == cycle)
    p, b = stream[i - 1], stream[i]
    took = i
    while took > 0 and stream[took - 1].goal_id == gid:
        took -= 1
    if took == i:
        after = f"taking over from {goal_name(p.goal_id, goals)}"
    elif took > 0:
        after = f"{i - took} cycles after taking over from {goal_name(stream[took - 1].goal_id, goals)}"
    else:
        after = f"{i} cycles into the stream"
    qd, qdd, J = a.qd[j], a.qdd[j], a.qddd[j]
    jerk = (b.qdd[j] - p.qdd[j]) / DT
    dqd = b.qd[j] - p.qd[j] - p.qdd[j] * DT
    dq = b.q[j] - p.q[j] - p.qd[j] * DT - p.qdd[j] * DT ** 2 / 2
    return (f"{goal_name(gid, goals)}, {after}, cycle {cycle}, joint q{j + 1}: "
            f"jerk {jerk:.9g} rad/s^3 = {abs(jerk) / J:.7f} x qddd_max {J:g}; "
            f"qdd {b.qdd[j]:.9g} rad/s^2 (qdd_max {qdd:g}); qd {b.qd[j]:.9g} rad/s (qd_max {qd:g}); "
            f"qd off the jerk-limited step by {dqd:.3g} rad/s (bound {J * DT ** 2 / 2:.3g}), "
            f"q by {dq:.3g} rad (bound {J * DT ** 3 / 6:.3g})")


def checked(check, a, stream, goals, **kw):
    """check(stream, **kw), a method of Arm: None, or where it failed (its
    assertion's cycle, goal id and joint index) and that explained."""
    try:
        check(stream, **kw)
    except AssertionError as e:
        where = e.args[0] if e.args else None
        if isinstance(where, tuple) and len(where) == 3:
            return where, f"Arm.{check.__name__}: {explain(a, stream, where, goals)}"
        return where, f"Arm.{check.__name__}: {e}"
    return None


def worst_jerk(a, stream):
    """The largest |change of qdd| / (qddd_max dt) over the stream, with
    the goal, cycle and joint where it is."""
    worst = (0.0, 0, 0, 0)
    for p, b in zip(stream, stream[1:]):
        for j in range(a.n):
            r = abs(b.qdd[j] - p.qdd[j]) / (a.qddd[j] * DT)
            if r > worst[0]:
                worst = (r, b.goal_id, b.cycle, j)
    return worst


def check_events(goals, answers, statuses):
    """Each goal answered once; each accepted one ended once, each rejected
    one never; no FAULT. Returns what is wrong (messages)."""
    problems = []
    for g in goals:
        evs = [s for s in statuses if s.event_goal_id == g]
        names = [EVENT_NAMES[s.event] for s in evs]
        ends = [s for s in evs if s.event in ENDINGS]
        if len(answers[g]) != 1:
            problems.append(f"{goal_name(g, goals)} answered {len(answers[g])} times: {names}")
        elif answers[g][0].event == EVENTS["ACCEPTED"] and len(ends) != 1:
            problems.append(f"{goal_name(g, goals)}, accepted, ended {len(ends)} times: {names}")
        elif answers[g][0].event == EVENTS["REJECTED"] and ends:
            problems.append(f"{goal_name(g, goals)}, rejected, has an end: {names}")
    return problems + [f"FAULT about {goal_name(s.event_goal_id, goals)} at cycle {s.cycle}: {s.reason}"
                       for s in statuses if s.event == EVENTS["FAULT"]]


def check_setpoints(a, stream, goals):
    """No cycle missing; every setpoint within the limits; each joint move,
    from the setpoint before its first, integrating as a jerk-limited
    motion. Returns what is wrong (messages: the first failure of each
    check)."""
    for p, b in zip(stream, stream[1:]):
        if b.cycle != p.cycle + 1:
            return [f"setpoints of cycles {p.cycle + 1} to {b.cycle - 1} missing "
                    f"({goal_name(p.goal_id, goals)} to {goal_name(b.goal_id, goals)})"]
    failed = [checked(a.check_limits, a, stream, goals)]
    for i in range(1, len(stream)):
        g = stream[i].goal_id
        if g != stream[i - 1].goal_id and goals.get(g, ("",))[0] == "joint":
            k = next((k for k in range(i, len(stream)) if stream[k].goal_id != g), len(stream))
            failed.append(checked(a.check_stream, a, stream[i - 1:k], goals))
    # A setpoint over a limit fails both checks: named once.
    problems, seen = [], set()
    for where, text in filter(None, failed):
        if where not in seen:
            seen.add(where)
            problems.append(text)
    return problems


def replace_at_random(d, a, rng, label, kinds=MIX):
    """Sends GOALS random goals of kinds, each replacing the one before
    after a random delay (the last no servo stream: it would never end),
    waits for the last accepted one to end (completed, or a servo stream
    gone quiet when the goals after it were refused), prints a summary of
    the run and returns what went wrong (messages)."""
    t0 = time.monotonic()
    start = d.bus.last_setpoint().cycle
    goals = {}
    last_kinds = tuple(k for k in kinds if k != "servo")
    for gid in range(FIRST, FIRST + GOALS):
        last = gid == FIRST + GOALS - 1
        kind, target, msg = random_goal(rng, a, d.bus.last_setpoint(), gid, last_kinds if last else kinds)
        send_for(d, kind, msg, 0.0 if last else rng.uniform(*DELAY))
        goals[gid] = (kind, target)
    try:
        d.bus.wait(lambda: all(any(s.event in ANSWERS for s in d.bus.events(g)) for g in goals), 10.0)
    except AssertionError:
        pass  # named below
    answers = {g: [s for s in d.bus.events(g) if s.event in ANSWERS] for g in goals}
    accepted = [g for g in goals if answers[g] and answers[g][0].event == EVENTS["ACCEPTED"]]
    problems = []
    # Enough taken to mean something: a quarter, some of them Cartesian.
    if len(accepted) < GOALS // 4 or all(goals[g][0] == "joint" for g in accepted):
        problems.append(f"only {len(accepted)} goals accepted: {[goals[g][0] for g in accepted]}")
    last = max(accepted, default=None)
    completed = stale = False
    if last is not None:
        st = d.bus.wait_event(last, END + ("PREEMPTED",), 20.0)
        completed = st.event == EVENTS["COMPLETED"]
        # A servo stream the goals after it did not replace (refused) ends
        # when it goes quiet, at rest.
        stale = goals[last][0] == "servo" and st.event == EVENTS["ABORTED"] and st.reason.startswith("servo_timeout")
        if st.event not in (EVENTS["COMPLETED"], EVENTS["FAULT"]) and not stale:  # a FAULT: check_events names it
            problems.append(f"the last accepted, {goal_name(last, goals)}, ended {EVENT_NAMES[st.event]} at "
                            f"cycle {st.cycle}: {st.reason}")
    # The end: the first setpoint at rest after the last goal (else the latest).
    end = d.bus.wait_idle() if completed or stale else d.bus.wait_setpoints(10)[-1]
    stream = [s for s in setpoints_since(d, start) if s.cycle <= end.cycle]
    with d.bus.lock:
        statuses = [s for s in d.bus.statuses if s.event != EVENTS["NONE"]]

    problems += check_events(goals, answers, statuses)
    if completed:
        kind, target = goals[last]
        if kind in ("joint", "path"):
            off = max(abs(x - y) for x, y in zip(end.q, target))
            if off > 1e-9:
                problems.append(f"{goal_name(last, goals)} ended {off:.3g} rad off its target")
        else:
            off = math.sqrt(sum((x - y) ** 2 for x, y in zip(end.position, target[:3])))
            if off > 1e-6:
                problems.append(f"{goal_name(last, goals)} ended {off:.3g} m off its target")
    problems += check_setpoints(a, stream, goals)

    kinds = [goals[g][0] for g in accepted]
    ends = {e: sum(s.event == EVENTS[e] for s in statuses if s.event_goal_id in goals)
            for e in ("PREEMPTED", "ABORTED")}
    # An ACCEPTED with a reason: taken with the motion it replaces stopping first.
    stop_first = sum(bool(answers[g][0].reason) for g in accepted)
    r, wg, wc, wj = worst_jerk(a, stream)
    taken = ", ".join(f"{kinds.count(k)} {k}" for k in EVERY if k in kinds)
    print(f"\n{label}: {len(accepted)} of {GOALS} goals accepted ({taken}; {stop_first} stopping first), "
          f"{ends['PREEMPTED']} preempted, {ends['ABORTED']} aborted; {len(stream)} cycles; worst jerk "
          f"{r:.7f} x qddd_max ({goal_name(wg, goals)}, cycle {wc}, q{wj + 1}); {time.monotonic() - t0:.1f} s")
    for g in goals:
        if answers[g] and answers[g][0].event == EVENTS["REJECTED"]:
            print(f"  rejected {goal_name(g, goals)}: {answers[g][0].reason}")
        elif answers[g] and answers[g][0].reason:
            before = max((p for p in accepted if p < g), default=None)
            print(f"  stopping first: {goal_name(g, goals)} replacing "
                  f"{goal_name(before, goals) if before else 'the move home'}: {answers[g][0].reason}")
    for m in problems:
        print(f"  FAILED: {m}")
    return problems


# The three kinds of the first test (MIX) on each arm, and every kind
# (EVERY): the Panda's seeds 20-29 and the PUMA 560's seeds 20-39 all
# passed in probes; PUMA seeds 22 and 25 are two that went 2.0 and 1.7
# times beyond qddd_max while a Cartesian path stopped (superposed on a
# joint move's stop, then replaced by a goal that stops it first).
@pytest.mark.parametrize("arm,seed,kinds", [("puma560", 6, MIX), ("panda", 7, MIX), ("panda", 20, EVERY),
                                            ("panda", 34, EVERY), ("puma560", 22, EVERY), ("puma560", 25, EVERY)])
def test_random_mix_replaced_at_random_moments(kinctld, arm, seed, kinds, tmp_path):
    a = Arm(arm)
    cfg = tmp_path / "servo.cfg"
    cfg.write_text(f"controller = {{ servo_timeout_ms = {SERVO_TIMEOUT * 1000.0}; }};\n")
    d = kinctld("--model", arm, "--config", str(cfg))
    # kinctld starts with every joint at 0: the puma560 stretched out.
    d.bus.send_goal_joint(FIRST - 1, HOMES[arm])
    finished(d, FIRST - 1)
    label = f"{arm} seed {seed}" + (", every kind" if kinds == EVERY else "")
    problems = replace_at_random(d, a, random.Random(seed), label, kinds)
    assert not problems, "\n".join(problems)
    assert d.stop() == 0
