# SPDX-License-Identifier: BSD-3-Clause
"""controller.can: read and checked at start-up (no interface needed for
--check), each problem one line naming the file and line, exit 2; an
interface that cannot be opened is a run-time failure, exit 1. And the
controller's own check of the whole, which names the joint and line it
refuses."""
import re

import pytest

from kinctl_testing import run_kinctld

J6 = ", ".join(f"{{ node = {n}; counts_per_unit = 100000.0; }}" for n in range(1, 7))
# Six drives fit a 1 Mbit/s bus at 1 kHz only with a bus cycle every 2 ms
# and TPDOs every 2nd SYNC (daemon/can_budget.h).
FITS = "sync_every = 2; tpdo_every = 2;"


def frame_bits(n):
    """Worst-case bits of a classic 11-bit CAN frame with n data bytes, stuff
    bits included (Davis et al. 2007, eq. 1)."""
    return 47 + 8 * n + (34 + 8 * n - 1) // 4


def write(tmp_path, text):
    p = tmp_path / "k.cfg"
    p.write_text(text)
    return str(p)


def can(body):
    return "controller = {\n  can = {\n" + body + "\n  };\n};\n"


def test_can_config_check(tmp_path):
    r = run_kinctld("--config", write(tmp_path, can(f'interface = "vcan7"; {FITS} joints = ( {J6} );')), "--check",
                    "--model", "puma560")
    assert r.returncode == 0, r.stderr
    # SYNC (empty) + 6 RPDO1 of 6 bytes + 6 TPDO1 of 6 bytes every 2nd SYNC,
    # in a 2000 us bus cycle at 1 bit/us
    share = 100.0 * (frame_bits(0) + 6 * frame_bits(6) + 6 * frame_bits(6) / 2) / 2000.0
    m = re.search(r"CAN vcan7 \(6 drives, 1000000 bit/s, bus (\d+) % of a 2000 us bus cycle\)", r.stdout)
    assert m, r.stdout
    assert abs(int(m.group(1)) - share) <= 0.5 + 1e-9, (m.group(1), share)
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
    ('interface = "vcan0";\n    bitrate = 5;', "k.cfg:4: controller.can.bitrate = 5 is outside"),
    ('interface = "vcan0";\n    sync_counter = 1;',
     "k.cfg:4: controller.can.sync_counter = 1 is not a SYNC counter: 0 (empty SYNC) or 2 .. 240"),
    ('interface = "vcan0";\n    sync_counter = 241;', "k.cfg:4: controller.can.sync_counter = 241 is outside 0 .. 240"),
    ('interface = "vcan0";\n    tpdo_every = 0;', "k.cfg:4: controller.can.tpdo_every = 0 is outside 1 .. 240"),
    ('interface = "vcan0";\n    shutdown_nmt = "off";',
     'k.cfg:4: controller.can.shutdown_nmt must be "pre_operational" or "stop", not "off"'),
    ('interface = "vcan0";\n    lost_master_reaction = -2;',
     "k.cfg:4: controller.can.lost_master_reaction = -2 is outside -1 .. 32767"),
    ('interface = "vcan0";\n    bus_speed = 1;', 'k.cfg:4: unknown key "bus_speed" in controller.can'),
    ('interface = "vcan0"; joints = ( { node = 1; counts_per_unit = 1.0; identity = [1, 2, 3]; } );',
     "controller.can.joints[0].identity must be [vendor, product, revision, serial] (0: unchecked)"),
    ('interface = "vcan0"; joints = ( { node = 1; counts_per_unit = 1.0;\n'
     '      writes = ( { index = 0x6065; size = 3; value = 16777216; } ); } );',
     "controller.can.joints[0].writes[0].value = 16777216 is outside"),
    ('interface = "vcan0"; joints = ( { node = 1; counts_per_unit = 1.0;\n'
     '      writes = ( { index = 0x6065; size = 4; } ); } );', "controller.can.joints[0].writes[0]"),
    ('interface = "vcan0"; joints = ( { node = 1; counts_per_unit = 1.0;\n'
     '      writes = ( { index = 0x6065; subindex = 0; size = 5; value = 1; } ); } );',
     "controller.can.joints[0].writes[0].size = 5 is outside 1 .. 4"),
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


def test_can_bus_budget_refused(tmp_path):
    """Six drives on a 1 Mbit/s bus at 1 kHz need 143.5 % of it: refused at
    start, with the figures and what would fit."""
    r = run_kinctld("--config", write(tmp_path, can(f'    interface = "vcan0"; joints = ( {J6} );')), "--check",
                    "--no-rt", "--model", "puma560")
    assert r.returncode == 2, (r.returncode, r.stderr)
    need = frame_bits(0) + 6 * (frame_bits(6) + frame_bits(6))  # bits = us at 1 Mbit/s
    assert need == 1435
    assert (f"controller.can: bus budget: 6 drives need {need} us of a 1000 us bus cycle at 1000000 bit/s "
            f"({100.0 * need / 1000:.1f} %") in r.stderr, r.stderr
    # 70 % of 1000 us: (700 - 55) / 230 = 2.8 drives; 1435 / 0.7 = 2050 us: sync_every 3; the RPDOs alone
    # (55 + 6 x 115 = 745 us) exceed 700, so TPDOs less often cannot help
    assert "would fit: 2 drives, or sync_every 3 (a 3000 us bus cycle), and TPDOs less often cannot make it fit" \
        in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr


def test_can_interpolation_period_refused(tmp_path):
    """A bus cycle of 256 us has no 0x60C2 form (value 0..255 times a power
    of ten seconds): refused, naming it."""
    r = run_kinctld("--config", write(tmp_path, can('    interface = "vcan0"; joints = ( { node = 1; '
                                                    'counts_per_unit = 1000.0; }, { node = 2; '
                                                    'counts_per_unit = 1000.0; } );')),
                    "--check", "--no-rt", "--model", "planar2", "--period-us", "256")
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert "is not an interpolation period 0x60C2 can say" in r.stderr, r.stderr


def test_can_interface_missing_exit_1(tmp_path):
    cfg = write(tmp_path, can(f'    interface = "nosuchcan9"; {FITS} joints = ( {J6} );'))
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
