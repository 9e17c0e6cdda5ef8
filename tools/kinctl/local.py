# SPDX-License-Identifier: BSD-3-Clause
"""A kinctld of one's own on this machine: a private LCM URL, start, stop.

The one daemon launcher: the demo (kinctl.demo), the benchmarks and every
Python test suite start kinctld through Kinctld. Every URL is a multicast
group and port of its own with ttl=0, so nothing leaves the machine and
concurrent runs never hear each other.
"""
import itertools
import os
import re
import signal
import subprocess
import time

import lcm

from kinctl import programs

_counter = itertools.count()


def unique_url(subnet=78, port_base=24000):
    """A multicast group and port of this process's own (239.255.<subnet>.x,
    ttl=0). Suites that may run at the same time use different subnets and
    port ranges (port_base to port_base + 3,999), all below the kernel's
    ephemeral ports (32768 up by default), which another socket of the
    machine may hold: LCM's bind then fails ("Address already in use").
    The receive buffer is sized for the bursts of statuses a flood of
    goals brings (the kernel caps it at net.core.rmem_max)."""
    n = next(_counter)
    pid = os.getpid()
    group = 1 + (pid + n) % 250
    port = port_base + (pid % 100) * 40 + n % 40
    return f"udpm://239.255.{subnet}.{group}:{port}?ttl=0&recv_buf_size=4194304"


def multicast_works(url=None):
    """True when LCM multicast loops back on this machine."""
    url = url or unique_url()
    a, b = lcm.LCM(url), lcm.LCM(url)
    got = []
    b.subscribe("PROBE", lambda c, d: got.append(d))
    for _ in range(3):
        a.publish("PROBE", b"x")
        b.handle_timeout(200)
        if got:
            return True
    return False


MULTICAST_HELP = ("LCM multicast does not loop back on this machine; as root: "
                  "ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo")


def ensure_multicast():
    """True when multicast works, after routing 224.0.0.0/4 on lo when it does
    not and we are root; else False."""
    if multicast_works():
        return True
    if os.geteuid() == 0:
        subprocess.run(["ip", "link", "set", "lo", "multicast", "on"], check=False, capture_output=True)
        subprocess.run(["ip", "route", "add", "224.0.0.0/4", "dev", "lo"], check=False, capture_output=True)
        return multicast_works()
    return False


# What a sanitizer build's runtime writes when it finds something.
SANITIZER_REPORT = re.compile(r"runtime error:|ERROR: (?:Address|Leak|UndefinedBehavior)Sanitizer")
DEFAULT_PREFIX = "KINCTL_"


class Kinctld:
    """kinctld as a subprocess on an LCM URL of its own: Kinctld(...),
    wait_ready(), stop() (or close(), which also fails on a sanitizer's
    report). After either: proc.returncode, stderr (the text it wrote).

    args are kinctld's own; --lcm-url (unless url_flag is False: the URL
    then reaches it otherwise, e.g. env LCM_DEFAULT_URL), --prefix (unless
    the default), --rt or --no-rt and extra_args follow them. wrapper: a
    command line the daemon runs under (valgrind ...). env: added to this
    process's environment, which loses LCM_DEFAULT_URL. stderr: a file for
    the daemon's stderr (default: captured in memory; os.devnull: dropped).
    stdout: True sends the daemon's stdout where its stderr goes, one log
    of both (default: discarded). slowdown: every timeout is multiplied by
    it (sanitizer builds run several times slower).
    """

    def __init__(self, *args, binary=None, url=None, prefix=DEFAULT_PREFIX, rt=False, stderr=None, env=None,
                 url_flag=True, extra_args=(), wrapper=(), slowdown=1.0, stdout=False):
        self.binary = binary or programs.find("kinctld")
        self.url = url or unique_url()
        self.prefix = prefix
        self.slowdown = slowdown
        argv = [self.binary] + list(args)
        if url_flag:
            argv += ["--lcm-url", self.url]
        if prefix != DEFAULT_PREFIX:
            argv += ["--prefix", prefix]
        self.argv = list(wrapper) + argv + ["--rt" if rt else "--no-rt"] + list(extra_args)
        e = dict(os.environ)
        e.pop("LCM_DEFAULT_URL", None)
        e.update(env or {})
        self._stderr_path = stderr
        self._stderr = open(stderr, "w") if stderr else subprocess.PIPE
        if not stdout:
            out, err = subprocess.DEVNULL, self._stderr
        elif stderr:
            out, err = self._stderr, self._stderr
        else:
            out, err = subprocess.PIPE, subprocess.STDOUT  # one pipe: communicate() returns both as out
        self.proc = subprocess.Popen(self.argv, stdout=out, stderr=err, text=True, env=e)
        self.stderr = ""
        self.stopped = False
        self.hung = False

    def wait_ready(self, timeout=10.0):
        """Waits for the first setpoint; raises RuntimeError with stderr when none comes."""
        from kinctl.client import Client, DaemonNotFound
        with Client(self.url, self.prefix) as c:
            deadline = time.monotonic() + timeout * self.slowdown
            while time.monotonic() < deadline:
                if self.proc.poll() is not None:
                    break
                try:
                    return c.wait_daemon(0.2)
                except DaemonNotFound:
                    pass
        self._end(signal.SIGKILL, 20.0)
        raise RuntimeError(f"{' '.join(self.argv)} sent no setpoint (exit {self.proc.returncode}): "
                           f"{self.stderr.strip()}")

    def stop(self, sig=signal.SIGTERM, timeout=20.0, while_waiting=None):
        """Signals the daemon (SIGTERM: controlled stop), waits, returns its exit code
        (at once when stopped before; also when it had exited on its own). One
        that does not exit within timeout is killed, and hung set.
        while_waiting: called over and over until the daemon exits or the
        timeout passes, each call blocking a little (lc.handle_timeout(50)),
        so that the caller goes on reading what the daemon publishes as it
        stops (its last status and stats); the daemon's stderr should then
        go to a file, as a pipe is not read meanwhile."""
        return self._end(sig, timeout, while_waiting)

    def close(self, sig=signal.SIGKILL, timeout=20.0):
        """The end of the daemon: stopped by sig when it still runs; then
        RuntimeError when its stderr holds a sanitizer's report (a sanitizer
        build's daemon that died of a finding may have failed nothing else)."""
        self._end(sig, timeout)
        report = self.sanitizer_report()
        if report:
            raise RuntimeError(f"kinctld's sanitizer report:\n{report}")

    def sanitizer_report(self):
        """The sanitizer's report in the daemon's stderr, from its first line
        on ('' when there is none)."""
        m = SANITIZER_REPORT.search(self.stderr)
        return self.stderr[self.stderr.rfind("\n", 0, m.start()) + 1:] if m else ""

    def _end(self, sig, timeout, while_waiting=None):
        if self.stopped:
            return self.proc.returncode
        self.stopped = True
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
        deadline = time.monotonic() + timeout * self.slowdown
        while while_waiting is not None and self.proc.poll() is None and time.monotonic() < deadline:
            while_waiting()
        # An exited daemon's pipe is read to its end without a deadline.
        left = None if self.proc.poll() is not None else max(0.0, deadline - time.monotonic())
        try:
            out, err = self.proc.communicate(timeout=left)
        except subprocess.TimeoutExpired:
            self.hung = True
            self.proc.kill()
            out, err = self.proc.communicate()
        if self._stderr_path:
            self._stderr.close()
            with open(self._stderr_path) as f:
                self.stderr = f.read()
        else:
            self.stderr = (out if self.proc.stdout is not None else err) or ""
        return self.proc.returncode

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop(signal.SIGTERM if exc[0] is None else signal.SIGKILL)
