# SPDX-License-Identifier: BSD-3-Clause
"""kinctl spy's jar, and --help of the data commands."""
import glob
import os
import subprocess

import pytest

from kinctl import spy

LCM_DIR = os.environ.get("KINCTL_LCM_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "lcmtypes"))
TYPES = sorted(os.path.basename(p)[:-4] for p in glob.glob(os.path.join(LCM_DIR, "*.lcm")))


@pytest.fixture
def jar():
    if not os.environ.get("KINCTL_JAR"):
        pytest.skip("KINCTL_JAR is not set: the build has no Java classes (KINCTL_LCM_JAVA=OFF)")
    return spy.find_jar()


def test_jar_holds_a_class_for_every_type(jar):
    assert len(TYPES) >= 9
    assert spy.jar_types(jar) == TYPES


def test_lcm_spy_finds_every_type_on_its_classpath(jar):
    """What lcm-spy's type database scans (lcm.util.ClassDiscoverer over
    lcm.jar and CLASSPATH), with the CLASSPATH that `kinctl spy` gives it."""
    argv, env = spy.command(None, jar)
    assert argv[0].endswith("lcm-spy") and os.access(argv[0], os.X_OK)
    assert env["CLASSPATH"].split(os.pathsep)[0] == jar
    import lcm
    lcm_jar = os.path.join(os.path.dirname(os.path.dirname(lcm.__file__)), "share", "java", "lcm.jar")
    r = subprocess.run(["java", "-cp", lcm_jar + os.pathsep + env["CLASSPATH"], "lcm.util.ClassDiscoverer"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    found = {line.split()[-1] for line in r.stdout.splitlines() if line.startswith(jar)}
    assert found == {f"kinctl.{t}" for t in TYPES}


def test_spy_print(jar, kinctl):
    r = kinctl(None, "spy", "--print")
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith(f"CLASSPATH={jar}") and "lcm-spy" in r.stdout


@pytest.mark.parametrize("cmd", ["record", "play", "replay", "spy", "import-urdf"])
def test_help_has_an_example(kinctl, cmd):
    r = kinctl(None, cmd, "--help")
    assert r.returncode == 0, r.stderr
    assert "example:\n  kinctl " + cmd in r.stdout, r.stdout


def test_replay_program_help():
    exe = os.environ.get("KINCTL_REPLAY")
    if not exe:
        pytest.skip("KINCTL_REPLAY is not set (run through ctest)")
    r = subprocess.run([exe, "--help"], capture_output=True, text=True)
    assert r.returncode == 0 and "example:\n  kinctl-replay " in r.stdout
    r = subprocess.run([exe], capture_output=True, text=True)
    assert r.returncode == 2 and "no LOG given" in r.stderr
    r = subprocess.run([exe, __file__], capture_output=True, text=True)
    assert r.returncode == 2 and "is not an LCM event log" in r.stderr
