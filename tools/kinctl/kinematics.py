# SPDX-License-Identifier: BSD-3-Clause
"""Every link frame of an arm, from the core's own forward kinematics: the
calculator `kinctl-calc fk --frames` (tools/calc, which links the core and
reads robot description files), run as one `kinctl-calc batch` process; and
the planner's leading joint of joint moves (`kinctl-calc interp joint`).

    from kinctl.kinematics import ArmFK
    with ArmFK(model="puma560") as fk:               # or model_file="models/panda.cfg"
        base, frames, tool = fk.frames([0, 0.7854, -3.1416, 0, 0.7854, 0])
        many = fk.frames_many(list_of_q)             # one pass for a whole log
    leads = planned_leads([(q0, q1), ...], model="puma560")   # 1-based, 0: nothing moves

Poses are 4 x 4 numpy arrays in the world frame (m). The calculator is
kinctl.programs.find("kinctl-calc"): $KINCTL_CALC, else
build/tools/kinctl-calc of this checkout, else kinctl-calc on PATH.
"""
import json
import os
import subprocess
import threading

import numpy as np

from kinctl import programs


class ArmFK:
    """Forward kinematics of every frame through a `kinctl-calc batch` process."""

    def __init__(self, model=None, model_file=None, calc=None):
        if model and model_file:
            raise ValueError("give --model or --model-file, not both")
        self.model, self.model_file = (model or ("puma560" if not model_file else None)), model_file
        if model_file and not os.path.exists(model_file):
            raise ValueError(f"--model-file {model_file}: no such file (models/*.cfg are examples)")
        self.calc = calc or programs.find("kinctl-calc")
        self._proc = None
        self.n_joints = None
        # Probe once: the model exists, and how many joints it has.
        probe = self._request([0.0] * 16)
        if "error" in probe:
            import re
            m = re.search(r"has (\d+) joints", probe["error"])
            if m is None:
                raise ValueError(f"{self.describe()}: {probe['error'].split(': ', 1)[-1]}")
            self.n_joints = int(m.group(1))
        else:
            self.n_joints = 16
        check = self._request([0.0] * self.n_joints)
        if "error" in check:
            raise ValueError(f"{self.describe()}: {check['error'].split(': ', 1)[-1]}")
        self.n_frames = len(check["frames"])

    def describe(self):
        """The arm as the command line names it: "--model puma560" or "--model-file PATH"."""
        return f"--model-file {self.model_file}" if self.model_file else f"--model {self.model}"

    def _req(self, q):
        r = {"op": "fk", "q": [float(v) for v in q], "frames": True}
        if self.model_file:
            r["model_file"] = self.model_file
        else:
            r["model"] = self.model
        return json.dumps(r)

    def _start(self):
        if self._proc is None:
            self._proc = subprocess.Popen([self.calc, "batch"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                          stderr=subprocess.DEVNULL, text=True, bufsize=1)
        return self._proc

    def _request(self, q):
        p = self._start()
        p.stdin.write(self._req(q) + "\n")
        p.stdin.flush()
        line = p.stdout.readline()
        if not line:
            raise RuntimeError(f"{self.calc} batch stopped answering")
        return json.loads(line)

    @staticmethod
    def _parse(ans):
        return (np.array(ans["base"], dtype=float), [np.array(f, dtype=float) for f in ans["frames"]],
                np.array(ans["pose"], dtype=float))

    def _check(self, q):
        if len(q) != self.n_joints:
            raise ValueError(f"{len(q)} joint values for {self.describe()}, which has {self.n_joints} joints: "
                             f"is the daemon running another arm? pass its --model or --model-file")

    def frames(self, q):
        """(base, [frames], tool) at q, each 4 x 4."""
        self._check(q)
        ans = self._request(q)
        if "error" in ans:
            raise ValueError(f"fk at q = {list(q)}: {ans['error']}")
        return self._parse(ans)

    def frames_many(self, qs, progress=False):
        """frames() of every q in qs, through one batch run (a progress bar when progress)."""
        from kinctl.progress import bar
        for q in qs:
            self._check(q)
        p = subprocess.Popen([self.calc, "batch"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                             stderr=subprocess.DEVNULL, text=True)

        def feed():
            try:
                for q in qs:
                    p.stdin.write(self._req(q) + "\n")
                p.stdin.close()
            except BrokenPipeError:
                pass
        writer = threading.Thread(target=feed, daemon=True)
        writer.start()
        lines = []
        with bar(len(qs), "forward kinematics", unit="frame", show=progress) as b:
            for line in p.stdout:
                lines.append(line)
                b.update(1)
        writer.join()
        p.stdout.close()
        p.wait()
        answers = [json.loads(line) for line in lines if line.strip()]
        if len(answers) != len(qs):
            raise RuntimeError(f"{self.calc} batch answered {len(answers)} of {len(qs)} requests")
        for q, a in zip(qs, answers):
            if "error" in a:
                raise ValueError(f"fk at q = {list(q)}: {a['error']}")
        return [self._parse(a) for a in answers]

    def close(self):
        if self._proc is not None:
            self._proc.stdin.close()
            self._proc.wait(5)
            self._proc.stdout.close()
            self._proc = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def jerk_limits(n, model=None, model_file=None, calc=None):
    """Each joint's jerk limit (rad/s^3 or m/s^3) as kinctl's planner reads
    it from the arm's model: the jerk of the first tick of a jerk-limited
    move of that joint alone by 1 mrad (or mm), which starts at +qddd_max
    (kinctl/scurve.h). None where a joint has none (the planner refuses)."""
    if model and model_file:
        raise ValueError("give --model or --model-file, not both")
    where = {"model_file": model_file} if model_file else {"model": model or "puma560"}
    reqs = []
    for j in range(n):
        q1 = [0.0] * n
        q1[j] = 1e-3
        reqs.append(dict(op="interp", kind="joint", q0=[0.0] * n, q1=q1, profile="jerk", dt=1e-4, **where))
    r = subprocess.run([calc or programs.find("kinctl-calc"), "batch"],
                       input="".join(json.dumps(q) + "\n" for q in reqs), capture_output=True, text=True, timeout=60)
    answers = [json.loads(line) for line in r.stdout.splitlines() if line.strip()]
    if len(answers) != n:
        raise RuntimeError(f"kinctl-calc batch answered {len(answers)} of {n} requests: {r.stderr}")
    out = []
    for j, a in enumerate(answers):
        if "error" in a:
            out.append(None)
            continue
        col = a["columns"].index(f"qddd{j + 1}")
        out.append(float(a["rows"][0][col]))
    return out


def planned_leads(moves, model=None, model_file=None, calc=None):
    """The leading joint (1-based; 0 when nothing moves) that kinctl's planner
    picks for a joint move from q0 to q1 with the arm's own limits (the joint
    whose own fastest move takes longest), for each (q0, q1) in moves."""
    if model and model_file:
        raise ValueError("give --model or --model-file, not both")
    if model_file and not os.path.exists(model_file):
        raise ValueError(f"--model-file {model_file}: no such file (models/*.cfg are examples)")
    where = {"model_file": model_file} if model_file else {"model": model or "puma560"}
    # dt far beyond any move: two rows (start and end) per answer.
    text = "".join(json.dumps(dict(op="interp", kind="joint", q0=[float(v) for v in q0], q1=[float(v) for v in q1],
                                   dt=1e6, **where)) + "\n" for q0, q1 in moves)
    r = subprocess.run([calc or programs.find("kinctl-calc"), "batch"], input=text, capture_output=True, text=True,
                       timeout=60)
    answers = [json.loads(line) for line in r.stdout.splitlines() if line.strip()]
    if len(answers) != len(moves):
        raise RuntimeError(f"kinctl-calc batch answered {len(answers)} of {len(moves)} requests: {r.stderr}")
    leads = []
    for a in answers:
        if "error" in a:
            raise ValueError(f"{'--model-file ' + model_file if model_file else '--model ' + where['model']}: "
                             f"{a['error'].split(': ', 1)[-1]}")
        leads.append(int(a["lead"]))
    return leads
