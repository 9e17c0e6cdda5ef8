# SPDX-License-Identifier: BSD-3-Clause
"""Writes the seed corpora of the message and controller harnesses.

  PYTHONPATH=build/lcmtypes/python:tools .venv/bin/python tests/fuzz/make_seeds.py

msg/: one valid datagram of every client type, built with the kinctl Python
API, behind the harness's type byte (KD_MSG_GOAL_JOINT = 0 ... COMMAND = 5),
plus a few broken ones. ctrl/: byte strings that drive fuzz_ctrl.c through
each goal kind with and without replace and every command (random bytes
from a fixed seed, with the record headers set). Other corpora are text
files written by hand. Reruns write the same files.
"""
import os
import random
import sys

from kinctl import client
from kinctl_msgs import command_t

HERE = os.path.dirname(os.path.abspath(__file__))
Q = [0.1, 0.8, -2.4, 0.1, 0.6, 0.2]
POSE = [0.45, 0.1, 0.5, 0.7071068, 0.0, 0.7071068, 0.0]


def write(corpus, name, data):
    d = os.path.join(HERE, "corpus", corpus)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def msg_seeds():
    cmd = command_t()
    cmd.command = command_t.STOP
    msgs = {
        "joint": (0, client.make_goal_joint(Q, goal_id=1, vel_scale=0.5, acc_scale=0.5)),
        "joint-replace": (0, client.make_goal_joint(Q, goal_id=2, replace=True)),
        "line": (1, client.make_goal_line(POSE, goal_id=3, speed=0.2)),
        "arc": (2, client.make_goal_arc([0.5, 0.2, 0.55], POSE, goal_id=4)),
        "path-joint": (3, client.make_goal_path([Q, [0.2, 0.7, -2.3, 0.0, 0.5, 0.1]], goal_id=5)),
        "path-cart": (3, client.make_goal_path([POSE, [0.5, 0.0, 0.55] + POSE[3:]], space="cartesian",
                                               method="spline", times=[1.0, 2.0], goal_id=6)),
        "servo-pose": (4, client.make_servo_message(7, pose=POSE)),
        "servo-twist": (4, client.make_servo_message(8, twist=[0.0, 0.05, 0.0, 0.0, 0.0, 0.1])),
        "command": (5, cmd),
    }
    for name, (t, m) in msgs.items():
        data = m.encode()
        write("msg", name, bytes([t]) + data)
        write("msg", name + "-truncated", bytes([t]) + data[:-3])
        write("msg", name + "-other-type", bytes([(t + 1) % 6]) + data)


def ctrl_seeds():
    rng = random.Random(20261201)
    for kind in range(6):
        for replace in (0, 1):
            b = bytearray()
            for rec in range(6):
                op = 0x40 | rng.randrange(64) if rec % 2 == 0 else rng.randrange(64)
                b.append(op)
                if op & 0x40:
                    b.append(kind)       # kind
                    b.append(replace)    # replace
                    b += bytes(rng.randrange(256) % 255 for _ in range(300))
            write("ctrl", f"kind{kind}-replace{replace}", bytes(b))
    for cmd in range(1, 6):
        b = bytearray([0x40 | 20, 0, 0] + [rng.randrange(255) for _ in range(200)])
        b += bytes([0xC0 | 10, cmd, 0, 0] + [rng.randrange(255) for _ in range(200)])
        b += bytes([0xC0 | 30, 5, 1, 1] + [rng.randrange(255) for _ in range(200)])
        write("ctrl", f"command{cmd}", bytes(b))


if __name__ == "__main__":
    msg_seeds()
    ctrl_seeds()
    print("seeds written under", os.path.join(HERE, "corpus"), file=sys.stderr)
