# SPDX-License-Identifier: BSD-3-Clause
"""What the Python suites that drive a real kinctld share (tests/daemon,
faults, tools, viz, vcan): the multicast check, the daemon, the CLI runner,
and the motion helpers of puma560 at its nominal pose. On PYTHONPATH through
tests/CMakeLists.txt (KINCTLD_TEST_ENV); each suite's conftest.py imports
the fixtures it uses, its tests import the names.

Each daemon has its own LCM URL (a multicast group and port of its own,
ttl=0, so nothing leaves the machine and tests never hear each other) and is
a kinctl.local.Kinctld, the launcher the tools use too.

    def test_something(kinctld):           # the fixture (conftest: from kinctl_testing import kinctld)
        d = kinctld()                      # puma560, 1 kHz, --no-rt, a Bus on its URL
        d.bus.wait_setpoints(100)
        d.bus.send_goal_joint(7, [0.1] * 6)
        st = d.bus.wait_event(7, ("COMPLETED", "REJECTED"))
        assert d.stop() == 0

    d = start_kinctld("--model", "panda")  # a Kinctld without a Bus, for the CLI's tests
    r = run_kinctl(d, "status", "--json")  # `python -m kinctl --lcm-url <d's URL> status --json`

Environment (tests/CMakeLists.txt): KINCTLD (the binary), PYTHONPATH with
the generated kinctl_msgs, tools/ and this directory, KINCTL_MODELS
(models/), KINCTLD_TEST_SLOWDOWN in sanitized builds (every timeout is
multiplied by it). KINCTLD_EXTRA_ARGS adds arguments to every start of the
kinctld fixture (e.g. "--rt"). KINCTLD_MEMCHECK=DIR runs every daemon of the
kinctld fixture under valgrind memcheck, its report in DIR, and fails the
test that started it on any error or leak (the vcan suite's memory check,
where ASan cannot run; set KINCTLD_TEST_SLOWDOWN too).
"""
import glob
import math
import os
import re
import shlex
import signal
import socket
import struct
import subprocess
import sys
import threading
import time

import pytest

from kinctl import local

import lcm
# The message classes, for the tests to import from here too.
from kinctl_msgs import (command_t, goal_arc_t, goal_joint_t, goal_line_t, goal_path_t, goal_servo_t, setpoint_t,
                         stats_t, status_t)

KINCTLD = os.environ.get("KINCTLD", "")
MODELS = os.environ.get("KINCTL_MODELS", os.path.join(os.path.dirname(__file__), "..", "..", "models"))
# Slow builds (sanitizers) get more time for everything.
SLOW = float(os.environ.get("KINCTLD_TEST_SLOWDOWN", "1"))
MEMCHECK_DIR = os.environ.get("KINCTLD_MEMCHECK", "")

EVENTS = {"NONE": 0, "ACCEPTED": 1, "REJECTED": 2, "COMPLETED": 3, "PREEMPTED": 4, "ABORTED": 5, "FAULT": 6,
          "STARTED": 7}
EVENT_NAMES = {v: k for k, v in EVENTS.items()}
STATES = {"IDLE": 0, "MOVING": 1, "PAUSED": 2, "STOPPING": 3, "FAULT": 4, "ESTOP": 5}


def unique_url():
    """A multicast group and port no other test (or concurrent run) uses:
    239.255.77.x for the kinctld fixture, apart from kinctl.local's
    239.255.78.x (start_kinctld's default) and tests/viz's 239.255.79.x."""
    return local.unique_url(subnet=77, port_base=20000)


@pytest.fixture(scope="session")
def multicast():
    """LCM multicast on this machine, set up on lo when needed and permitted."""
    if not local.ensure_multicast():
        pytest.skip(local.MULTICAST_HELP + " (the fixture does this itself when root)")


# -- valgrind memcheck -----------------------------------------------------

def memcheck_wrapper():
    """The command kinctld runs under: valgrind memcheck when KINCTLD_MEMCHECK is set, else none."""
    if not MEMCHECK_DIR:
        return []
    os.makedirs(MEMCHECK_DIR, exist_ok=True)
    return ["valgrind", "--tool=memcheck", "--leak-check=full", "--errors-for-leak-kinds=definite,indirect",
            "--show-leak-kinds=definite,indirect", "--error-exitcode=99",
            f"--log-file={MEMCHECK_DIR}/kinctld.%p.log"]


def daemon_argv(args):
    """kinctld's command line, under valgrind memcheck when KINCTLD_MEMCHECK is set."""
    return memcheck_wrapper() + [KINCTLD] + list(args)


def memcheck_errors(pid):
    """valgrind's complaints about the daemon that ran as pid ('' when clean
    or not under valgrind). A daemon killed outright has no summary, but its
    errors were written as they happened."""
    if not MEMCHECK_DIR:
        return ""
    text = "".join(open(f).read() for f in glob.glob(f"{MEMCHECK_DIR}/kinctld.{pid}.log"))
    summary = re.search(r"ERROR SUMMARY: (\d+) errors", text)
    blocks = re.findall(r"^==\d+== (?:Invalid|Conditional|Use of uninitialised|Syscall param|Mismatched|"
                        r"Source and destination|Argument|Process terminating|\S.* are definitely lost|"
                        r"\S.* are indirectly lost).*$", text, re.M)
    if (summary and summary.group(1) != "0") or blocks:
        return text
    return ""


# -- the bus and the daemon -------------------------------------------------

class Bus:
    """One LCM instance on the daemon's URL, recording what the daemon sends."""

    def __init__(self, url, prefix="KINCTL_"):
        self.url, self.prefix = url, prefix
        self.lc = lcm.LCM(url)
        self.lock = threading.Condition()
        self.setpoints, self.statuses, self.stats = [], [], []
        for name, cls, store in (("SETPOINT", setpoint_t, self.setpoints), ("STATUS", status_t, self.statuses),
                                 ("STATS", stats_t, self.stats)):
            sub = self.lc.subscribe(prefix + name, self._handler(cls, store))
            # LCM keeps 30 messages per subscription by default: a test thread
            # holding the GIL for 30 ms would lose setpoints, not the daemon.
            sub.set_queue_capacity(100000)
        self._run = True
        self._thread = threading.Thread(target=self._loop, daemon=True)
        self._thread.start()

    def _handler(self, cls, store):
        def handle(channel, data):
            msg = cls.decode(data)
            with self.lock:
                store.append(msg)
                self.lock.notify_all()
        return handle

    def _loop(self):
        while self._run:
            self.lc.handle_timeout(20)

    def close(self):
        self._run = False
        self._thread.join(2)

    # -- waiting ---------------------------------------------------------
    def wait(self, predicate, timeout=5.0, what="a condition"):
        """Waits until predicate() (called under the lock) is truthy; returns it."""
        deadline = time.monotonic() + timeout * SLOW
        with self.lock:
            while True:
                r = predicate()
                if r:
                    return r
                left = deadline - time.monotonic()
                if left <= 0:
                    raise AssertionError(f"timed out after {timeout * SLOW:.1f} s waiting for {what}")
                self.lock.wait(min(left, 0.05))

    def wait_count(self, count, target, stall=10.0, what="answers"):
        """Waits until count() (called under the lock) reaches target, for as
        long as it keeps rising: fails only when it has not risen for stall
        s (times the slowdown), saying how far it got. For a flood whose
        throughput is the machine's, not the property under test."""
        last, since = count(), time.monotonic()
        with self.lock:
            while True:
                n = count()
                if n >= target:
                    return n
                now = time.monotonic()
                if n > last:
                    last, since = n, now
                elif now - since > stall * SLOW:
                    raise AssertionError(f"{what}: {n} of {target}, none more for {stall * SLOW:.0f} s")
                self.lock.wait(0.05)

    def wait_setpoints(self, count, timeout=5.0):
        """Waits for count setpoints more than have arrived so far; returns them."""
        with self.lock:
            start = len(self.setpoints)
        self.wait(lambda: len(self.setpoints) >= start + count, timeout, f"{count} setpoints")
        with self.lock:
            return list(self.setpoints[start:])

    def events(self, goal_id):
        with self.lock:
            return [s for s in self.statuses if s.event != 0 and s.event_goal_id == goal_id]

    def wait_event(self, goal_id, kinds, timeout=10.0):
        """The first status about goal_id whose event is one of kinds (names)."""
        codes = {EVENTS[k] for k in kinds}

        def find():
            for s in self.statuses:
                if s.event_goal_id == goal_id and s.event in codes:
                    return s
            return None
        return self.wait(find, timeout, f"event {'/'.join(kinds)} for goal {goal_id}")

    def wait_stats(self, predicate=lambda s: True, timeout=5.0):
        with self.lock:
            start = len(self.stats)

        def find():
            for s in self.stats[start:]:
                if predicate(s):
                    return s
            return None
        return self.wait(find, timeout, "a stats_t")

    def wait_idle(self, timeout=10.0):
        """Waits for an idle setpoint with no goal and returns it."""
        with self.lock:
            start = len(self.setpoints)

        def find():
            for s in self.setpoints[start:]:
                if s.state == STATES["IDLE"] and s.goal_id == 0:
                    return s
            return None
        return self.wait(find, timeout, "an idle setpoint")

    def last_setpoint(self):
        with self.lock:
            return self.setpoints[-1] if self.setpoints else None

    # -- sending ---------------------------------------------------------
    def send_raw(self, suffix, data):
        self.lc.publish(self.prefix + suffix, data)

    def send(self, suffix, msg):
        msg.utime = int(time.time() * 1e6)
        self.send_raw(suffix, msg.encode())

    def send_goal_joint(self, goal_id, q, replace=False, vel_scale=0.0, acc_scale=0.0, n=None,
                        profile=goal_joint_t.PROFILE_CONFIG):
        g = goal_joint_t()
        g.goal_id = goal_id
        g.mode = goal_joint_t.REPLACE if replace else goal_joint_t.QUEUE
        g.n = len(q) if n is None else n
        g.q = list(q) + [0.0] * (goal_joint_t.MAX_JOINTS - len(q))
        g.vel_scale, g.acc_scale = vel_scale, acc_scale
        g.profile = profile
        self.send("GOAL_JOINT", g)
        return g

    def send_goal_line(self, goal_id, position, orientation, replace=False):
        g = goal_line_t()
        g.goal_id = goal_id
        g.mode = goal_line_t.REPLACE if replace else goal_line_t.QUEUE
        g.position = list(position)
        g.orientation = list(orientation)
        self.send("GOAL_LINE", g)
        return g

    def send_command(self, name):
        c = command_t()
        c.command = getattr(command_t, name)
        self.send("COMMAND", c)


class Daemon(local.Kinctld):
    """kinctld under test (kinctl.local.Kinctld: memcheck, KINCTLD_EXTRA_ARGS
    and the slowdown of this build) with a Bus recording what it sends."""

    def __init__(self, args, url, prefix, rt, url_flag, env):
        self.bus = Bus(url, prefix)
        super().__init__(*args, binary=KINCTLD, url=url, prefix=prefix, rt=rt, url_flag=url_flag, env=env,
                         extra_args=shlex.split(os.environ.get("KINCTLD_EXTRA_ARGS", "")),
                         wrapper=memcheck_wrapper(), slowdown=SLOW)

    def stop(self, sig=signal.SIGTERM, timeout=15.0):
        """Signals the daemon, waits for it and returns its exit code."""
        rc = super().stop(sig, timeout)
        if self.hung:
            raise AssertionError("kinctld did not exit after " + signal.Signals(sig).name)
        # Give the last datagrams a moment to arrive.
        time.sleep(0.1)
        return rc

    def close(self):
        try:
            # SIGTERM under memcheck, so that valgrind gets to check for leaks at the exit.
            super().close(signal.SIGTERM if MEMCHECK_DIR else signal.SIGKILL, 15.0)
        except RuntimeError as e:
            raise AssertionError(str(e)) from None
        finally:
            self.bus.close()
            errors = memcheck_errors(self.proc.pid)
            assert not errors, f"valgrind memcheck found errors in kinctld:\n{errors}"


@pytest.fixture
def kinctld(multicast):
    """Factory: kinctld(*args, prefix=..., rt=False, env=...) starts a daemon on
    a fresh URL, waits for its first setpoints and returns a Daemon."""
    if not KINCTLD:
        pytest.skip("KINCTLD is not set (run through ctest)")
    started = []

    def start(*args, prefix="KINCTL_", rt=False, url=None, env=None, url_flag=True, wait=True):
        d = Daemon(args, url or unique_url(), prefix, rt, url_flag, env)
        started.append(d)
        if wait:
            try:
                d.bus.wait_setpoints(20, timeout=10.0)
            except AssertionError:
                d.close()
                raise AssertionError(f"{' '.join(d.argv)} sent no setpoints; stderr: {d.stderr}")
        return d

    yield start
    for d in started:
        d.close()


def run_kinctld(*args, env=None, timeout=10.0):
    """Runs kinctld to completion (configuration errors, --help, --check)."""
    e = dict(os.environ)
    e.update(env or {})
    return subprocess.run(daemon_argv(args), capture_output=True, text=True, timeout=timeout * SLOW, env=e)


def quat_norm(q):
    return math.sqrt(sum(x * x for x in q))


# -- kinctld for the CLI's tests, and the CLI --------------------------------

def start_kinctld(*args, **kw):
    """A kinctl.local.Kinctld of this build (--no-rt; keyword arguments as
    Kinctld's), once its first setpoint came. Skips the test when KINCTLD is
    not set."""
    if not KINCTLD:
        pytest.skip("KINCTLD is not set (run through ctest)")
    d = local.Kinctld(*args, binary=KINCTLD, slowdown=SLOW, **kw)
    d.wait_ready(10.0)
    return d


def run_kinctl(daemon, *args, timeout=60.0):
    """`python -m kinctl --lcm-url URL args...`, URL the daemon's (a Kinctld,
    or the URL itself; None: no --lcm-url): a CompletedProcess."""
    url = getattr(daemon, "url", daemon)
    env = dict(os.environ)
    env.pop("LCM_DEFAULT_URL", None)
    url_args = ["--lcm-url", url] if url else []
    return subprocess.run([sys.executable, "-m", "kinctl"] + url_args + [str(a) for a in args],
                          capture_output=True, text=True, timeout=timeout * SLOW, env=env)


# -- puma560 moving from its nominal pose --------------------------------------

N = 6
QN = [0.0, 0.7854, -3.1416, 0.0, 0.7854, 0.0]
# puma560's limits as built in (models/puma560.cfg).
QD_MAX = [2.0, 2.0, 2.0, 4.0, 4.0, 4.0]
QDD_MAX = [5.0, 5.0, 5.0, 10.0, 10.0, 10.0]
QDDD_MAX = [50.0, 50.0, 50.0, 100.0, 100.0, 100.0]
DT = 1e-3
# The tool pose at QN (puma560's forward kinematics).
QN_POSITION = [0.5963008264104923, -0.15005, 0.6574746899005355]
QN_ORIENTATION = [0.7071054825112363, 0.0, 0.7071080798594737, 0.0]
END = ("COMPLETED", "REJECTED", "ABORTED", "FAULT")


def servo_twist(goal_id, twist, timeout_us):
    """A goal_servo_t that replaces what runs by a twist stream (m/s, rad/s;
    the target's orientation the tool's own), going stale after timeout_us
    without a message."""
    g = goal_servo_t()
    g.goal_id = goal_id
    g.mode = goal_servo_t.REPLACE
    g.kind = goal_servo_t.TWIST
    g.twist = list(twist)
    g.orientation = [1.0, 0.0, 0.0, 0.0]
    g.timeout_us = timeout_us
    return g


def go_nominal(d, goal_id=1):
    d.bus.send_goal_joint(goal_id, QN)
    st = d.bus.wait_event(goal_id, END)
    assert st.event == EVENTS["COMPLETED"], st.reason
    s = d.bus.wait_idle()
    assert close(s.position, QN_POSITION, 1e-9)
    return s


def finished(d, goal_id, timeout=20.0):
    st = d.bus.wait_event(goal_id, END, timeout)
    assert st.event == EVENTS["COMPLETED"], f"{EVENT_NAMES[st.event]}: {st.reason}"
    return d.bus.wait_idle()


def setpoints_since(d, cycle):
    with d.bus.lock:
        return [s for s in d.bus.setpoints if s.cycle >= cycle]


def assert_smooth(sps, slack=1e-6):
    """Consecutive cycles; |qd| within the limits; the velocity change per
    tick within qdd_max dt; the position change within qd_max dt."""
    for a, b in zip(sps, sps[1:]):
        assert b.cycle == a.cycle + 1, (a.cycle, b.cycle)
        for j in range(N):
            assert abs(b.qd[j]) <= QD_MAX[j] * (1 + slack), (b.cycle, j, b.qd[j])
            assert abs(b.qd[j] - a.qd[j]) <= QDD_MAX[j] * DT * (1 + slack) + 1e-12, (b.cycle, j)
            assert abs(b.q[j] - a.q[j]) <= QD_MAX[j] * DT * (1 + slack) + 1e-12, (b.cycle, j)


def max_jerk_ratio(sps):
    """The largest |change of qdd per tick| / dt / qddd_max over the
    stream (consecutive cycles), and the largest |qdd| / qdd_max."""
    rj = ra = 0.0
    for a, b in zip(sps, sps[1:]):
        assert b.cycle == a.cycle + 1, (a.cycle, b.cycle)
        for j in range(N):
            rj = max(rj, abs(b.qdd[j] - a.qdd[j]) / DT / QDDD_MAX[j])
            ra = max(ra, abs(b.qdd[j]) / QDD_MAX[j])
    return rj, ra


def random_offset(rng, position, lo, hi):
    """position moved by lo to hi (m) in a random direction (uniform on the
    sphere: drawn in the unit ball, away from its centre)."""
    while True:
        u = [rng.uniform(-1.0, 1.0) for _ in range(3)]
        n = math.sqrt(sum(x * x for x in u))
        if 0.1 < n <= 1.0:
            break
    length = rng.uniform(lo, hi)
    return [p + length * x / n for p, x in zip(position, u)]


def fast_cart_limits(rng):
    """A Cartesian goal's speed, accel and jerk drawn up to fast ones (as
    keyword arguments of kinctl.client's make_goal_line and _arc)."""
    speed = rng.uniform(0.05, 0.5)
    accel = speed * rng.uniform(2.0, 8.0)
    return {"speed": speed, "accel": accel, "jerk": accel * rng.uniform(5.0, 20.0)}


def close(a, b, tol):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


# -- hostile datagrams -------------------------------------------------------

def forged_fragment(seqno, channel, claimed=256 << 20):
    """LCM's first-fragment header (lcm_udpm.c: magic "LC03", sequence
    number, message size, fragment offset, fragment number, fragments in the
    message), claiming a message of `claimed` bytes in two fragments that
    never completes; the first fragment carries the channel name."""
    return struct.pack(">IIIIHH", 0x4C433033, seqno, claimed, 0, 0, 2) + channel.encode() + b"\0" + bytes(1000)


def flood_fragments(url, prefix, count, done=None):
    """Sends count forged first fragments to the LCM group of url (TTL 0:
    this host only), on three of kinctld's channels; sets done at the end."""
    m = re.match(r"udpm://([\d.]+):(\d+)", url)
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 0)
    channels = [prefix + c for c in ("GOAL_PATH", "COMMAND", "GOAL_JOINT")]
    for i in range(count):
        s.sendto(forged_fragment(i, channels[i % 3]), (m.group(1), int(m.group(2))))
    s.close()
    if done is not None:
        done.set()
