# SPDX-License-Identifier: BSD-3-Clause
"""kinctl: the client of kinctld (command line `kinctl`, Python API `kinctl.Client`).

The modules (no import circle among them; none but __main__ imports cli:
tests/tools/test_imports.py):

- the command line: cli (the entry point: the top-level parser and the
  dispatch), built from the command modules, each of which registers its own
  subcommands: goalcmds (goal), livecmds (stop ... reset, status, log),
  plotcmd (plot), viewcmd (view), datacmds (record, play, replay, spy,
  import-urdf), cancmds (drivesim, candecode); what they share: argtypes
  (argument types and messages, a leaf) and connection (the connection
  options and the client a live command opens);
- talking to kinctld: client, msgs (the generated messages), eventlog,
  logcsv, runlog (logs), replay (kinctl-replay);
- drawing: plot, view (the arm), projection, shapes, zonedraw, kinematics
  (the core's forward kinematics through kinctl-calc), progress;
- CAN: canraw, dbc, candecode, drive402 (the drive simulator);
- the machine: programs (where the built programs are), local (a kinctld of
  one's own: the launcher of the demo and the tests), demo, urdf.
"""


def _version():
    # tools/pyproject.toml holds it (checked against the CMake project's by
    # cmake/wheel.cmake); installed, editable or as the wheel, it is here.
    from importlib import metadata
    try:
        return metadata.version("kinctl")
    except metadata.PackageNotFoundError:
        return "unknown (not installed)"


__version__ = _version()


def __getattr__(name):
    # Lazy, so that `kinctl --help` works before the messages are built.
    if name in ("Client", "DaemonNotFound"):
        from kinctl import client
        return getattr(client, name)
    raise AttributeError(name)
