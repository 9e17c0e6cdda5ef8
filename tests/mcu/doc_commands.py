# SPDX-License-Identifier: BSD-3-Clause
"""mcu.docs: the commands of docs/microcontroller.md's code blocks and its
host command, run as they are written from the repository's top, the way
a reader pastes them, with their build directory and program moved into a
scratch directory:
  - the cross build's configuration (its full build is the top-level
    build's kinctl_mcu, the same configuration);
  - a program of one's own (mcu/example/kinematics.c as prog.c):
    configured with KINCTL_MCU_PROGRAMS, its image built and run on QEMU's
    mps2-an386, which must exit 0 with output;
  - the same program linked on this host against the double core.
Fails naming the command that failed. (A relative toolchain path in the
page's commands failed for every reader: CMake looks it up in the build
and source directories.)

    tests/mcu/doc_commands.py SOURCE_DIR BUILD_DIR
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile


def commands(text):
    """The shell commands of the page's fenced blocks (continuation lines
    joined), and its inline host command."""
    out = []
    for block in re.findall(r"```\n(.*?)```", text, re.S):
        out += [c.strip() for c in block.replace("\\\n", " ").split("\n") if c.strip()]
    out += re.findall(r"`(cc -std=c99 [^`]*)`", text)
    return out


def run(cmd, cwd, timeout=600):
    print(f"$ {cmd}", flush=True)
    p = subprocess.run(["bash", "-c", cmd], cwd=cwd, capture_output=True, text=True, timeout=timeout)
    if p.returncode != 0:
        print(p.stdout[-2000:], p.stderr[-2000:], sep="\n")
        sys.exit(f"mcu.docs: exit status {p.returncode}: {cmd}")
    return p.stdout


def main():
    root, build = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    text = open(os.path.join(root, "docs", "microcontroller.md"), encoding="utf-8").read()
    cmds = commands(text)
    tmp = tempfile.mkdtemp(prefix="kinctl-mcu-docs.")
    try:
        shutil.copy(os.path.join(root, "mcu", "example", "kinematics.c"), os.path.join(tmp, "prog.c"))

        def moved(cmd):
            cmd = cmd.replace("$PWD/prog.c", f"{tmp}/prog.c")
            return re.sub(r"(?<![\w/.-])build-mcu(?=[\s/]|$)", f"{tmp}/build-mcu", cmd)

        configure = [c for c in cmds if c.startswith("cmake -S mcu ")]
        plain = [c for c in configure if "KINCTL_MCU_PROGRAMS" not in c]
        own = [c for c in configure if "KINCTL_MCU_PROGRAMS=$PWD/prog.c" in c]
        board = [c for c in cmds if c.startswith("qemu-system-arm ") and "prog.elf" in c]
        host = [c for c in cmds if c.startswith("cc -std=c99 ") and "prog.c" in c]
        if not (plain and own and board and host and "cmake --build build-mcu" in cmds):
            sys.exit("mcu.docs: the page no longer has the commands this test runs "
                     "(cross build, a program of one's own, its run on the board, its host build)")
        run(moved(plain[0]), root)
        run(moved(own[0]), root)
        run(moved("cmake --build build-mcu") + " --target prog", root)
        out = run(moved(board[0]), root, timeout=120)
        if not out.strip():
            sys.exit("mcu.docs: the program printed nothing on the board")
        run(re.sub(r"\bbuild/", f"{build}/", host[0].replace("prog.c", f"{tmp}/prog.c")) + f" -o {tmp}/prog_host",
            root)
        host_out = run(f"{tmp}/prog_host", root)
        print(f"mcu.docs: {len(cmds)} commands on the page; the program printed {len(out.splitlines())} lines "
              f"on the board and {len(host_out.splitlines())} on this host")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
