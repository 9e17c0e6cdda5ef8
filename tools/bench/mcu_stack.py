#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Worst-case stack per function from GCC's call graphs.

Reads every .ci file (gcc -fcallgraph-info=su: one VCG graph per object,
each function's own frame in "N bytes (static)") given, or under the
directories given, and for each function named on the command line,
prints the deepest sum of frames along any call path from it:

    stack <function> <bytes> [unknown: callees without a frame] [recursive]

Callees with no frame in any graph (newlib's libm, memcpy) are listed as
unknown: their frames are not in the sum. With --symbols FILE (the
image's `nm` output), a callee without a node that is another name of a
function with one (the same address: link-time optimisation folds
identical functions, e.g. the copies of a header's static inline function
that it numbers name.lto_priv.0, name.lto_priv.1) takes that one's frame.
A cycle in the graph (recursion) would make the bound infinite and is
reported as such. Indirect calls (__indirect_call) are unknown too.
"""
import os
import re
import sys

NODE = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"')
EDGE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')
FRAME = re.compile(r"\\n(\d+) bytes \(([a-z,]+)\)")


def graphs(paths):
    """The .ci files given, and those under the directories given."""
    for top in paths:
        if os.path.isfile(top):
            yield top
        for root, _, files in os.walk(top):
            for name in sorted(files):
                if name.endswith(".ci"):
                    yield os.path.join(root, name)


def load(paths):
    frames, dynamic, calls = {}, set(), {}
    for path in graphs(paths):
        with open(path, encoding="utf-8") as f:
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


def aliases(path):
    """Each function name of an nm listing -> the names at its address."""
    at = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            parts = line.split()
            if len(parts) == 3 and parts[1] in "Tt":
                at.setdefault(parts[0], []).append(parts[2])
    return {name: names for names in at.values() for name in names}


def node_of(fn, frames, alias):
    """FN's node, or that of a function at the same address."""
    if fn in frames:
        return fn
    prefix, _, name = fn.rpartition(":")
    for other in alias.get(name, ()):
        for title in (other, prefix + ":" + other if prefix else other):
            if title in frames:
                return title
    return None


def worst(fn, frames, calls, memo, path, unknown, flags, alias):
    node = node_of(fn, frames, alias)
    if node is None:
        unknown.add(fn.split(":")[-1])
        return 0
    fn = node
    if fn in memo:
        return memo[fn]
    if fn in path:
        flags.add("recursive")
        return 0
    path.add(fn)
    deepest = 0
    for callee in calls.get(fn, ()):
        deepest = max(deepest, worst(callee, frames, calls, memo, path, unknown, flags, alias))
    path.discard(fn)
    memo[fn] = frames[fn] + deepest
    return memo[fn]


def main():
    args = sys.argv[1:]
    alias = {}
    if len(args) >= 2 and args[0] == "--symbols":
        alias = aliases(args[1])
        args = args[2:]
    if len(args) < 2 or "--" not in args:
        sys.exit("usage: mcu_stack.py [--symbols NM_OUTPUT] DIR|FILE.ci... -- FUNCTION...")
    split = args.index("--")
    dirs, names = args[:split], args[split + 1:]
    frames, dynamic, calls = load(dirs)
    if not frames:
        sys.exit("no .ci files (gcc -fcallgraph-info=su) in " + " ".join(dirs))
    status = 0
    for name in names:
        fn = resolve(name, frames)
        if fn not in frames:
            print("stack %s ? (not in the call graphs)" % name)
            status = 1
            continue
        unknown, flags = set(), set()
        total = worst(fn, frames, calls, {}, set(), unknown, flags, alias)
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
