#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Writes OUT_DIR/compile_commands.json with the entries of BUILD_DIR's that
compile kinctl's own C code (core, desc, daemon, kinctl-calc, the C test
harnesses), not the code lcm-gen generates into the build tree, and
OUT_DIR/files with those files, one a line, relative to SOURCE_DIR.
--tests-once keeps one entry a test file (the unit tests are built once
a precision and read alike in both).
  own_sources.py SOURCE_DIR BUILD_DIR OUT_DIR [--tests-once]"""
import json
import os
import re
import sys

OURS = re.compile(r'^(core/src|core/desc/src|daemon|tools/calc|tests/unit|tests/desc|tests/msg|tests/fuzz)/[^/]+\.c$')


def main(argv):
    if len(argv) not in (4, 5) or (len(argv) == 5 and argv[4] != '--tests-once'):
        sys.exit(__doc__)
    src, build, out = (os.path.abspath(a) for a in argv[1:4])
    tests_once = len(argv) == 5
    db = os.path.join(build, 'compile_commands.json')
    if not os.path.exists(db):
        sys.exit(f'no {db}: configure with CMAKE_EXPORT_COMPILE_COMMANDS=ON (the top-level CMakeLists.txt sets it)')
    keep, files = [], []
    for e in json.load(open(db)):
        f = os.path.relpath(os.path.join(e['directory'], e['file']), src)
        if not OURS.match(f):
            continue
        if tests_once and f.startswith('tests/') and f in files:
            continue
        keep.append(e)
        if f not in files:
            files.append(f)
    with open(os.path.join(out, 'compile_commands.json'), 'w') as fh:
        json.dump(keep, fh, indent=1)
    with open(os.path.join(out, 'files'), 'w') as fh:
        fh.write(''.join(f + '\n' for f in sorted(files)))


if __name__ == '__main__':
    main(sys.argv)
