"""A kinctld of one's own on this machine: a private LCM URL, start, stop.

Used by the demo (kinctl.demo) and the tests in tests/tools: the one place
for these helpers on the client side. Like tests/daemon/conftest.py, every
URL is a multicast group and port of its own with ttl=0, so nothing leaves
the machine and concurrent runs never hear each other.
"""
import itertools
import os
import signal
import subprocess
import time

import lcm

from kinctl import programs

_counter = itertools.count()


def unique_url(subnet=78, port_base=30000):
    """A multicast group and port of this process's own (239.255.<subnet>.x,
    ttl=0). Suites that may run at the same time use different subnets and
    port ranges. The receive buffer is sized for the bursts of statuses a
    flood of goals brings (the kernel caps it at net.core.rmem_max)."""
    n = next(_counter)
    pid = os.getpid()
    group = 1 + (pid + n) % 250
    port = port_base + (pid % 500) * 40 + n % 40
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
    not and we are root (as tests/daemon/conftest.py does); else False."""
    if multicast_works():
        return True
    if os.geteuid() == 0:
        subprocess.run(["ip", "link", "set", "lo", "multicast", "on"], check=False, capture_output=True)
        subprocess.run(["ip", "route", "add", "224.0.0.0/4", "dev", "lo"], check=False, capture_output=True)
        return multicast_works()
    return False


class Kinctld:
    """kinctld as a subprocess on its own URL (--no-rt): start() ... stop()."""

    def __init__(self, *args, binary=None, url=None, prefix="KINCTL_", rt=False, stderr=None):
        self.binary = binary or programs.find("kinctld")
        self.url = url or unique_url()
        self.prefix = prefix
        self.argv = [self.binary] + list(args) + ["--lcm-url", self.url, "--prefix", prefix,
                                                  "--rt" if rt else "--no-rt"]
        env = dict(os.environ)
        env.pop("LCM_DEFAULT_URL", None)
        self._stderr_path = stderr
        self._stderr = open(stderr, "w") if stderr else subprocess.PIPE
        self.proc = subprocess.Popen(self.argv, stdout=subprocess.DEVNULL, stderr=self._stderr, text=True, env=env)
        self.stderr_text = ""
        self.stopped = False

    def wait_ready(self, timeout=10.0):
        """Waits for the first setpoint; raises RuntimeError with stderr when none comes."""
        from kinctl.client import Client, DaemonNotFound
        with Client(self.url, self.prefix) as c:
            deadline = time.monotonic() + timeout
            while time.monotonic() < deadline:
                if self.proc.poll() is not None:
                    break
                try:
                    return c.wait_daemon(0.2)
                except DaemonNotFound:
                    pass
        self.stop(signal.SIGKILL)
        raise RuntimeError(f"{' '.join(self.argv)} sent no setpoint (exit {self.proc.returncode}): "
                           f"{self.stderr_text.strip()}")

    def stop(self, sig=signal.SIGTERM, timeout=20.0):
        """Signals the daemon (SIGTERM: controlled stop), waits, returns its exit code
        (at once when stopped before; also when it had exited on its own)."""
        if self.stopped:
            return self.proc.returncode
        self.stopped = True
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
        try:
            _, err = self.proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            _, err = self.proc.communicate()
        if err:
            self.stderr_text = err
        elif self._stderr_path:
            self._stderr.close()
            with open(self._stderr_path) as f:
                self.stderr_text = f.read()
        return self.proc.returncode

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop(signal.SIGTERM if exc[0] is None else signal.SIGKILL)
