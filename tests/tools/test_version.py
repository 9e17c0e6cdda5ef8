# SPDX-License-Identifier: BSD-3-Clause
"""`--version` on every program prints the one version of the project (the
CMake project's, CMakeLists.txt), and `kinctl` without its generated message
classes says how to get them instead of ending in a traceback."""
import os
import re
import subprocess
import sys

import pytest

from kinctl import programs


def project_version():
    with open(os.path.join(programs.SOURCE_DIR, "CMakeLists.txt")) as f:
        return re.search(r"project\(kinctl VERSION (\d+\.\d+\.\d+)", f.read()).group(1)


@pytest.mark.parametrize("name", sorted(programs.PROGRAMS))
def test_c_programs_print_the_project_version(name):
    r = subprocess.run([programs.find(name), "--version"], capture_output=True, text=True, timeout=10)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split()[:2] == [name, project_version()], r.stdout


def test_kinctl_prints_the_project_version():
    r = subprocess.run([sys.executable, "-m", "kinctl", "--version"], capture_output=True, text=True, timeout=30)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == f"kinctl {project_version()}"


def test_missing_message_classes_are_named_not_a_traceback(tmp_path):
    # The package alone on the path, the generated kinctl_msgs nowhere.
    env = dict(os.environ, PYTHONPATH=os.path.join(programs.SOURCE_DIR, "tools"), PYTHONNOUSERSITE="1")
    code = ("import sys; sys.path = [p for p in sys.path if not p.endswith('lcmtypes/python')]; "
            "from kinctl import cli; sys.exit(cli.main(['status']))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=30, env=env,
                       cwd=tmp_path)
    assert r.returncode == 1
    assert "Traceback" not in r.stderr, r.stderr
    assert "kinctl_msgs is not importable" in r.stderr and "scripts/setup.sh" in r.stderr
