# SPDX-License-Identifier: BSD-3-Clause
"""kinctld with forbidden zones (controller.zones): goals that cross a zone
are rejected naming the zone and the link volume, ones that pass near it
run, a servo stream driven into a wall stops at the margin, and bad zone
configurations are refused at start-up.

The robot is models/puma560.cfg (its volumes carry names), at test_goals'
nominal pose QN: the tool at QN_POSITION, its z axis (the flange capsule,
0.06 m beyond the wrist centre plus 0.04 m radius) along world +x."""
import math
import os
import re
import time

from kinctl_testing import EVENTS, EVENT_NAMES, MODELS, SLOW, run_kinctld, servo_twist

QN = [0.0, 0.7854, -3.1416, 0.0, 0.7854, 0.0]
QN_POSITION = [0.5963008264104923, -0.15005, 0.6574746899005355]
END = ("COMPLETED", "REJECTED", "ABORTED", "FAULT")
MARGIN = 0.02


def config(tmp_path, zones, margin=MARGIN, extra=""):
    # libconfig resolves @include beside the including file
    (tmp_path / "puma560.cfg").write_text(open(os.path.join(MODELS, "puma560.cfg")).read())
    cfg = tmp_path / "zones.cfg"
    cfg.write_text(
        '@include "puma560.cfg"\n'
        f"controller = {{\n{extra}  zones = {{\n    margin = {margin};\n    list = (\n"
        + ",\n".join("      " + z for z in zones)
        + "\n    );\n  };\n};\n"
    )
    return str(cfg)


def on_sweep(angle, dz=0.0):
    """The point the tool passes when the waist turns by angle from QN."""
    r = math.hypot(QN_POSITION[0], QN_POSITION[1])
    a0 = math.atan2(QN_POSITION[1], QN_POSITION[0])
    return [r * math.cos(a0 + angle), r * math.sin(a0 + angle), QN_POSITION[2] + dz]


def ball(name, p, r=0.05):
    return f'{{ name = "{name}"; shape = "sphere"; xyz = [{p[0]!r}, {p[1]!r}, {p[2]!r}]; radius = {r}; }}'


def go(d, goal_id, q):
    d.bus.send_goal_joint(goal_id, q)
    return d.bus.wait_event(goal_id, END, 20.0)


def test_goal_through_a_zone_rejected_and_one_near_it_runs(kinctld, tmp_path):
    d = kinctld("--config", config(tmp_path, [ball("ball", on_sweep(0.6)), ball("lamp", on_sweep(0.6, dz=0.2))]))
    st = go(d, 1, QN)
    assert st.event == EVENTS["COMPLETED"], st.reason
    # The waist turns the wrist through the ball: refused before it moves.
    st = go(d, 2, [1.2] + QN[1:])
    assert st.event == EVENTS["REJECTED"], EVENT_NAMES[st.event]
    assert st.reason.startswith("zone: "), st.reason
    assert 'zone "ball" and link volume "' in st.reason, st.reason
    assert st.code < 0
    # Never moved: the last setpoint is still at QN.
    assert all(abs(a - b) < 1e-9 for a, b in zip(d.bus.last_setpoint().q, QN))
    assert d.stop() == 0


def test_goal_passing_near_a_zone_runs(kinctld, tmp_path):
    # The lamp hangs 0.2 m above the sweep: the flange passes 5 cm below it.
    d = kinctld("--config", config(tmp_path, [ball("lamp", on_sweep(0.6, dz=0.2))]))
    assert go(d, 1, QN).event == EVENTS["COMPLETED"]
    st = go(d, 2, [1.2] + QN[1:])
    assert st.event == EVENTS["COMPLETED"], f"{EVENT_NAMES[st.event]}: {st.reason}"
    assert not [s for s in d.bus.statuses if s.event == EVENTS["FAULT"]]
    assert d.stop() == 0


def test_servo_into_a_wall_stops_at_the_margin(kinctld, tmp_path):
    # A wall (half-space x > x_w) 10 cm beyond the flange's tip plus the
    # margin. The arm starts at QN (the move there from the default home
    # would itself pass within the margin: refused).
    x_w = QN_POSITION[0] + 0.10 + MARGIN + 0.10
    wall = f'{{ name = "wall"; shape = "halfspace"; point = [{x_w!r}, 0.0, 0.0]; normal = [-1.0, 0.0, 0.0]; }}'
    d = kinctld("--config", config(tmp_path, [wall], extra=f"  home = [{', '.join(map(str, QN))}];\n"))
    g = servo_twist(5, [0.1, 0.0, 0.0, 0.0, 0.0, 0.0], 100000)
    xs = []
    for _ in range(200):  # 2 s of a 0.1 m/s stream: it would go 20 cm
        d.bus.send("GOAL_SERVO", g)
        time.sleep(0.01)
        xs.append(d.bus.last_setpoint().position[0])
    assert not [s for s in d.bus.statuses if s.event == EVENTS["FAULT"]]
    # It moved toward the wall, then came to rest short of it: the flange's
    # tip (0.1 m beyond the wrist) keeps the margin.
    assert max(xs) > QN_POSITION[0] + 0.08
    assert max(xs) + 0.10 <= x_w - MARGIN + 1e-6
    assert max(xs) + 0.10 >= x_w - MARGIN - 0.005
    assert abs(xs[-1] - xs[-30]) < 1e-4  # at rest toward the wall for the last 0.3 s
    # The stream ends: the ordinary servo timeout, not a fault.
    st = d.bus.wait_event(5, END)
    assert st.event == EVENTS["ABORTED"] and st.reason.startswith("servo_timeout: "), st.reason
    assert d.stop() == 0


def test_bad_zone_configurations_refused(tmp_path):
    cfg = config(tmp_path, [ball("ball", on_sweep(0.6))], margin=0.001)
    r = run_kinctld("--config", cfg, "--check")
    assert r.returncode == 2
    assert "zones.cfg:4: controller.zones.margin = 0.001 m is not above" in r.stderr, r.stderr
    bad = tmp_path / "bad.cfg"
    bad.write_text('controller = {\n  zones = {\n    list = (\n      { shape = "cone"; }\n    );\n  };\n};\n')
    r = run_kinctld("--config", str(bad), "--check")
    assert r.returncode == 2
    assert "bad.cfg:4: zone 1: unknown shape \"cone\"" in r.stderr, r.stderr
    # A good one passes --check, which says what it will guard.
    cfg = config(tmp_path, [ball("ball", on_sweep(0.6)), DEMO_CELL[0]], margin=0.03)
    r = run_kinctld("--config", cfg, "--check")
    assert r.returncode == 0, r.stderr
    volumes = re.search(r"volumes = \((.*?)\n  \);", open(os.path.join(MODELS, "puma560.cfg")).read(), re.S).group(1)
    n_volumes = volumes.count("shape =")
    assert n_volumes == 5  # what the regex found: column, upper_arm, elbow, forearm, flange
    assert f"2 zones (margin 0.03 m) against {n_volumes} link volumes" in r.stdout, r.stdout
    assert "zones off" in run_kinctld("--check").stdout


# The demo's cell: a table top under the base, a wall behind the arm and a
# shelf to its left, clear of every motion of the scripted demo.
DEMO_CELL = [
    '{ name = "table"; shape = "halfspace"; point = [0.0, 0.0, 0.0]; normal = [0.0, 0.0, 1.0]; }',
    '{ name = "wall"; shape = "halfspace"; point = [-0.7, 0.0, 0.0]; normal = [1.0, 0.0, 0.0]; }',
    '{ name = "shelf"; shape = "box"; xyz = [0.2, 0.95, 0.4]; half = [0.3, 0.15, 0.4]; }',
]


def test_no_false_stop_on_the_demo(kinctld, tmp_path):
    """The scripted demo (tools/kinctl/demo.py's SEQUENCE, through the real
    CLI) runs exactly as without zones: every goal accepted, none faulted."""
    from kinctl.demo import SEQUENCE, run_cli

    d = kinctld("--config", config(tmp_path, DEMO_CELL))
    codes = []
    for gid, _, args, pause in SEQUENCE:
        if "--wait" in args and SLOW != 1.0:
            args = args + ["--timeout", f"{60 * SLOW:g}"]
        rc, out = run_cli(args, d.url, echo=False, timeout=120.0 * SLOW)
        codes.append((args[0:2], rc, out[-300:]))
        time.sleep(pause)
    assert all(rc == 0 for _, rc, _ in codes), codes
    ids = {gid for gid, _, _, _ in SEQUENCE if gid}
    with d.bus.lock:
        ev = [(s.event_goal_id, EVENT_NAMES[s.event], s.reason) for s in d.bus.statuses if s.event != 0]
    counts = {}
    for gid, kind, _ in ev:
        if gid in ids:
            counts[kind] = counts.get(kind, 0) + 1
    assert not [e for e in ev if e[1] in ("FAULT", "REJECTED")], ev
    assert (counts.get("COMPLETED"), counts.get("PREEMPTED"), counts.get("ABORTED")) == (5, 1, 1), counts
    assert d.stop() == 0
