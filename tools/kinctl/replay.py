# SPDX-License-Identifier: BSD-3-Clause
"""`kinctl replay`: runs kinctl-replay (tools/replay, C) on a recorded log.

kinctl-replay feeds the goals and commands of the log through kc_ctrl_step
with the daemon's own configuration reader and goal conversion, and
compares every setpoint bit for bit; this wrapper finds it, shows its
progress and passes its verdict and exit status through.
"""
import subprocess
import sys

from kinctl import programs


def run(log, daemon_args, progress=True, out=sys.stdout):
    """Runs the replay; returns (exit status, its stdout text)."""
    from tqdm import tqdm
    argv = [programs.find("kinctl-replay"), "--progress", log] + list(daemon_args)
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    bar = None
    errors = []
    for line in proc.stderr:
        parts = line.split()
        if len(parts) == 3 and parts[0] == "progress":
            done, total = int(parts[1]), int(parts[2])
            if progress and bar is None:
                bar = tqdm(total=total, unit="cycle", desc="replay", dynamic_ncols=True, disable=None)
            if bar is not None:
                bar.update(done - bar.n)
        else:
            errors.append(line)
    text = proc.stdout.read()
    rc = proc.wait()
    if bar is not None:
        bar.close()
    if errors:
        sys.stderr.write("".join(errors))
    out.write(text)
    out.flush()
    return rc, text
