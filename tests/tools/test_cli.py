# SPDX-License-Identifier: BSD-3-Clause
"""The kinctl CLI against a real kinctld over real LCM."""
import csv
import math
import subprocess
import sys
import time

import pytest

from conftest import status
from kinctl_testing import QN, SLOW, run_kinctl

QN_DEG = "0,45,-180,0,45,0"
DOWN = [0.7071068, 0.0, 0.7071068, 0.0]  # the tool's orientation at QN


def csv_of(v):
    return ",".join(repr(x) for x in v)


def close(a, b, tol):
    return len(a) == len(b) and all(abs(x - y) <= tol for x, y in zip(a, b))


def go_nominal(d):
    r = run_kinctl(d, "--deg", "goal", "joint", "--q", QN_DEG, "--wait")
    assert r.returncode == 0, r.stderr
    assert "COMPLETED" in r.stdout
    s = status(d)
    assert s["state"] == "IDLE"
    assert close(s["q"], [math.radians(v) for v in (0, 45, -180, 0, 45, 0)], 1e-9)
    return s


def test_every_goal_kind_completes_with_wait(daemon):
    d = daemon()
    s0 = go_nominal(d)
    p = s0["position"]
    line_to = [p[0], p[1] + 0.1, p[2] - 0.05]
    r = run_kinctl(d, "goal", "line", "--to", csv_of(line_to + DOWN), "--speed", "0.2", "--wait")
    assert r.returncode == 0 and "COMPLETED" in r.stdout, r.stdout + r.stderr
    assert close(status(d)["position"], line_to, 1e-5)

    arc_to = [p[0], p[1], p[2] + 0.05]
    r = run_kinctl(d, "goal", "arc", "--via", csv_of([p[0], p[1] + 0.05, p[2]]), "--to", csv_of(arc_to + DOWN),
                   "--wait")
    assert r.returncode == 0 and "COMPLETED" in r.stdout, r.stdout + r.stderr
    assert close(status(d)["position"], arc_to, 1e-5)

    pts = [[0.2, 0.9, -3.0, 0.1, 0.7, 0.1], [0.4, 0.7, -2.9, 0.0, 0.9, 0.2], [0.1, 0.6, -3.1, -0.1, 0.8, 0.0]]
    for method in ("blend", "spline", "quintic"):
        r = run_kinctl(d, "goal", "path", "--space", "joint", "--method", method,
                       "--points", ";".join(csv_of(q) for q in pts), "--wait")
        assert r.returncode == 0 and "COMPLETED" in r.stdout, method + r.stdout + r.stderr
        assert close(status(d)["q"], pts[-1], 1e-9)
        r = run_kinctl(d, "goal", "joint", "--q", csv_of(QN), "--wait")
        assert r.returncode == 0, r.stderr

    p = status(d)["position"]
    knots = [[p[0], p[1] + 0.05, p[2]], [p[0], p[1] + 0.05, p[2] + 0.05], [p[0], p[1], p[2] + 0.05]]
    r = run_kinctl(d, "goal", "path", "--space", "cartesian", "--method", "spline",
                   "--points", ";".join(csv_of(k + DOWN) for k in knots), "--wait")
    assert r.returncode == 0 and "COMPLETED" in r.stdout, r.stdout + r.stderr
    assert close(status(d)["position"], knots[-1], 1e-5)

    y0 = status(d)["position"][1]
    r = run_kinctl(d, "goal", "servo", "--twist", "0,0.05,0,0,0,0", "--rate", "100", "--duration", "0.5",
                   "--replace", "--wait")
    assert r.returncode == 0 and "stream ended" in r.stdout, r.stdout + r.stderr
    s = status(d)
    assert s["state"] == "IDLE" and all(v == 0.0 for v in s["qd"])
    assert s["position"][1] > y0 + 0.01


@pytest.mark.parametrize("args, token", [
    (["goal", "joint", "--q", "0,10,-3,0,0,0"], "joint_limit"),
    (["goal", "joint", "--q", "0,0.5,-3"], "joint_count"),
    (["goal", "line", "--to", "3,0,0,1,0,0,0"], "unreachable"),
])
def test_rejection_exits_1_with_the_reason(daemon, args, token):
    d = daemon()
    r = run_kinctl(d, *args, "--wait")
    assert r.returncode == 1, r.stdout + r.stderr
    assert "REJECTED" in r.stderr and token in r.stderr, r.stderr
    # Without --wait a rejection is still exit 1.
    r = run_kinctl(d, *args)
    assert r.returncode == 1 and token in r.stderr


def test_joint_limit_rejection_in_the_clis_units(daemon):
    """A limit rejection names the joint from 1 and gives the value and the
    limits in the CLI's units: degrees after --deg (puma560's joint 2 is
    limited to [-45, 225] deg, models/puma560.cfg), radians without."""
    d = daemon()
    r = run_kinctl(d, "--deg", "goal", "joint", "--q", "0,250,-90,0,0,0")
    assert r.returncode == 1, r.stdout + r.stderr
    assert "REJECTED: joint_limit: joint 2: 250 deg is outside its limits [-45, 225] deg" in r.stderr, r.stderr
    r = run_kinctl(d, "goal", "joint", "--q", "0,0.5,-3")
    assert "joint_count" in r.stderr, r.stderr
    r = run_kinctl(d, "goal", "joint", "--q", "0,0.5,-4,0,0,0")
    assert "REJECTED: joint_limit: joint 3: -4 rad is outside its limits [-3.92699, 0.785398] rad" in r.stderr, \
        r.stderr


def test_preempted_goal_exits_1_and_the_replacing_goal_0(daemon):
    d = daemon()
    go_nominal(d)
    env_cmd = [sys.executable, "-m", "kinctl", "--lcm-url", d.url]
    slow = subprocess.Popen(env_cmd + ["goal", "joint", "--q", "1.5,0.5,-2.5,1,0.5,1", "--speed", "0.3",
                                       "--id", "41", "--wait"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    deadline = time.monotonic() + 10 * SLOW
    while status(d)["active_goal_id"] != 41:
        assert time.monotonic() < deadline, "goal 41 never started"
        time.sleep(0.05)
    r = run_kinctl(d, "goal", "joint", "--q", csv_of(QN), "--replace", "--id", "42", "--wait")
    assert r.returncode == 0 and "goal 42 (joint) COMPLETED" in r.stdout, r.stdout + r.stderr
    out, err = slow.communicate(timeout=30 * SLOW)
    assert slow.returncode == 1 and "goal 41 (joint) PREEMPTED" in err, out + err
    assert close(status(d)["q"], QN, 1e-9)


def test_commands_change_the_state(daemon):
    d = daemon()
    go_nominal(d)
    target = "1.0,0.5,-2.5,0.5,0.5,0.5"
    r = run_kinctl(d, "goal", "joint", "--q", target, "--speed", "0.3")
    assert r.returncode == 0 and "ACCEPTED" in r.stdout, r.stderr
    assert status(d)["state"] == "MOVING"

    r = run_kinctl(d, "pause", "--wait")
    assert r.returncode == 0 and "PAUSED" in r.stdout, r.stdout + r.stderr
    s = status(d)
    assert s["state"] == "PAUSED" and all(v == 0.0 for v in s["qd"])
    held = s["q"]
    time.sleep(0.2)
    assert status(d)["q"] == held

    r = run_kinctl(d, "resume")
    assert r.returncode == 0, r.stderr
    assert status(d)["state"] == "MOVING"

    r = run_kinctl(d, "stop", "--wait")
    assert r.returncode == 0 and "IDLE" in r.stdout, r.stdout + r.stderr
    s = status(d)
    assert s["state"] == "IDLE" and s["queue_length"] == 0 and not close(s["q"], [1.0, 0.5, -2.5, 0.5, 0.5, 0.5],
                                                                          1e-3)

    r = run_kinctl(d, "goal", "joint", "--q", csv_of(QN), "--speed", "0.3")
    assert r.returncode == 0
    r = run_kinctl(d, "estop", "--wait")
    assert r.returncode == 0 and "ESTOP" in r.stdout, r.stdout + r.stderr
    assert status(d)["state"] == "ESTOP"
    # Latched: a goal is refused until reset.
    r = run_kinctl(d, "goal", "joint", "--q", csv_of(QN), "--wait")
    assert r.returncode == 1 and "REJECTED" in r.stderr, r.stdout + r.stderr
    r = run_kinctl(d, "reset")
    assert r.returncode == 0 and "IDLE" in r.stdout, r.stdout + r.stderr
    assert status(d)["state"] == "IDLE"
    r = run_kinctl(d, "goal", "joint", "--q", csv_of(QN), "--wait")
    assert r.returncode == 0, r.stderr


def test_status_human_readable(daemon):
    d = daemon()
    r = run_kinctl(d, "status")
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("state     IDLE") and "tool" in r.stdout
    r = run_kinctl(d, "--deg", "status")
    assert " deg" in r.stdout


def test_log_csv_has_a_row_per_cycle(daemon, tmp_path):
    d = daemon()
    path = tmp_path / "log.csv"
    events = tmp_path / "events.csv"
    log = subprocess.Popen([sys.executable, "-m", "kinctl", "--lcm-url", d.url, "log", "--csv", str(path),
                            "--duration", "4", "--events", str(events)],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(0.6)
    r = run_kinctl(d, "goal", "joint", "--q", csv_of(QN), "--id", "77", "--wait")
    assert r.returncode == 0, r.stderr
    out, err = log.communicate(timeout=30 * SLOW)
    assert log.returncode == 0, err
    assert "none missing" in out, out
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    n = 6
    assert rows[0] == (["utime", "cycle", "goal_id", "state"] + [f"q{i}" for i in range(1, n + 1)]
                       + [f"qd{i}" for i in range(1, n + 1)] + [f"qdd{i}" for i in range(1, n + 1)]
                       + ["x", "y", "z", "qw", "qx", "qy", "qz"])
    body = rows[1:]
    cycles = [int(r[1]) for r in body]
    assert all(b == a + 1 for a, b in zip(cycles, cycles[1:])), "cycles not consecutive"
    # About 4 s at 1 kHz (the daemon skips cycles it overran; none are lost here).
    assert len(body) > 2000, len(body)
    assert all(len(r) == len(rows[0]) for r in body)
    assert {r[3] for r in body} <= {"IDLE", "MOVING"}
    assert any(r[2] == "77" for r in body)
    assert f"{len(body)} setpoints received" in out
    with open(events, newline="") as f:
        ev = list(csv.DictReader(f))
    assert [e["event"] for e in ev if e["goal_id"] == "77"][:1] == ["ACCEPTED"]
    assert any(e["event"] == "COMPLETED" and e["goal_id"] == "77" for e in ev)


@pytest.mark.parametrize("args, message", [
    (["goal", "joint", "--q", "1,abc"], "'abc' is not a number"),
    (["goal", "joint"], "--q"),
    (["goal", "line", "--to", "1,2,3"], "needs 7 numbers"),
    (["goal", "line", "--to", "0.5,0,0.5,2,0,0,0"], "not a unit quaternion"),
    (["goal", "arc", "--via", "1,2", "--to", "0.5,0,0.5,1,0,0,0"], "needs 3 numbers"),
    (["goal", "path", "--points", "0,0,0;1,1"], "point 2 has 2 values"),
    (["goal", "path", "--points", "0,0;1,1", "--times", "1"], "times needs 2 numbers"),
    (["goal", "path", "--method", "bezier", "--points", "0"], "invalid choice"),
    (["goal", "servo", "--rate", "10"], "one of the arguments --pose --twist is required"),
    (["goal", "servo", "--twist", "1,2,3"], "needs 6 numbers"),
    (["goal", "joint", "--q", "0", "--speed", "1.5"], "must be a fraction"),
    (["goal", "joint", "--q", "0", "--id", "0"], "non-zero"),
    (["log"], "--csv"),
    (["frobnicate"], "invalid choice"),
    ([], "required"),
])
def test_bad_input_exits_2(args, message):
    # No daemon is needed: input is checked before anything is sent.
    r = run_kinctl(None, "--connect-timeout", "0.3", *args)
    assert r.returncode == 2, r.stdout + r.stderr
    assert message in r.stderr, r.stderr


def test_negative_values_need_no_equals_sign():
    # "--q -0.5,1" would be an unknown option to argparse; kinctl takes it as the value.
    r = run_kinctl(None, "--connect-timeout", "0.3", "goal", "joint", "--q", "-0.5,abc")
    assert r.returncode == 2 and "'abc' is not a number" in r.stderr


def test_no_daemon_is_a_clear_error():
    from kinctl.local import unique_url
    t0 = time.monotonic()
    r = subprocess.run([sys.executable, "-m", "kinctl", "--lcm-url", unique_url(), "--connect-timeout", "0.5",
                        "goal", "joint", "--q", "0,0,0,0,0,0", "--wait"], capture_output=True, text=True,
                       timeout=30)
    assert r.returncode == 1
    assert "is kinctld running" in r.stderr, r.stderr
    assert time.monotonic() - t0 < 10


@pytest.mark.parametrize("args", [[], ["goal"], ["goal", "joint"], ["goal", "line"], ["goal", "arc"],
                                  ["goal", "path"], ["goal", "servo"], ["stop"], ["estop"], ["pause"], ["resume"],
                                  ["reset"], ["status"], ["log"], ["plot"]])
def test_help_everywhere_with_an_example(args):
    r = run_kinctl(None, *args, "--help")
    assert r.returncode == 0, r.stderr
    assert "example" in r.stdout and "kinctl " in r.stdout.split("example", 1)[1], r.stdout


# A two-joint arm with a prismatic second joint (models/README.md's
# example): --deg converts only the revolute joint.
RP_ARM = """robot = {
  name = "rp";
  angles = "deg";
  dh = (
    { name = "j1"; type = "revolute"; a = 0.0; alpha = 90.0; d = 0.4; theta = 0.0;
      limits = { q = [-170.0, 170.0]; qd = 120.0; qdd = 500.0; qddd = 5000.0; }; },
    { name = "j2"; type = "prismatic"; a = 0.0; alpha = 0.0; d = 0.1; theta = 0.0;
      limits = { q = [0.0, 0.3]; qd = 0.5; qdd = 2.0; qddd = 20.0; }; }
  );
};
"""


def test_deg_converts_revolute_joints_only(daemon, tmp_path):
    cfg = tmp_path / "rp.cfg"
    cfg.write_text(RP_ARM)
    d = daemon("--config", str(cfg))
    r = run_kinctl(d, "--deg", "goal", "joint", "--q", "30,0.25", "--wait")
    assert r.returncode == 0, r.stderr
    s = status(d)
    assert s["prismatic"] == [False, True]
    assert close(s["q"], [math.radians(30.0), 0.25], 1e-9), s["q"]
    r = run_kinctl(d, "--deg", "status")
    assert r.returncode == 0, r.stderr
    q_line = next(line for line in r.stdout.splitlines() if line.startswith("q "))
    assert q_line.split()[1:] == ["30.0000", "0.2500", "deg;", "joint", "2", "in", "m"], q_line
    # A joint path too, and a limit rejection in the joint's own unit.
    r = run_kinctl(d, "--deg", "goal", "path", "--space", "joint", "--points", "0,0.1;-20,0.05", "--wait")
    assert r.returncode == 0, r.stderr
    assert close(status(d)["q"], [math.radians(-20.0), 0.05], 1e-9)
    r = run_kinctl(d, "--deg", "goal", "joint", "--q", "10,0.5")
    assert r.returncode != 0
    assert "joint 2: 0.5 m is outside its limits [0, 0.3] m" in r.stderr, r.stderr
