# SPDX-License-Identifier: BSD-3-Clause
"""How a `kinctl` command reaches kinctld: the connection options every
command takes (--lcm-url, --prefix, --deg, --connect-timeout) and the client
a live command opens with them.
"""
import argparse
import os

from kinctl.argtypes import positive


def add_options(p, suppress):
    """The connection options on p. suppress: on a subcommand (its parents),
    where an option given before the subcommand must not be reset."""
    d = (lambda v: argparse.SUPPRESS) if suppress else (lambda v: v)
    g = p.add_argument_group("connection")
    g.add_argument("--lcm-url", default=d(os.environ.get("LCM_DEFAULT_URL") or None), metavar="URL",
                   help="LCM URL of the daemon (default: $LCM_DEFAULT_URL, then LCM's default "
                        "udpm://239.255.76.67:7667?ttl=0)")
    g.add_argument("--prefix", default=d("KINCTL_"), help="channel prefix (default KINCTL_)")
    g.add_argument("--deg", action="store_true", default=d(False),
                   help="revolute joints' values and angular rates in degrees (prismatic joints stay in m)")
    g.add_argument("--connect-timeout", type=positive, default=d(2.0), metavar="S",
                   help="how long to wait for the daemon's first setpoint and for an answer (default 2 s)")


def connect(args, **kw):
    """A kinctl.client.Client on the daemon of args, once its first setpoint
    came (DaemonNotFound after --connect-timeout)."""
    from kinctl.client import Client
    c = Client(url=args.lcm_url, prefix=args.prefix, **kw)
    try:
        c.wait_daemon(args.connect_timeout)
    except Exception:
        c.close()
        raise
    return c


def state_of(sp):
    """The state name of a setpoint ('?' for none)."""
    from kinctl.msgs import state_name
    return state_name(sp.state) if sp is not None else "?"
