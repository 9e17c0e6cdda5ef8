# SPDX-License-Identifier: BSD-3-Clause
"""The demo (what scripts/demo.sh runs) to its end: summary, CSV and plot."""
import os

from kinctl_testing import KINCTLD, SLOW

import pytest

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def test_demo_runs_to_the_end(multicast, tmp_path):
    if not KINCTLD:
        pytest.skip("KINCTLD is not set (run through ctest)")
    from kinctl.demo import print_summary, run_demo
    s = run_demo(str(tmp_path), KINCTLD, echo=False, slow=SLOW)
    print_summary(s)
    assert s["cli_exit_codes"] == [0] * len(s["cli_exit_codes"])
    assert s["daemon_exit"] == 0
    # 7 goals: 5 complete, one is preempted by the --replace goal, the last is stopped (aborted).
    assert (s["goals_sent"], s["accepted"], s["completed"], s["preempted"], s["aborted"], s["rejected"]) == \
        (7, 7, 5, 1, 1, 0)
    assert s["missing"] == 0 and s["setpoints"] > 5000
    assert all(m <= l * (1 + 1e-6) for m, l in zip(s["max_qd"], s["qd_limits"]))

    png = s["files"]["png"]
    with open(png, "rb") as f:
        assert f.read(8) == PNG_SIGNATURE
    assert os.path.getsize(png) > 10000
    import matplotlib.image
    img = matplotlib.image.imread(png)
    assert img.shape[0] >= 600 and img.shape[1] >= 1000

    info = s["plot"]
    assert info["rows"] == s["setpoints"] and info["joints"] == 6
    assert info["goals"] == [1, 2, 3, 4, 5, 6, 7]
    q, qd, qdd, path3d, xy, xz = info["axes"][:6]
    for ax, key in ((q, "q"), (qd, "qd"), (qdd, "qdd")):
        assert f"{key} (rad" in ax["ylabel"]
        assert [c for c in ax["curves"] if c.startswith(key)] == [f"{key}{j}" for j in range(1, 7)]
    assert info["axes"][7]["xlabel"] == "time (s)"  # the speed panel, under qdd
    assert "stopping" in qd["curves"]  # the stop and the preemption are shaded
    assert path3d["name"] == "3d" and path3d["title"].startswith("tool path")
    assert (xy["xlabel"], xy["ylabel"]) == ("x (m)", "y (m)")
    assert (xz["xlabel"], xz["ylabel"]) == ("x (m)", "z (m)")
    assert len(xy["curves"]) == 7  # one per goal
    # The jerk panel: each joint's jerk from the logged qdd, the model's limits (the built-in puma560's
    # qddd_max, ten times qdd_max) marked.
    jerk = info["axes"][8]
    assert jerk["curves"] == [f"jerk{j}" for j in range(1, 7)] + ["±qddd_max"] and "jerk" in jerk["ylabel"]
    assert info["jerk_limits"] == [50.0, 50.0, 50.0, 100.0, 100.0, 100.0]
    # The joint moves (goals 1, 5, 6, 7: jerk-limited by default), including the takeover of 5 by the
    # --replace goal 6, keep every joint within its jerk limit from one setpoint to the next.
    from kinctl import logcsv
    cols = logcsv.read(s["files"]["csv"])
    joint_moves, worst = {1, 5, 6, 7}, 0.0
    for k in range(1, len(cols["cycle"])):
        if cols["goal_id"][k - 1] in joint_moves and cols["goal_id"][k] in joint_moves:
            for j in range(1, 7):
                d = abs(cols[f"qdd{j}"][k] - cols[f"qdd{j}"][k - 1]) / 1e-3 / info["jerk_limits"][j - 1]
                worst = max(worst, d)
    assert 0.99 < worst <= 1.0 + 1e-6, worst
