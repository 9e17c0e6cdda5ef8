# SPDX-License-Identifier: BSD-3-Clause
"""Fixtures for the kinctl CLI tests: a kinctld of the test's own (a
kinctl.local.Kinctld, the launcher the demo uses too) and a runner for
`kinctl`, from the suites' shared module tests/pylib/kinctl_testing.py.

    def test_x(daemon, kinctl):
        d = daemon()
        r = kinctl(d, "goal", "joint", "--q", "0,0,0,0,0,0", "--wait")
        assert r.returncode == 0

Environment (tests/CMakeLists.txt, tests/tools/CMakeLists.txt): KINCTLD,
KINCTL_CALC, KINCTL_REPLAY, PYTHONPATH with this build's kinctl_msgs, tools/
and tests/pylib, KINCTLD_TEST_SLOWDOWN in sanitized builds.
"""
import json
import signal

import pytest

from kinctl_testing import kinctld, multicast, run_kinctl, start_kinctld  # noqa: F401 (fixtures)


@pytest.fixture
def daemon(multicast):
    """Factory: daemon(*kinctld args) starts kinctld --no-rt on a fresh URL,
    waits for its first setpoint and returns the kinctl.local.Kinctld."""
    started = []

    def start(*args):
        d = start_kinctld(*args)
        started.append(d)
        return d
    yield start
    # Every daemon a test left running stops cleanly; one that exited on its
    # own (a sanitizer build's finding, say) fails the test with what it said.
    for d in started:
        assert d.stop(signal.SIGTERM, 20.0) == 0, d.stderr


@pytest.fixture
def kinctl():
    return run_kinctl


def status(d):
    r = run_kinctl(d, "status", "--json")
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)
