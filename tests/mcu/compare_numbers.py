#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs one program on this host and on the board and compares what they
print, number by number: every line is a label followed by numbers, the
lines must match in order and label, integers exactly (counts, indices,
tick counts) and reals within an absolute tolerance plus a relative one
(the float core on the board against the double core here). Both programs
must exit 0.

Usage: compare_numbers.py --abs A --rel R HOST_PROGRAM -- QEMU_COMMAND...
"""
import argparse
import subprocess
import sys


def run(cmd):
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    if proc.returncode != 0:
        sys.stdout.write(proc.stdout + proc.stderr)
        sys.exit(f"FAIL: {' '.join(cmd)} exited with {proc.returncode}")
    return [line.split() for line in proc.stdout.splitlines() if line.strip()]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--abs", type=float, required=True, help="absolute tolerance of a real")
    ap.add_argument("--rel", type=float, required=True, help="relative tolerance of a real")
    ap.add_argument("host", help="the program built for this host")
    ap.add_argument("board", nargs=argparse.REMAINDER, help="-- then the command that runs it on the board")
    args = ap.parse_args()
    board_cmd = args.board[1:] if args.board[:1] == ["--"] else args.board
    host, board = run([args.host]), run(board_cmd)
    if len(host) != len(board):
        sys.exit(f"FAIL: the host printed {len(host)} lines, the board {len(board)}")
    worst, where, count = 0.0, "", 0
    for n, (h, b) in enumerate(zip(host, board), 1):
        if h[0] != b[0] or len(h) != len(b):
            sys.exit(f"FAIL: line {n} differs in shape: host {' '.join(h[:3])}..., board {' '.join(b[:3])}...")
        for hv, bv in zip(h[1:], b[1:]):
            if "." not in hv and "e" not in hv:
                if hv != bv:
                    sys.exit(f"FAIL: line {n} ({' '.join(h[:3])}): integer {bv} on the board, {hv} here")
                continue
            x, y = float(hv), float(bv)
            err = abs(x - y)
            count += 1
            if err > args.abs + args.rel * abs(x):
                sys.exit(f"FAIL: line {n} ({' '.join(h[:3])}): {y!r} on the board, {x!r} here, "
                         f"difference {err:.3e} above {args.abs:g} + {args.rel:g} x |value|")
            if err > worst:
                worst, where = err, " ".join(h[:3])
    print(f"ok: {len(host)} lines, {count} reals within {args.abs:g} + {args.rel:g} x |value|; "
          f"largest difference {worst:.3e} ({where})")


if __name__ == "__main__":
    main()
