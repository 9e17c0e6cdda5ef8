"""Fault injection against the real daemon: the fixtures and names of
tests/daemon/conftest.py (kinctld, multicast, Bus, EVENTS...) and the motion
helpers of tests/daemon/test_goals.py (go_nominal, assert_smooth...), shared
rather than copied."""
import importlib.util
import os
import sys

_DAEMON_TESTS = os.path.join(os.path.dirname(__file__), "..", "daemon")


def _load(name, filename):
    spec = importlib.util.spec_from_file_location(name, os.path.join(_DAEMON_TESTS, filename))
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


fixtures = _load("kinctld_fixtures", "conftest.py")
globals().update({name: getattr(fixtures, name) for name in fixtures.__all__})
kinctld = fixtures.kinctld
multicast = fixtures.multicast
# test_goals.py imports its names from `conftest`, which here is this module.
motion = _load("kinctld_motion", "test_goals.py")
