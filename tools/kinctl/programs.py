# SPDX-License-Identifier: BSD-3-Clause
"""Where kinctl's built programs are: kinctld, kinctl-calc, kinctl-replay.

    from kinctl import programs
    calc = programs.find("kinctl-calc")

Each is looked for in one order: its environment variable (ctest sets them
to the build under test), else this checkout's build/ (scripts/setup.sh
builds there), else PATH (an installed kinctl).
"""
import os
import shutil

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.path.dirname(os.path.dirname(HERE))  # tools/kinctl -> the checkout

# Program -> (its environment variable, its directory in the build tree).
PROGRAMS = {
    "kinctld": ("KINCTLD", "daemon"),
    "kinctl-calc": ("KINCTL_CALC", "tools"),
    "kinctl-replay": ("KINCTL_REPLAY", "tools"),
}


def find(name):
    """The path of the program `name` (a key of PROGRAMS): $VARIABLE, else
    build/<dir>/<name> of this checkout, else <name> on PATH, the first that
    is executable. FileNotFoundError when none is."""
    variable, build_dir = PROGRAMS[name]
    for cand in (os.environ.get(variable), os.path.join(SOURCE_DIR, "build", build_dir, name), shutil.which(name)):
        if cand and os.access(cand, os.X_OK):
            return cand
    raise FileNotFoundError(f"{name} not found: build it (scripts/setup.sh) or set {variable}")
