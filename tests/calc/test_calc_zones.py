# SPDX-License-Identifier: BSD-3-Clause
"""kinctl-calc zones (and the zones batch op): distances of the built-in
arms' capsules to every zone kind against an independent computation here,
the world geometry moving rigidly with the frames, and bad input.

Independent reference: a capsule is a segment p(t) swept by a radius r;
its distance to a convex zone is min_t dist(p(t), zone) - r, and
dist(p(t), zone) is convex in t, so a golden-section search finds the
minimum. Point distances are closed forms (box: clamping in the box frame,
sphere, cylinder: the (rho, z) rectangle, capsule: the nearest point of its
segment, half-space: the height above the plane), the frustum's the same
search over its rectangular slices.

Environment as test_calc.py: KINCTL_CALC, KINCTL_REAL.
"""
import json
import math
import os
import random
import subprocess

CALC = os.environ.get("KINCTL_CALC", "kinctl-calc")
FLOAT = os.environ.get("KINCTL_REAL", "double") == "float"
TOL = 1e-4 if FLOAT else 1e-7


def run(args, stdin=None):
    return subprocess.run([CALC] + [str(a) for a in args], input=stdin, capture_output=True, text=True, timeout=120)


def csv(values):
    return ",".join(repr(float(v)) for v in values)


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def norm(a):
    return math.sqrt(dot(a, a))


def col(T, k):
    return [T[0][k], T[1][k], T[2][k]]


def local(T, p):
    """p in the frame of the 4x4 pose T."""
    d = sub(p, col(T, 3))
    return [dot(col(T, k), d) for k in range(3)]


def unit(v):
    n = norm(v)
    return [x / n for x in v]


# Zones as the CLI takes them, with a point distance for each.
def zone_point_distance(spec, p):
    kind, nums = spec.split(":")
    v = [float(x) for x in nums.split(",")]
    if kind == "sphere":
        return max(norm(sub(p, v[0:3])) - v[3], 0.0)
    if kind == "box":
        e = [max(abs(p[i] - v[i]) - v[3 + i], 0.0) for i in range(3)]
        return norm(e)
    if kind == "cylinder":
        a, b, r = v[0:3], v[3:6], v[6]
        axis = sub(b, a)
        length = norm(axis)
        u = unit(axis)
        c = [(a[i] + b[i]) / 2 for i in range(3)]
        d = sub(p, c)
        z = dot(d, u)
        rho = norm([d[i] - z * u[i] for i in range(3)])
        return math.hypot(max(rho - r, 0.0), max(abs(z) - length / 2, 0.0))
    if kind == "capsule":
        a, b, r = v[0:3], v[3:6], v[6]
        ab = sub(b, a)
        t = min(max(dot(sub(p, a), ab) / dot(ab, ab), 0.0), 1.0)
        return max(norm(sub(p, [a[i] + t * ab[i] for i in range(3)])) - r, 0.0)
    if kind == "frustum":
        # The slice at height s is a rectangle whose half extents go linearly
        # from the bottom's to the top's; the distance to the slice is
        # convex in s (the frustum is convex): ternary search.
        c, bottom, top, h = v[0:3], v[3:5], v[5:7], v[7]
        d = sub(p, c)

        def to_slice(s):
            w = (s + h) / (2 * h)
            e = [max(abs(d[i]) - (bottom[i] + w * (top[i] - bottom[i])), 0.0) for i in range(2)]
            return math.sqrt(e[0] ** 2 + e[1] ** 2 + (d[2] - s) ** 2)

        return max(convex_min(to_slice, -h, h), 0.0)
    if kind == "halfspace":
        n = unit(v[3:6])
        return max(dot(sub(p, v[0:3]), n), 0.0)
    raise ValueError(kind)


def convex_min(f, lo, hi):
    """The minimum of a convex f on [lo, hi] (golden-section search)."""
    g = (math.sqrt(5) - 1) / 2
    a, b = lo, hi
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(90):
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = f(d)
    return min(fc, fd, f(lo), f(hi))


def capsule_distance(shape, spec):
    T, r, h = shape["pose"], shape["dim"][0], shape["dim"][1]
    c, z = col(T, 3), col(T, 2)

    def f(t):
        return zone_point_distance(spec, [c[i] + t * z[i] for i in range(3)])

    return max(convex_min(f, -h, h) - r, 0.0)


ZONES = [
    "halfspace:0,0,0.05,0,0,1",
    "box:0.45,0.1,0.5,0.1,0.15,0.2",
    "sphere:0.2,-0.4,0.7,0.12",
    "cylinder:-0.3,0.3,0,-0.3,0.3,1.2,0.08",
    "halfspace:0.7,0,0,-1,0,0",
    "capsule:0.3,-0.3,0.2,0.5,-0.1,0.9,0.06",
    "frustum:-0.1,0.45,0.45,0.2,0.12,0.06,0.1,0.25",
]

MODELS = {
    "puma560": [(-2.7, 2.7), (-0.7, 3.8), (-3.8, 0.7), (-1.9, 2.9), (-1.7, 1.7), (-4.6, 4.6)],
    "panda": [(-2.8, 2.8), (-1.7, 1.7), (-2.8, 2.8), (-3.0, -0.1), (-2.8, 2.8), (0.0, 3.7), (-2.8, 2.8)],
    "rrr3": [(-3.1, 3.1)] * 3,
    "rm01": [(-3.1, 3.1)] * 6,
}


def zones_answer(model, q, extra=()):
    args = ["zones", "--model", model, "--q", csv(q), "--geometry"]
    for z in ZONES:
        args += ["--zone", z]
    r = run(args + list(extra))
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def test_capsule_distances_against_independent_reference():
    rng = random.Random(8)
    checked = touching = 0
    for model, lim in MODELS.items():
        for _ in range(12):
            q = [rng.uniform(a, b) for a, b in lim]
            out = zones_answer(model, q)
            vols = out["geometry"]["volumes"]
            assert len(out["distances"]) == len(vols) == len(out["volumes"])
            best = (math.inf, None)
            for i, shape in enumerate(vols):
                assert len(out["distances"][i]) == len(ZONES)
                for k, spec in enumerate(ZONES):
                    got = out["distances"][i][k]
                    best = min(best, (got, (i, k)), key=lambda x: x[0])
                    if shape["kind"] != "capsule":
                        continue
                    ref = capsule_distance(shape, spec)
                    assert abs(got - ref) <= TOL, (model, q, i, spec, got, ref)
                    checked += 1
                    touching += ref == 0.0
            closest = out["closest"]
            assert (closest["volume"], closest["zone"]) == best[1]
            assert abs(closest["distance"] - best[0]) <= 1e-12
            assert out["clear"] == (best[0] >= out["margin"])
    assert checked > 1000
    assert touching > 20  # the poses reach into zones too


def test_geometry_moves_with_its_frame():
    """A volume's pose relative to its frame (fk --frames) is the same at
    every q: it is attached to that frame."""
    rng = random.Random(9)
    rel = {}
    for _ in range(5):
        q = [rng.uniform(a, b) for a, b in MODELS["panda"]]
        out = zones_answer("panda", q)
        fk = run(["fk", "--model", "panda", "--q", csv(q), "--frames"])
        frames = json.loads(fk.stdout)["frames"]
        for i, shape in enumerate(out["geometry"]["volumes"]):
            F, W = frames[int(shape["frame"]) - 1], shape["pose"]
            # F^-1 W: rotation F_R^T W_R, translation F_R^T (W_t - F_t)
            R = [[dot(col(F, a), col(W, b)) for b in range(3)] for a in range(3)]
            t = local(F, col(W, 3))
            flat = [x for row in R for x in row] + t
            if i in rel:
                assert max(abs(a - b) for a, b in zip(flat, rel[i])) <= (1e-5 if FLOAT else 1e-9)
            rel[i] = flat
    # panda's hand is a box, the rest capsules
    kinds = [s["kind"] for s in out["geometry"]["volumes"]]
    assert kinds.count("box") == 1 and kinds.count("capsule") == len(kinds) - 1
    assert [z["kind"] for z in out["geometry"]["zones"]] == [spec.split(":")[0] for spec in ZONES]


def test_margin_and_batch_op():
    q = [0, 0.8, -2.4, 0, 0.6, 0]
    cli = zones_answer("puma560", q, ["--margin", "0.5"])
    assert cli["margin"] == 0.5 and cli["clear"] is False
    req = {"op": "zones", "model": "puma560", "q": q, "zone": ZONES, "margin": 0.5, "geometry": True, "id": 4}
    r = run(["batch"], json.dumps(req) + "\n" + json.dumps(dict(req, zone=["blob:1"])) + "\n")
    assert r.returncode == 0, r.stderr
    lines = [json.loads(x) for x in r.stdout.splitlines()]
    assert lines[0]["distances"] == cli["distances"]
    assert lines[0]["id"] == 4
    assert "unknown kind" in lines[1]["error"]


def test_bad_input():
    base = ["zones", "--model", "puma560", "--q", "0,0,0,0,0,0"]
    for zone, msg in [
        ("blob:1,2", "unknown kind"),
        ("sphere:0,0,0", "takes 4 numbers"),
        ("sphere:0,0,0,-1", "positive"),
        ("cylinder:0,0,0,0,0,0,0.1", "nonzero"),
        ("halfspace:0,0,0,0,0,0", "nonzero"),
        ("capsule:1,2,3,1,2,3,0.1", "nonzero"),
        ("frustum:0,0,0,0.2,0.2,0.1,0.1", "takes 8 numbers"),
        ("frustum:0,0,0,0.2,0.2,0.1,0.1,-0.3", "positive"),
        ("box", "KIND:NUMBERS"),
    ]:
        r = run(base + ["--zone", zone])
        assert r.returncode == 2, zone
        assert msg in r.stderr, (zone, r.stderr)
    r = run(base + ["--margin", "-1"])
    assert r.returncode == 2 and "margin" in r.stderr
    r = run(["zones", "--help"])
    assert r.returncode == 0 and "Example: kinctl-calc zones" in r.stdout


def test_zones_file(tmp_path):
    cfg = tmp_path / "kinctld.cfg"
    cfg.write_text(
        "controller = {\n  zones = {\n    margin = 0.05;\n    list = (\n"
        '      { name = "table"; shape = "halfspace"; point = [0.0, 0.0, 0.05]; normal = [0.0, 0.0, 1.0]; },\n'
        '      { name = "ball"; shape = "sphere"; xyz = [0.2, -0.4, 0.7]; radius = 0.12; }\n    );\n  };\n};\n'
    )
    q = [0.3, 0.9, -2.2, 0.1, 0.5, 0.0]
    a = json.loads(run(["zones", "--model", "puma560", "--q", csv(q), "--zones-file", cfg]).stdout)
    b = json.loads(
        run(["zones", "--model", "puma560", "--q", csv(q), "--zone", ZONES[0], "--zone", ZONES[2], "--margin", "0.05"]).stdout
    )
    assert a == b
    # --zone adds to the file's zones; a bad file names its line
    c = json.loads(run(["zones", "--model", "puma560", "--q", csv(q), "--zones-file", cfg, "--zone", ZONES[1]]).stdout)
    assert [row[:2] for row in c["distances"]] == a["distances"] and len(c["distances"][0]) == 3
    bad = tmp_path / "bad.cfg"
    bad.write_text('controller = {\n  zones = {\n    list = ( { shape = "cone"; } );\n  };\n};\n')
    r = run(["zones", "--model", "puma560", "--q", csv(q), "--zones-file", bad])
    assert r.returncode == 2 and "bad.cfg:3: zone 1: unknown shape" in r.stderr
