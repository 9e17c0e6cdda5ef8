# SPDX-License-Identifier: BSD-3-Clause
"""Every source file of the project carries its license's SPDX identifier
in its first lines (LICENSE: BSD-3-Clause). Source files are the ones git
tracks with a source ending (C, C++, Python, shell, CMake, LCM, Java, and
the CMake templates); data (reference vectors, fuzz corpora, models, the
EDS, the DBC) and prose carry none. Exit 1 naming each file without it.

    tests/analysis/spdx.py SOURCE_DIR
"""
import os
import subprocess
import sys

ID = "SPDX-License-Identifier: BSD-3-Clause"
ENDINGS = (".c", ".h", ".cpp", ".hpp", ".py", ".sh", ".cmake", ".lcm", ".java", ".in", ".toml")
NAMES = ("CMakeLists.txt", ".clang-tidy")
SKIP = ("tests/fuzz/corpus/", "tests/vectors/")


def sources(top):
    files = subprocess.run(["git", "-C", top, "ls-files"], capture_output=True, text=True, check=True).stdout.split()
    return [f for f in files if not f.startswith(SKIP) and (f.endswith(ENDINGS) or os.path.basename(f) in NAMES
                                                             or f == ".ci/run")]


def main():
    top = sys.argv[1]
    files = sources(top)
    missing = []
    for f in files:
        with open(os.path.join(top, f), errors="replace") as fh:
            head = [fh.readline() for _ in range(3)]
        if not any(ID in line for line in head):
            missing.append(f)
    for f in missing:
        print(f"{f}: no '{ID}' in its first 3 lines")
    print(f"spdx: {len(files) - len(missing)} of {len(files)} source files carry the identifier")
    return 1 if missing or not files else 0


if __name__ == "__main__":
    sys.exit(main())
