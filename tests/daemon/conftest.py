# SPDX-License-Identifier: BSD-3-Clause
"""Fixtures for kinctld's integration tests: the real daemon over real LCM,
from the suites' shared module tests/pylib/kinctl_testing.py (kinctld,
multicast); the tests import its names (Bus, EVENTS, run_kinctld...)."""
from kinctl_testing import kinctld, multicast  # noqa: F401 (fixtures)
