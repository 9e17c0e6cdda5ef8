# SPDX-License-Identifier: BSD-3-Clause
"""kinctl's Python API: talk to a running kinctld over LCM.

    from kinctl import Client
    with Client(url="udpm://239.255.76.67:7667?ttl=0") as c:
        c.wait_daemon()                          # a setpoint, or DaemonNotFound
        gid = c.goal_joint([0, 0.7854, -3.1416, 0, 0.7854, 0], vel_scale=0.5)
        st = c.wait_end(gid, timeout=30)         # status_t: COMPLETED, ...
        print(c.event(st), st.reason)

A background thread handles LCM: it keeps the latest setpoint and status and
every status that carries an event, so that an answer cannot be missed
between sending a goal and waiting for it. `on_setpoint` / `on_status`
callbacks (called on that thread) see every message, for logging.
"""
import math
import random
import struct
import threading
import time

import lcm

from kinctl.msgs import (CHANNELS, END_EVENTS, EVENTS, command_t, event_name, goal_arc_t, goal_joint_t,
                         goal_line_t, goal_path_t, goal_servo_t, setpoint_t, status_t)

DEFAULT_PREFIX = "KINCTL_"
# LCM queues 30 messages per subscription by default; a client busy for 30 ms
# (the GIL, a slow disk) would lose setpoints at 1 kHz.
QUEUE_CAPACITY = 100000
MODES = {False: 0, True: 1}  # QUEUE, REPLACE in every goal type
# goal_joint_t.profile: the controller's setting, the trapezoid, jerk-limited
PROFILES = {None: 0, "trapezoid": 1, "jerk": 2}


class DaemonNotFound(RuntimeError):
    """No setpoint arrived from kinctld within the timeout."""


def new_goal_id():
    """A random non-zero id (clients pick their own ids; 0 means no goal)."""
    return random.SystemRandom().randrange(1, 2 ** 31)


def _finite(name, values):
    for i, v in enumerate(values):
        if not math.isfinite(v):
            raise ValueError(f"{name}[{i}] = {v} is not a finite number")


def _count(name, values, want):
    if len(values) != want:
        raise ValueError(f"{name} needs {want} numbers, got {len(values)}")


def unit_quaternion(name, q):
    """q (w, x, y, z) normalised when within 1e-3 of unit length; else ValueError."""
    _count(name, q, 4)
    _finite(name, q)
    norm = math.sqrt(sum(x * x for x in q))
    if abs(norm - 1.0) > 1e-3:
        raise ValueError(f"{name} = {','.join(repr(x) for x in q)} is not a unit quaternion (|q| = {norm:.6g})")
    return [x / norm for x in q]


def _pose(name, pose):
    _count(name, pose, 7)
    _finite(name, pose)
    return list(pose[:3]), unit_quaternion(name + " orientation", pose[3:])


def _scale(name, s):
    if not (math.isfinite(s) and 0.0 <= s <= 1.0):
        raise ValueError(f"{name} = {s} must be a fraction of the limits in [0, 1] (0 means 1)")
    return s


def _nonneg(name, v):
    if not (math.isfinite(v) and v >= 0.0):
        raise ValueError(f"{name} = {v} must be >= 0 (0 means the controller's default)")
    return v


# -- goal messages (ValueError on bad input; nothing is sent) ---------------


def make_goal_joint(q, goal_id=None, replace=False, vel_scale=0.0, acc_scale=0.0, profile=None):
    """Joint move to q (rad or m); vel_scale, acc_scale in [0, 1] (0 = 1); profile "jerk",
    "trapezoid" or None (controller.profile). Returns the message."""
    if profile not in PROFILES:
        raise ValueError(f"profile = {profile!r} must be 'jerk', 'trapezoid' or None (the controller's)")
    g = goal_joint_t()
    if not 1 <= len(q) <= goal_joint_t.MAX_JOINTS:
        raise ValueError(f"q needs 1 to {goal_joint_t.MAX_JOINTS} joint values, got {len(q)}")
    _finite("q", q)
    g.goal_id = goal_id or new_goal_id()
    g.mode = MODES[bool(replace)]
    g.n = len(q)
    g.q = list(q) + [0.0] * (goal_joint_t.MAX_JOINTS - len(q))
    g.vel_scale, g.acc_scale = _scale("vel_scale", vel_scale), _scale("acc_scale", acc_scale)
    g.profile = PROFILES[profile]
    return g


def _cartesian(g, speed, accel, angular_speed, angular_accel, vel_scale, acc_scale, jerk=0.0, angular_jerk=0.0):
    g.speed, g.accel = _nonneg("speed", speed), _nonneg("accel", accel)
    g.angular_speed = _nonneg("angular_speed", angular_speed)
    g.angular_accel = _nonneg("angular_accel", angular_accel)
    g.jerk, g.angular_jerk = _nonneg("jerk", jerk), _nonneg("angular_jerk", angular_jerk)
    g.vel_scale, g.acc_scale = _scale("vel_scale", vel_scale), _scale("acc_scale", acc_scale)


def make_goal_line(to, goal_id=None, replace=False, speed=0.0, accel=0.0, angular_speed=0.0,
              angular_accel=0.0, slerp=False, vel_scale=0.0, acc_scale=0.0, jerk=0.0, angular_jerk=0.0):
    """Straight line of the tool to pose to = x, y, z (m), qw, qx, qy, qz. Returns the message."""
    g = goal_line_t()
    g.goal_id = goal_id or new_goal_id()
    g.mode = MODES[bool(replace)]
    g.position, g.orientation = _pose("to", to)
    _cartesian(g, speed, accel, angular_speed, angular_accel, vel_scale, acc_scale, jerk, angular_jerk)
    g.orientation_method = goal_line_t.SLERP if slerp else goal_line_t.TWO_ROTATIONS
    return g


def make_goal_arc(via, to, goal_id=None, replace=False, speed=0.0, accel=0.0, angular_speed=0.0,
             angular_accel=0.0, vel_scale=0.0, acc_scale=0.0, jerk=0.0, angular_jerk=0.0):
    """Arc of the tool through via = x, y, z to pose to. Returns the message."""
    g = goal_arc_t()
    _count("via", via, 3)
    _finite("via", via)
    g.goal_id = goal_id or new_goal_id()
    g.mode = MODES[bool(replace)]
    g.via = list(via)
    g.position, g.orientation = _pose("to", to)
    _cartesian(g, speed, accel, angular_speed, angular_accel, vel_scale, acc_scale, jerk, angular_jerk)
    return g


def make_goal_path(points, space="joint", method="blend", times=None, blend_time=0.0, goal_id=None,
              replace=False, speed=0.0, accel=0.0, vel_scale=0.0, acc_scale=0.0, shape="quartic",
              ends="clamped", jerk=0.0, angular_jerk=0.0):
    """Multi-point path through points (joint vectors, or x,y,z,qw,qx,qy,qz poses for
    space "cartesian"); method blend, spline, quintic or lagrange; times (s) optional. Returns the message."""
    g = goal_path_t()
    if not 1 <= len(points) <= goal_path_t.MAX_POINTS:
        raise ValueError(f"points needs 1 to {goal_path_t.MAX_POINTS} points, got {len(points)}")
    if space not in ("joint", "cartesian"):
        raise ValueError(f"space = {space!r} must be 'joint' or 'cartesian'")
    if method not in ("blend", "spline", "quintic", "lagrange"):
        raise ValueError(f"method = {method!r} must be 'blend', 'spline', 'quintic' or 'lagrange'")
    if space == "cartesian":
        rows = []
        for i, p in enumerate(points):
            pos, quat = _pose(f"point {i + 1}", p)
            rows.append(pos + quat)
        dim = goal_path_t.CARTESIAN_DIM
    else:
        dim = len(points[0])
        if not 1 <= dim <= goal_path_t.MAX_DIM:
            raise ValueError(f"a joint point needs 1 to {goal_path_t.MAX_DIM} values, got {dim}")
        for i, p in enumerate(points):
            if len(p) != dim:
                raise ValueError(f"point {i + 1} has {len(p)} values, point 1 has {dim}")
            _finite(f"point {i + 1}", p)
        rows = [list(p) for p in points]
    g.goal_id = goal_id or new_goal_id()
    g.mode = MODES[bool(replace)]
    g.space = goal_path_t.CARTESIAN if space == "cartesian" else goal_path_t.JOINT
    g.method = getattr(goal_path_t, method.upper())
    g.blend_shape = goal_path_t.BLEND_PARABOLIC if shape == "parabolic" else goal_path_t.BLEND_QUARTIC
    g.spline_ends = goal_path_t.SPLINE_NATURAL if ends == "natural" else goal_path_t.SPLINE_CLAMPED
    g.n_points, g.dim = len(rows), dim
    g.points = [r + [0.0] * (goal_path_t.MAX_DIM - dim) for r in rows] + \
        [[0.0] * goal_path_t.MAX_DIM for _ in range(goal_path_t.MAX_POINTS - len(rows))]
    if times:
        _count("times", times, len(rows))
        _finite("times", times)
        if any(b <= a for a, b in zip(times, times[1:])) or times[0] <= 0.0:
            raise ValueError("times must be positive and increasing (s after the start of the motion)")
        g.has_times = 1
        g.times = list(times) + [0.0] * (goal_path_t.MAX_POINTS - len(times))
    else:
        g.has_times = 0
        g.times = [0.0] * goal_path_t.MAX_POINTS
    g.blend_time = _nonneg("blend_time", blend_time)
    g.speed, g.accel = _nonneg("speed", speed), _nonneg("accel", accel)
    g.jerk, g.angular_jerk = _nonneg("jerk", jerk), _nonneg("angular_jerk", angular_jerk)
    g.vel_scale, g.acc_scale = _scale("vel_scale", vel_scale), _scale("acc_scale", acc_scale)
    return g


def make_servo_message(goal_id, pose=None, twist=None, replace=False, timeout_s=0.1):
    """One goal_servo_t of a stream (not sent): a target pose, or a twist
    vx, vy, vz (m/s), wx, wy, wz (rad/s) in the base frame."""
    if (pose is None) == (twist is None):
        raise ValueError("a servo message needs either pose or twist")
    g = goal_servo_t()
    g.goal_id = goal_id
    g.mode = MODES[bool(replace)]
    if pose is not None:
        g.kind = goal_servo_t.POSE
        g.position, g.orientation = _pose("pose", pose)
    else:
        _count("twist", twist, 6)
        _finite("twist", twist)
        g.kind = goal_servo_t.TWIST
        g.orientation = [1.0, 0.0, 0.0, 0.0]
        g.twist = list(twist)
    if not (math.isfinite(timeout_s) and timeout_s > 0):
        raise ValueError("the servo staleness timeout must be > 0")
    g.timeout_us = max(1, int(round(timeout_s * 1e6)))
    return g


class Client:
    """One LCM connection to kinctld (url None: $LCM_DEFAULT_URL, then LCM's default)."""

    def __init__(self, url=None, prefix=DEFAULT_PREFIX, on_setpoint=None, on_status=None):
        self.url, self.prefix = url, prefix
        self.lc = lcm.LCM(url) if url else lcm.LCM()
        self.cond = threading.Condition()
        self.setpoint = None
        self.status = None
        self.n_setpoints = 0
        self.n_statuses = 0
        # Datagrams on the two channels that are not what they claim (garbage,
        # another type, a truncated one): counted and passed over.
        self.n_invalid = 0
        self.events = []  # every status_t with an event, in order
        self._on_setpoint, self._on_status = on_setpoint, on_status
        for suffix, handler in (("SETPOINT", self._handle_setpoint), ("STATUS", self._handle_status)):
            self.lc.subscribe(prefix + suffix, handler).set_queue_capacity(QUEUE_CAPACITY)
        self._run = True
        self._thread = threading.Thread(target=self._loop, name="kinctl-lcm", daemon=True)
        self._thread.start()

    # -- the LCM thread ---------------------------------------------------
    def _loop(self):
        while self._run:
            self.lc.handle_timeout(20)

    def _decode(self, cls, data):
        """cls.decode(data), or None (counted) for anything else on its channel."""
        try:
            return cls.decode(data)
        except (ValueError, struct.error, UnicodeDecodeError, IndexError):
            with self.cond:
                self.n_invalid += 1
            return None

    def _handle_setpoint(self, channel, data):
        sp = self._decode(setpoint_t, data)
        if sp is None:
            return
        if self._on_setpoint:
            self._on_setpoint(sp)
        with self.cond:
            self.setpoint = sp
            self.n_setpoints += 1
            self.cond.notify_all()

    def _handle_status(self, channel, data):
        st = self._decode(status_t, data)
        if st is None:
            return
        if self._on_status:
            self._on_status(st)
        with self.cond:
            self.status = st
            self.n_statuses += 1
            if st.event != EVENTS["NONE"]:
                self.events.append(st)
            self.cond.notify_all()

    def close(self):
        self._run = False
        self._thread.join(2.0)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # -- waiting ----------------------------------------------------------
    def wait_for(self, predicate, timeout):
        """Waits until predicate() (called under the lock) is truthy and
        returns it; None after timeout seconds (None: no limit)."""
        deadline = None if timeout is None else time.monotonic() + timeout
        with self.cond:
            while True:
                r = predicate()
                if r:
                    return r
                left = None if deadline is None else deadline - time.monotonic()
                if left is not None and left <= 0:
                    return None
                self.cond.wait(0.05 if left is None else min(left, 0.05))

    def wait_daemon(self, timeout=2.0):
        """The first setpoint from kinctld; DaemonNotFound after timeout s."""
        sp = self.wait_for(lambda: self.setpoint, timeout)
        if sp is None:
            raise DaemonNotFound(
                f"no setpoint on {self.prefix}SETPOINT within {timeout:g} s on LCM URL "
                f"{self.url or '$LCM_DEFAULT_URL or LCM default'}: is kinctld running with the same "
                f"LCM URL and channel prefix? (start one with: kinctld --no-rt)")
        return sp

    def wait_setpoint(self, predicate, timeout):
        """The first newer setpoint for which predicate(setpoint) holds, or None."""
        with self.cond:
            seen = self.n_setpoints

        def find():
            if self.n_setpoints != seen and self.setpoint is not None and predicate(self.setpoint):
                return self.setpoint
            return None
        return self.wait_for(find, timeout)

    def wait_status(self, timeout=1.0):
        """The next status_t (periodic or event), or None."""
        with self.cond:
            seen = self.n_statuses
        return self.wait_for(lambda: self.status if self.n_statuses != seen else None, timeout)

    def wait_event(self, goal_id, kinds, timeout):
        """The first status about goal_id with an event in kinds (names), or None."""
        codes = {EVENTS[k] for k in kinds if k in EVENTS}

        def find():
            for st in self.events:
                if st.event_goal_id == goal_id and st.event in codes:
                    return st
            return None
        return self.wait_for(find, timeout)

    def wait_answer(self, goal_id, timeout=2.0):
        """ACCEPTED or REJECTED (or, for a very short goal, an end event) for goal_id."""
        return self.wait_event(goal_id, ("ACCEPTED", "REJECTED") + END_EVENTS, timeout)

    def wait_end(self, goal_id, timeout=None):
        """REJECTED, COMPLETED, PREEMPTED, ABORTED or FAULT for goal_id, or None."""
        return self.wait_event(goal_id, ("REJECTED",) + END_EVENTS, timeout)

    @staticmethod
    def event(status):
        return event_name(status.event)

    # -- sending ----------------------------------------------------------
    def publish(self, msg):
        msg.utime = int(time.time() * 1e6)
        self.lc.publish(self.prefix + CHANNELS[type(msg)], msg.encode())

    def goal_joint(self, q, **kw):
        """Sends make_goal_joint(q, **kw); returns the goal id."""
        return self.send(make_goal_joint(q, **kw))

    def goal_line(self, to, **kw):
        """Sends make_goal_line(to, **kw); returns the goal id."""
        return self.send(make_goal_line(to, **kw))

    def goal_arc(self, via, to, **kw):
        """Sends make_goal_arc(via, to, **kw); returns the goal id."""
        return self.send(make_goal_arc(via, to, **kw))

    def goal_path(self, points, **kw):
        """Sends make_goal_path(points, **kw); returns the goal id."""
        return self.send(make_goal_path(points, **kw))

    def send(self, goal):
        """Publishes a goal message; returns its goal id."""
        self.publish(goal)
        return goal.goal_id

    def command(self, name):
        """stop, estop, pause, resume or reset."""
        c = command_t()
        c.command = getattr(command_t, name.upper())
        self.publish(c)
