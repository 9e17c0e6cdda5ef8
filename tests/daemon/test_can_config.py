# SPDX-License-Identifier: BSD-3-Clause
"""controller.can: read and checked at start-up (no interface needed for
--check), each problem one line naming the file and line, exit 2; an
interface that cannot be opened is a run-time failure, exit 1. And the
controller's own check of the whole, which names the joint and line it
refuses."""
import pytest

from kinctl_testing import run_kinctld

J6 = ", ".join(f"{{ node = {n}; counts_per_unit = 100000.0; }}" for n in range(1, 7))


def write(tmp_path, text):
    p = tmp_path / "k.cfg"
    p.write_text(text)
    return str(p)


def can(body):
    return "controller = {\n  can = {\n" + body + "\n  };\n};\n"


def test_can_config_check(tmp_path):
    r = run_kinctld("--config", write(tmp_path, can(f'interface = "vcan7"; joints = ( {J6} );')), "--check",
                    "--model", "puma560")
    assert r.returncode == 0, r.stderr
    assert "CAN vcan7" in r.stdout
    r = run_kinctld("--check", "--model", "puma560")
    assert "CAN off" in r.stdout


@pytest.mark.parametrize("body,expect", [
    (f'interface = "vcan0"; joints = ( {J6.rsplit(", {", 1)[0]} );',
     'k.cfg:3: controller.can.joints has 5 drives, the arm "puma560" has 6 joints'),
    ('interface = "vcan0"; joints = ( { node = 1; counts_per_unit = 1.0; }, { node = 1; counts_per_unit = 1.0; } );',
     "k.cfg:3: controller.can.joints[1].node = 1 is also joint 1's"),
    (f'interface = "vcan0"; master_id = 3; joints = ( {J6} );',
     "k.cfg:3: controller.can.joints[2].node = 3 (joint 3) is the master's"),
    ('interface = "vcan0";\n    on_error = "panic";', 'k.cfg:4: controller.can.on_error must be "stop" or "lcm_only"'),
    ('interface = "vcan0";\n    sync_every = 0;', "k.cfg:4: controller.can.sync_every = 0 is outside 1 .. 1000"),
    ('interface = "vcan0";\n    master_id = 128;', "controller.can.master_id = 128 is outside 1 .. 127"),
    ('interface = "vcan0";\n    bitrate = 1000000;', 'k.cfg:4: unknown key "bitrate" in controller.can'),
    ('interface = "an-interface-name-too-long";', "is longer than 15 characters"),
    ('interface = "vcan0"; joints = ( { node = 1; } );', "controller.can.joints[0] needs node and counts_per_unit"),
    ('interface = "vcan0"; joints = ( { node = 1; counts_per_unit = 1.0; sign = 0; } );',
     "controller.can.joints[0].sign must be 1 or -1"),
    ('interface = "vcan0"; joints = ( { node = 200; counts_per_unit = 1.0; } );',
     "controller.can.joints[0].node = 200 is outside 1 .. 127"),
    ("interface = \"vcan0\"; joints = ( " + ", ".join(f"{{ node = {n}; counts_per_unit = 1e9; }}"
                                                      for n in range(1, 7)) + " );",
     "k.cfg:3: controller.can.joints[0]: joint 1's range [-2.79253, 2.79253] or speed 2 at 1e+09 counts per unit "
     "does not fit int32 counts"),
    ('interface = "vcan0";\n    feedback = { enable = true; following_error = -1.0; };',
     "controller.can.feedback.following_error = -1 is outside"),
])
def test_can_config_errors(tmp_path, body, expect):
    r = run_kinctld("--config", write(tmp_path, can("    " + body)), "--check", "--no-rt", "--model", "puma560")
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert expect in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr


def test_can_interface_missing_exit_1(tmp_path):
    cfg = write(tmp_path, can(f'    interface = "nosuchcan9"; joints = ( {J6} );'))
    r = run_kinctld("--config", cfg, "--no-rt", "--model", "puma560", "--lcm-url", "udpm://239.255.77.251:7998?ttl=0")
    assert r.returncode == 1, r.stderr
    assert 'kinctld: cannot open CAN interface "nosuchcan9"' in r.stderr


ARM = """robot = {
  name = "arm";
  angles = "rad";
  dh = (
    { type = "revolute"; a = 0.0; alpha = 1.5708; d = 0.3; theta = 0.0; name = "shoulder";
      limits = { q = [-3.0, 3.0]; qd = 2.0; qdd = 5.0; }; },
    { type = "revolute"; a = 0.4; alpha = 0.0; d = 0.0; theta = 0.0; name = "elbow";
      limits = { q = [-3.0, 3.0]; %s }; }
  );
};
"""


@pytest.mark.parametrize("limits,expect", [
    ("qd = 2.0;", 'k.cfg:7: robot "arm" joint 2 (elbow) has no acceleration limit (limits.qdd)'),
    ("qdd = 5.0;", 'k.cfg:7: robot "arm" joint 2 (elbow) has no velocity limit (limits.qd)'),
])
def test_controller_refusal_names_the_joint_and_line(tmp_path, limits, expect):
    """A joint without a rate limit (a URDF imported without --acc, say): the
    refusal names the joint, its line and the missing limit, not the whole."""
    r = run_kinctld("--config", write(tmp_path, ARM % limits), "--check", "--no-rt")
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert r.stderr.strip().endswith("/" + expect + ": the controller needs a finite one for every joint"), r.stderr
