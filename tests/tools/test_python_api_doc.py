# SPDX-License-Identifier: BSD-3-Clause
"""docs/python-api.md's example, run as written against a real kinctld
(the built-in puma560): the page's ```python block, extracted, in a
subprocess with $LCM_DEFAULT_URL naming the daemon's URL."""
import os
import re
import subprocess
import sys

DOC = os.path.join(os.path.dirname(__file__), "..", "..", "docs", "python-api.md")


def example_code():
    blocks = re.findall(r"^```python\n(.*?)^```$", open(DOC).read(), flags=re.S | re.M)
    assert len(blocks) == 1, f"{DOC}: {len(blocks)} python blocks, the test runs exactly one"
    return blocks[0]


def test_python_api_example_runs(daemon, tmp_path):
    d = daemon()
    script = tmp_path / "example.py"
    script.write_text(example_code())
    env = dict(os.environ, LCM_DEFAULT_URL=d.url)
    r = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120, env=env)
    assert r.returncode == 0, r.stdout + r.stderr
    out = r.stdout
    # what the example prints is what the daemon answered
    assert out.startswith("arm: 6 joints, state IDLE"), out
    assert re.search(r"^joint move \d+ COMPLETED$", out, re.M), out
    assert re.search(r"^line \d+ ACCEPTED line \d+ ACCEPTED$", out, re.M), out
    assert "ends: COMPLETED COMPLETED" in out and "arc COMPLETED path COMPLETED" in out, out
    assert re.search(r"^bad goal: REJECTED joint_limit: ", out, re.M), out
    assert "servo: ABORTED servo_timeout: " in out, out
    assert "preempted: PREEMPTED" in out and "after stop: ABORTED" in out, out
    assert "status: state IDLE queue 0" in out, out
    n = int(re.search(r"^setpoints seen: (\d+)", out, re.M).group(1))
    assert n > 1000, out
