# SPDX-License-Identifier: BSD-3-Clause
"""Fault injection against the real daemon: the fixtures of the suites'
shared module tests/pylib/kinctl_testing.py (kinctld, multicast), as
tests/daemon uses them; the tests import its names and motion helpers."""
from kinctl_testing import kinctld, multicast  # noqa: F401 (fixtures)
