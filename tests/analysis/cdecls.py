# SPDX-License-Identifier: BSD-3-Clause
"""Every public header gives its declarations C linkage for C++ programs
(kinctl/decls.h): after its includes it opens KC_BEGIN_DECLS, before its
include guard's #endif it closes KC_END_DECLS, and nothing but comments and
preprocessor lines lies outside the two. kinctl.h, which only includes the
others, and decls.h are exempt. (install.consumer links a C++ build of a
program against the installed library.) Exit 1 naming each header that
does not.

    tests/analysis/cdecls.py SOURCE_DIR
"""
import glob
import os
import re
import sys

HEADERS = ("core/include/kinctl/*.h", "core/desc/include/kinctl/*.h")
EXEMPT = ("kinctl.h", "decls.h")


def code_lines(text):
    """(line number, line) of every line outside comments that is not a
    preprocessor line or blank."""
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    return [(i + 1, line) for i, line in enumerate(text.split("\n")) if line.strip() and not line.lstrip().startswith("#")]


def problems(path):
    text = open(path).read()
    lines = text.split("\n")
    begin = [i + 1 for i, l in enumerate(lines) if l.strip() == "KC_BEGIN_DECLS"]
    end = [i + 1 for i, l in enumerate(lines) if l.strip() == "KC_END_DECLS"]
    if '#include "kinctl/decls.h"' not in text:
        return ["does not include kinctl/decls.h"]
    if len(begin) != 1 or len(end) != 1:
        return [f"has {len(begin)} KC_BEGIN_DECLS and {len(end)} KC_END_DECLS, not one each"]
    last_include = max(i + 1 for i, l in enumerate(lines) if l.startswith("#include"))
    out = []
    if begin[0] < last_include:
        out.append(f"KC_BEGIN_DECLS (line {begin[0]}) before its last #include (line {last_include})")
    for n, line in code_lines(text):
        if line.strip() in ("KC_BEGIN_DECLS", "KC_END_DECLS"):
            continue
        if n < begin[0] or n > end[0]:
            out.append(f"line {n} outside KC_BEGIN_DECLS .. KC_END_DECLS: {line.strip()}")
    return out


def main():
    top = sys.argv[1]
    headers = sorted(h for p in HEADERS for h in glob.glob(os.path.join(top, p)) if os.path.basename(h) not in EXEMPT)
    bad = 0
    for h in headers:
        for p in problems(h):
            print(f"{os.path.relpath(h, top)}: {p}")
            bad += 1
    print(f"cdecls: {len(headers)} public headers, {bad} problems")
    return 1 if bad or not headers else 0


if __name__ == "__main__":
    sys.exit(main())
