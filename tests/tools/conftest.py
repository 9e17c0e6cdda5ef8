"""Fixtures for the kinctl CLI tests: a kinctld of the test's own (through
kinctl.local, the helpers the demo uses too) and a runner for `kinctl`.

    def test_x(daemon, kinctl):
        d = daemon()
        r = kinctl(d, "goal", "joint", "--q", "0,0,0,0,0,0", "--wait")
        assert r.returncode == 0

Environment (tests/tools/CMakeLists.txt): KINCTLD, PYTHONPATH with this
build's kinctl_msgs and tools/, KINCTLD_TEST_SLOWDOWN in sanitized builds.
"""
import json
import os
import signal
import subprocess
import sys

import pytest

from kinctl.local import MULTICAST_HELP, Kinctld, ensure_multicast

KINCTLD = os.environ.get("KINCTLD", "")
SLOW = float(os.environ.get("KINCTLD_TEST_SLOWDOWN", "1"))


@pytest.fixture(scope="session")
def multicast():
    if not ensure_multicast():
        pytest.skip(MULTICAST_HELP)


@pytest.fixture
def daemon(multicast):
    """Factory: daemon(*kinctld args) starts kinctld --no-rt on a fresh URL,
    waits for its first setpoint and returns the kinctl.local.Kinctld."""
    if not KINCTLD:
        pytest.skip("KINCTLD is not set (run through ctest)")
    started = []

    def start(*args):
        d = Kinctld(*args, binary=KINCTLD, slowdown=SLOW)
        started.append(d)
        d.wait_ready(10.0)
        return d
    yield start
    # Every daemon a test left running stops cleanly; one that exited on its
    # own (a sanitizer build's finding, say) fails the test with what it said.
    for d in started:
        assert d.stop(signal.SIGTERM, 20.0) == 0, d.stderr


def run_kinctl(d, *args, timeout=60.0):
    """`kinctl --lcm-url <d's> args...` (d None: no URL); a CompletedProcess."""
    url = ["--lcm-url", d.url] if d is not None else []
    env = dict(os.environ)
    env.pop("LCM_DEFAULT_URL", None)
    return subprocess.run([sys.executable, "-m", "kinctl"] + url + list(args), capture_output=True, text=True,
                          timeout=timeout * SLOW, env=env)


@pytest.fixture
def kinctl():
    return run_kinctl


def status(d):
    r = run_kinctl(d, "status", "--json")
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)
