# SPDX-License-Identifier: BSD-3-Clause
"""What every command module of the `kinctl` CLI shares: the argument types
(value parsers for argparse), the subcommand helper and the messages to the
user. A leaf: it imports nothing from kinctl, so every command module may
import it.

Bad input found after parsing raises UsageError or ValueError (exit 2).
"""
import argparse
import math
import re
import sys


class UsageError(Exception):
    """Bad input found after parsing: exit 2."""


def say(*a):
    """A line of the command's own output on stdout."""
    print(*a, flush=True)


def err(*a):
    """A line on stderr, as `kinctl: ...`."""
    print("kinctl:", *a, file=sys.stderr, flush=True)


# -- value parsers -----------------------------------------------------------

def numbers(text):
    """'a,b,c' -> [a, b, c] as floats; argparse reports a bad one."""
    out = []
    for part in text.split(","):
        part = part.strip()
        try:
            v = float(part)
        except ValueError:
            raise argparse.ArgumentTypeError(f"'{part}' is not a number (in '{text}')") from None
        if not math.isfinite(v):
            raise argparse.ArgumentTypeError(f"'{part}' is not a finite number (in '{text}')")
        out.append(v)
    return out


def vector(count, what):
    def parse(text):
        v = numbers(text)
        if len(v) != count:
            raise argparse.ArgumentTypeError(f"needs {count} numbers ({what}), got {len(v)} in '{text}'")
        return v
    parse.__name__ = f"{count} numbers"
    return parse


def points(text):
    """'p;p;...' -> a list of number lists."""
    pts = [p for p in text.split(";") if p.strip()]
    if not pts:
        raise argparse.ArgumentTypeError("no points given (format: 'a,b,c;d,e,f;...')")
    return [numbers(p) for p in pts]


def parse_nodes(text):
    """CAN node ids: '1-6' or '1,2,5' or '3' -> [1, ...]; ValueError
    otherwise."""
    nodes = []
    try:
        for part in text.split(","):
            part = part.strip()
            if "-" in part:
                a, b = part.split("-", 1)
                nodes += list(range(int(a), int(b) + 1))
            elif part:
                nodes.append(int(part))
    except ValueError:
        nodes = []
    if not nodes or any(not 1 <= n <= 127 for n in nodes) or len(set(nodes)) != len(nodes):
        raise ValueError(f"--nodes {text!r}: expected distinct node ids in 1..127, e.g. 1-6 or 1,2,3")
    return nodes


def positive(text):
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"{text} must be > 0")
    return v


def nonneg(text):
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not (math.isfinite(v) and v >= 0):
        raise argparse.ArgumentTypeError(f"{text} must be >= 0")
    return v


def fraction(text):
    """A fraction of the limits, 0 .. 1 (0 means 1, as the messages say)."""
    v = nonneg(text)
    if v > 1.0:
        raise argparse.ArgumentTypeError(f"{text} must be a fraction of the limits in [0, 1] (0 means 1)")
    return v


def goal_id(text):
    try:
        v = int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not an integer") from None
    if v == 0 or not -2 ** 63 <= v < 2 ** 63:
        raise argparse.ArgumentTypeError(f"{text}: a goal id is a non-zero 64-bit integer (0 means no goal)")
    return v


# Options whose value may start with '-' (a negative number): argparse would
# take "-0.5,1" for an option, so such values are glued on: --q=-0.5,1.
VALUE_OPTIONS = {"--q", "--to", "--via", "--points", "--times", "--pose", "--twist"}
NEGATIVE = re.compile(r"^-[0-9.]")


def glue_negative_values(argv):
    out, i = [], 0
    while i < len(argv):
        a = argv[i]
        if a in VALUE_OPTIONS and i + 1 < len(argv) and NEGATIVE.match(argv[i + 1]):
            out.append(f"{a}={argv[i + 1]}")
            i += 2
        else:
            out.append(a)
            i += 1
    return out


# -- subcommands -------------------------------------------------------------

class Formatter(argparse.RawDescriptionHelpFormatter):
    pass


def add_command(subparsers, name, help_, example, parents):
    """A subcommand's parser: its help, an example and the connection options (parents)."""
    return subparsers.add_parser(name, help=help_, description=help_, epilog="example:\n  " + example,
                                 formatter_class=Formatter, parents=parents)
