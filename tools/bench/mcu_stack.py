#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Worst-case stack per function from GCC's call graphs.

Reads every .ci file (gcc -fcallgraph-info=su: one VCG graph per object,
each function's own frame in "N bytes (static)") under the given
directories and, for each function named on the command line, prints the
deepest sum of frames along any call path from it:

    stack <function> <bytes> [unknown: callees without a frame] [recursive]

Callees with no frame in any graph (newlib's libm, memcpy) are listed as
unknown: their frames are not in the sum. A cycle in the graph (recursion)
would make the bound infinite and is reported as such. Indirect calls
(__indirect_call) are unknown too.
"""
import os
import re
import sys

NODE = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"')
EDGE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')
FRAME = re.compile(r"\\n(\d+) bytes \(([a-z,]+)\)")


def load(dirs):
    frames, dynamic, calls = {}, set(), {}
    for top in dirs:
        for root, _, files in os.walk(top):
            for name in files:
                if not name.endswith(".ci"):
                    continue
                with open(os.path.join(root, name), encoding="utf-8") as f:
                    text = f.read()
                for title, label in NODE.findall(text):
                    m = FRAME.search(label)
                    if m:
                        frames[title] = int(m.group(1))
                        if m.group(2) != "static":
                            dynamic.add(title)
                for src, dst in EDGE.findall(text):
                    calls.setdefault(src, set()).add(dst)
    return frames, dynamic, calls


def resolve(name, frames):
    """A global function is titled by its name; a static one by file:name."""
    if name in frames:
        return name
    hits = [t for t in frames if t.endswith(":" + name)]
    return hits[0] if len(hits) == 1 else name


def worst(fn, frames, calls, memo, path, unknown, flags):
    if fn in memo:
        return memo[fn]
    if fn in path:
        flags.add("recursive")
        return 0
    if fn not in frames:
        unknown.add(fn.split(":")[-1])
        return 0
    path.add(fn)
    deepest = 0
    for callee in calls.get(fn, ()):
        deepest = max(deepest, worst(callee, frames, calls, memo, path, unknown, flags))
    path.discard(fn)
    memo[fn] = frames[fn] + deepest
    return memo[fn]


def main():
    if len(sys.argv) < 3 or "--" not in sys.argv:
        sys.exit("usage: mcu_stack.py DIR... -- FUNCTION...")
    split = sys.argv.index("--")
    dirs, names = sys.argv[1:split], sys.argv[split + 1:]
    frames, dynamic, calls = load(dirs)
    if not frames:
        sys.exit("no .ci files (gcc -fcallgraph-info=su) under " + " ".join(dirs))
    status = 0
    for name in names:
        fn = resolve(name, frames)
        if fn not in frames:
            print("stack %s ? (not in the call graphs)" % name)
            status = 1
            continue
        unknown, flags = set(), set()
        total = worst(fn, frames, calls, {}, set(), unknown, flags)
        if any(f in dynamic for f in frames if f == fn):
            flags.add("dynamic")
        extra = ""
        if unknown:
            extra += " unknown: " + ",".join(sorted(unknown))
        if flags:
            extra += " " + " ".join(sorted(flags))
        print("stack %s %d%s" % (name, total, extra))
    return status


if __name__ == "__main__":
    sys.exit(main())
