# SPDX-License-Identifier: BSD-3-Clause
"""`kinctl spy`: lcm-spy with kinctl's message classes on its CLASSPATH.

lcm-spy decodes a channel field by field when a class of the message's
fingerprint is on its CLASSPATH: the build packs the lcm-gen --java classes
into kinctl_lcmtypes.jar (lcmtypes/CMakeLists.txt).
"""
import os
import shutil
import subprocess
import sys
import zipfile

from kinctl.programs import SOURCE_DIR

JAR_NAME = "kinctl_lcmtypes.jar"


def find_jar():
    """$KINCTL_JAR, else build/lcmtypes/kinctl_lcmtypes.jar of this checkout,
    else the installed share/kinctl/java/kinctl_lcmtypes.jar (cmake/install.cmake)
    below this Python's prefix, the prefix of the kinctld on PATH, /usr/local
    or /usr."""
    cands = [os.environ.get("KINCTL_JAR"), os.path.join(SOURCE_DIR, "build", "lcmtypes", JAR_NAME)]
    prefixes = [sys.prefix]
    daemon = shutil.which("kinctld")
    if daemon:
        prefixes.append(os.path.dirname(os.path.dirname(os.path.realpath(daemon))))
    for prefix in prefixes + ["/usr/local", "/usr"]:
        cands.append(os.path.join(prefix, "share", "kinctl", "java", JAR_NAME))
    for cand in cands:
        if cand and os.path.isfile(cand):
            return cand
    raise FileNotFoundError(f"{JAR_NAME} not found: build the tree (scripts/setup.sh), install kinctl (its .deb "
                            "or cmake --install) or set KINCTL_JAR")


def jar_types(jar):
    """The kinctl message classes in a jar: type names ('setpoint_t', ...)."""
    with zipfile.ZipFile(jar) as z:
        return sorted(n[len("kinctl/"):-len(".class")] for n in z.namelist()
                      if n.startswith("kinctl/") and n.endswith(".class") and "$" not in n)


def find_spy():
    """lcm-spy of the lcm wheel (beside this Python), else on PATH."""
    here = os.path.join(os.path.dirname(sys.executable), "lcm-spy")
    for cand in (here, shutil.which("lcm-spy")):
        if cand and os.access(cand, os.X_OK):
            return cand
    raise FileNotFoundError("lcm-spy not found: install the lcm wheel (pip install -r tools/requirements.txt)")


def command(url=None, jar=None):
    """(argv, env) that start lcm-spy on url with the jar on its CLASSPATH."""
    if jar is not None and not os.path.isfile(jar):
        raise ValueError(f"--jar {jar}: no such file")
    jar = jar or find_jar()
    env = dict(os.environ)
    env["CLASSPATH"] = jar + (os.pathsep + env["CLASSPATH"] if env.get("CLASSPATH") else "")
    argv = [find_spy()]
    if url:
        argv.append("--lcm-url=" + url)
    return argv, env


def run(url=None, jar=None):
    argv, env = command(url, jar)
    return subprocess.call(argv, env=env)
