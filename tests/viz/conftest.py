# SPDX-License-Identifier: BSD-3-Clause
"""Fixtures for kinctl plot and kinctl view: one real run, recorded once.

`recorded` starts a kinctld of its own (kinctl.local.Kinctld, on a private
LCM URL), records it with `kinctl log` (CSV and events) and lcm-logger (an
LCM event log) at the same time, and drives it with the kinctl CLI through three goals
whose shape is known in advance:

    11  joint move in which joint 2 travels farthest (1.0 rad; others 0.1 or less)
    12  straight line of 0.15 m at 0.2 m/s (cruises at that speed)
    13  joint move in which joint 1 travels farthest
    14  joint move in which joint 6 travels farthest (1.3 rad) but joint 1 (1.2 rad, half
        joint 6's rate limits) leads: alone it would take 1 s, joint 6 0.72 s

Environment (tests/CMakeLists.txt, tests/viz/CMakeLists.txt): KINCTLD,
KINCTL_CALC, PYTHONPATH with this build's kinctl_msgs, tools/ and
tests/pylib, KINCTLD_TEST_SLOWDOWN.
"""
import os
import signal
import subprocess
import sys
import time

import pytest

from kinctl.local import unique_url
from kinctl_testing import QN, SLOW, multicast, run_kinctl, start_kinctld  # noqa: F401 (fixtures)

DOWN = [0.7071068, 0.0, 0.7071068, 0.0]  # puma560's tool orientation at QN
Q11 = [0.1, -0.2146, -3.0416, 0.05, 0.7854, 0.0]   # joint 2: -1.0 rad, the rest <= 0.1
Q13 = [0.9, -0.1146, -3.1416, 0.05, 0.8854, 0.1]   # from Q11, joint 1 +0.8 rad, the rest <= 0.1
Q14 = [-0.3, -0.1146, -3.1416, 0.05, 0.8854, 1.4]  # from Q13, joint 1 -1.2 rad, joint 6 +1.3 rad
LINE_SPEED = 0.2


def csv_of(v):
    return ",".join(repr(float(x)) for x in v)


def goal_columns(recorded, goal_id):
    """The logged columns from the first setpoint of goal_id on."""
    from kinctl import logcsv
    cols = logcsv.read(recorded["csv"])
    start = cols["goal_id"].index(goal_id)
    return {k: v[start:] for k, v in cols.items()}


def live_view_while_moving(url, *view_args):
    """`kinctl view` with a live window (under xvfb-run, 3 s at 10 frames/s)
    while the arm moves from QN to Q11; its (stdout, stderr) once it has
    exited 0 without a traceback, and the number of frames it says it drew."""
    import shutil
    if shutil.which("xvfb-run") is None:
        pytest.skip("xvfb-run is not installed (scripts/setup.sh installs Debian's xvfb)")
    r = run_kinctl(url, "goal", "joint", "--q", csv_of(QN), "--wait")
    assert r.returncode == 0, r.stderr
    env = {k: v for k, v in os.environ.items() if k not in ("LCM_DEFAULT_URL", "MPLBACKEND")}
    v = subprocess.Popen(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", sys.executable, "-m", "kinctl",
                          "--lcm-url", url, "view", "--duration", "3", "--fps", "10", *view_args],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        time.sleep(1.0 * SLOW)
        r = run_kinctl(url, "goal", "joint", "--q", csv_of(Q11), "--wait")
        assert r.returncode == 0, r.stderr
        out, err = v.communicate(timeout=120 * SLOW)
    finally:
        if v.poll() is None:
            v.kill()
            v.communicate()
    assert v.returncode == 0, err
    assert "Traceback" not in err, err
    drawn = int(out.split(" frames drawn")[0].rsplit(" ", 1)[1])
    return out, err, drawn


@pytest.fixture(scope="session")
def daemon(multicast):
    """A kinctld (puma560, 1 kHz, --no-rt) for the session, at QN."""
    d = start_kinctld(url=unique_url(subnet=79, port_base=28000))
    try:
        r = run_kinctl(d.url, "goal", "joint", "--q", csv_of(QN), "--wait")
        assert r.returncode == 0, r.stdout + r.stderr
        yield d
    finally:
        assert d.stop(signal.SIGTERM, 20.0) == 0, d.stderr


@pytest.fixture(scope="session")
def recorded(daemon, tmp_path_factory):
    """{"csv", "events", "lcmlog", "url", "line_from", "line_to"}: the three goals, logged both ways."""
    import lcm
    d = daemon
    out = tmp_path_factory.mktemp("run")
    paths = {"csv": str(out / "run.csv"), "events": str(out / "events.csv"), "lcmlog": str(out / "run.lcmlog"),
             "url": d.url}
    env = dict(os.environ)
    env.pop("LCM_DEFAULT_URL", None)
    logger = subprocess.Popen([os.path.join(lcm.LCM_BIN_DIR, "lcm-logger"), f"--lcm-url={d.url}", "--quiet",
                               paths["lcmlog"]], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    log = subprocess.Popen([sys.executable, "-m", "kinctl", "--lcm-url", d.url, "log", "--csv", paths["csv"],
                            "--events", paths["events"]], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           text=True, env=env)
    try:
        time.sleep(0.8 * SLOW)
        status = run_kinctl(d.url, "status", "--json")
        assert status.returncode == 0, status.stderr
        import json
        p = json.loads(status.stdout)["position"]
        for args in (["goal", "joint", "--q", csv_of(Q11), "--id", "11", "--wait"],
                     ["goal", "joint", "--q", csv_of(QN), "--wait", "--id", "20"]):
            r = run_kinctl(d.url, *args)
            assert r.returncode == 0, r.stdout + r.stderr
        line_to = [p[0], p[1] + 0.15, p[2]]
        r = run_kinctl(d.url, "goal", "line", "--to", csv_of(line_to + DOWN), "--speed", str(LINE_SPEED),
                       "--id", "12", "--wait")
        assert r.returncode == 0, r.stdout + r.stderr
        for args in (["goal", "joint", "--q", csv_of(Q11), "--wait", "--id", "21"],
                     ["goal", "joint", "--q", csv_of(Q13), "--id", "13", "--wait"],
                     ["goal", "joint", "--q", csv_of(Q14), "--id", "14", "--wait"]):
            r = run_kinctl(d.url, *args)
            assert r.returncode == 0, r.stdout + r.stderr
        time.sleep(0.3 * SLOW)
    finally:
        log.send_signal(signal.SIGTERM)
        lout, lerr = log.communicate(timeout=30 * SLOW)
        logger.send_signal(signal.SIGINT)
        logger.communicate(timeout=30 * SLOW)
    assert log.returncode == 0, lerr
    assert "none missing" in lout, lout
    paths["line_from"], paths["line_to"] = p, line_to
    return paths
