# SPDX-License-Identifier: BSD-3-Clause
"""Link volumes and forbidden zones (core/include/kinctl/zone.h) as polylines
for kinctl plot and kinctl view (kinctl.shapes).

The geometry comes from the core through `kinctl-calc batch`'s zones op with
"geometry": every shape {"kind", "pose" (4 x 4, world), "dim" (zone.h's
sizes), "frame" (volumes: 1-based index into the FK frames)}. Nothing here
parses a zone or computes forward kinematics: --zone and --zones-file go to
the calculator as they are, and a volume follows the arm by composing the
pose of its frame (which the view gets from ArmFK) with its fixed placement
in that frame.

    from kinctl import zonedraw as zd
    geo = zd.geometry(model="puma560", q=q, zones=["sphere:0.5,0,0.3,0.1"])
    polylines = zd.shape_lines(geo["zones"][0])            # list of N x 3 arrays
    shapes = zd.zone_shapes(geo, bounds)                   # kinctl.shapes objects
"""
import json
import subprocess

import numpy as np

from kinctl.shapes import Polyline

ZONE_HELP = ("a forbidden zone to draw (repeatable), world frame, m, as kinctl-calc zones takes it: "
             "box:cx,cy,cz,hx,hy,hz | sphere:cx,cy,cz,r | cylinder:x0,y0,z0,x1,y1,z1,r | "
             "capsule:x0,y0,z0,x1,y1,z1,r | frustum:cx,cy,cz,bx,by,tx,ty,h (upright) | "
             "halfspace:px,py,pz,nx,ny,nz (a point of the plane, its normal out of the zone)")
ZONE_COLOR = "tab:red"
VOLUME_COLOR = "tab:purple"
SEGMENTS = 24  # points per circle


def add_options(parser, volumes=True):
    """--zones-file, --zone and (volumes) --no-volumes on a subcommand's parser."""
    parser.add_argument("--zones-file", default=None, metavar="CFG",
                        help="draw the forbidden zones of a kinctld configuration (controller.zones)")
    parser.add_argument("--zone", action="append", default=[], metavar="KIND:NUMBERS", help=ZONE_HELP)
    if volumes:
        parser.add_argument("--no-volumes", action="store_true",
                            help="do not draw the link volumes (drawn whenever --model or --model-file names "
                                 "the arm)")


def geometry(model=None, model_file=None, q=None, zones_file=None, zones=(), calc=None):
    """{"volumes": [...], "zones": [...]} at joints q, from kinctl-calc's zones op.
    ValueError (the calculator's message) for a bad zone, file or model."""
    from kinctl import programs
    where = {"model_file": model_file} if model_file else {"model": model or "puma560"}
    req = dict(op="zones", q=[float(v) for v in q], geometry=True, zone=list(zones), **where)
    if zones_file:
        req["zones_file"] = zones_file
    r = subprocess.run([calc or programs.find("kinctl-calc"), "batch"], input=json.dumps(req) + "\n",
                       capture_output=True, text=True, timeout=60)
    lines = [ln for ln in r.stdout.splitlines() if ln.strip()]
    if not lines:
        raise RuntimeError(f"kinctl-calc batch gave no answer: {r.stderr.strip()}")
    ans = json.loads(lines[0])
    if "error" in ans:
        import re
        raise ValueError(re.sub(r"^line \d+: ", "", ans["error"]))
    return ans["geometry"]


def zones_only(zones_file=None, zones=(), calc=None):
    """The zones alone (no arm known): the calculator's op needs an arm, so a
    built-in one at its zero pose is given and its volumes dropped."""
    if not zones_file and not zones:
        return []
    return geometry(model="rrr3", q=[0.0, 0.0, 0.0], zones_file=zones_file, zones=zones, calc=calc)["zones"]


# -- one shape, its own frame -------------------------------------------------

def _circle(r, z, n=SEGMENTS, cx=0.0, cy=0.0):
    a = np.linspace(0.0, 2 * np.pi, n + 1)
    return np.column_stack([cx + r * np.cos(a), cy + r * np.sin(a), np.full(n + 1, z)])


def _local_lines(kind, dim):
    """Polylines of a bounded shape in its own frame (zone.h's conventions)."""
    if kind == "box":
        hx, hy, hz = dim[:3]
        return _hull_edges([(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)], -hz,
                           [(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)], hz)
    if kind == "frustum":
        a, b, c, d, h = dim[:5]
        return _hull_edges([(-a, -b), (a, -b), (a, b), (-a, b)], -h, [(-c, -d), (c, -d), (c, d), (-c, d)], h)
    if kind == "sphere":
        r = dim[0]
        ring = _circle(r, 0.0)
        return [ring, ring[:, [0, 2, 1]], ring[:, [2, 0, 1]]]  # the three great circles on the axes' planes
    if kind == "cylinder":
        r, h = dim[:2]
        out = [_circle(r, -h), _circle(r, h)]
        for k in range(4):
            a = k * np.pi / 2
            out.append(np.array([[r * np.cos(a), r * np.sin(a), -h], [r * np.cos(a), r * np.sin(a), h]]))
        return out
    if kind == "capsule":
        r, h = dim[:2]
        out = [_circle(r, -h), _circle(r, h)]
        t = np.linspace(0.0, np.pi, SEGMENTS // 2 + 1)
        for k in range(4):
            a = k * np.pi / 2
            c, s = np.cos(a), np.sin(a)
            side = np.array([[r * c, r * s, -h], [r * c, r * s, h]])
            out.append(side)
            # half circles over the ends, in the plane of the axis and this side
            out.append(np.column_stack([r * c * np.cos(t), r * s * np.cos(t), h + r * np.sin(t)]))
            out.append(np.column_stack([r * c * np.cos(t), r * s * np.cos(t), -h - r * np.sin(t)]))
        return out
    raise ValueError(f"no wireframe for a shape of kind '{kind}'")


def _hull_edges(bottom, zb, top, zt):
    b = np.array([[x, y, zb] for x, y in bottom])
    t = np.array([[x, y, zt] for x, y in top])
    return [np.vstack([b, b[:1]]), np.vstack([t, t[:1]])] + [np.array([b[k], t[k]]) for k in range(4)]


def _apply(T, pts):
    return pts @ T[:3, :3].T + T[:3, 3]


def shape_lines(shape, bounds=None):
    """Polylines (world, N x 3 each) of one geometry shape; a half-space's
    plane clipped to bounds (lo, hi) (needed for it)."""
    T = np.asarray(shape["pose"], dtype=float)
    if shape["kind"] == "halfspace":
        if bounds is None:
            raise ValueError("a half-space is drawn clipped to bounds: give them")
        return halfspace_lines(T, bounds)
    return [_apply(T, p) for p in _local_lines(shape["kind"], shape["dim"])]


# -- half-spaces ---------------------------------------------------------------

def _clip_line(p, d, lo, hi):
    """The segment of the line p + t d inside the box lo..hi, or None."""
    t0, t1 = -np.inf, np.inf
    for k in range(3):
        if abs(d[k]) < 1e-12:
            if p[k] < lo[k] or p[k] > hi[k]:
                return None
            continue
        a, b = (lo[k] - p[k]) / d[k], (hi[k] - p[k]) / d[k]
        t0, t1 = max(t0, min(a, b)), min(t1, max(a, b))
    if t0 >= t1:
        return None
    return np.array([p + t0 * d, p + t1 * d])


def halfspace_lines(T, bounds, hatch=8):
    """The plane of a half-space (pose T: origin on the plane, z its normal)
    inside the box bounds = (lo, hi): its outline (a closed polygon) and
    hatch lines across it; [] when the plane misses the box."""
    lo, hi = np.asarray(bounds[0], float), np.asarray(bounds[1], float)
    o, u, v, n = T[:3, 3], T[:3, 0], T[:3, 1], T[:3, 2]
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    side = (corners - o) @ n
    pts = []
    for i in range(8):
        for j in range(i + 1, 8):
            if bin(i ^ j).count("1") != 1:
                continue
            si, sj = side[i], side[j]
            if si == 0.0:
                pts.append(corners[i])
            if (si < 0.0 < sj) or (sj < 0.0 < si):
                pts.append(corners[i] + (corners[j] - corners[i]) * (si / (si - sj)))
    if side[7] == 0.0:
        pts.append(corners[7])
    if len(pts) < 3:
        return []
    pts = np.unique(np.round(np.array(pts), 12), axis=0)
    c = pts.mean(axis=0)
    ang = np.arctan2((pts - c) @ v, (pts - c) @ u)
    poly = pts[np.argsort(ang)]
    out = [np.vstack([poly, poly[:1]])]
    # Hatching: lines along u at even steps of v across the polygon.
    s = (poly - o) @ v
    for k in range(1, hatch + 1):
        seg = _clip_line(o + (s.min() + (s.max() - s.min()) * k / (hatch + 1)) * v, u, lo, hi)
        if seg is not None:
            out.append(seg)
    return out


# -- drawn objects ---------------------------------------------------------------

def bounded_points(shapes):
    """Every drawn point of the bounded shapes (not half-spaces): M x 3."""
    pts = [p for s in shapes if s["kind"] != "halfspace" for p in shape_lines(s)]
    return np.vstack(pts) if pts else np.zeros((0, 3))


def zone_shapes(zones, bounds):
    """kinctl.shapes Polylines of the zones (half-spaces clipped to bounds,
    a translucent outline and hatching), one per zone, labelled once."""
    out = []
    for z in zones:
        plane = z["kind"] == "halfspace"
        lines = shape_lines(z, bounds)
        if lines:
            out.append(Polyline(lines, color=ZONE_COLOR, alpha=0.35 if plane else 0.8, lw=0.8 if plane else 1.1,
                                label=None if out else "forbidden zones"))
    return out


def volume_shapes(volumes, label="link volumes", color=VOLUME_COLOR, alpha=0.75):
    """One Polyline of all the link volumes as placed in the geometry."""
    lines = [p for s in volumes for p in shape_lines(s)]
    return [Polyline(lines, color=color, alpha=alpha, lw=0.9, label=label)] if lines else []


def joined(lines):
    """Polylines as one N x 3 array with NaN rows between (one artist)."""
    if not lines:
        return np.full((1, 3), np.nan)
    rows = []
    for p in lines:
        rows += [p, np.full((1, 3), np.nan)]
    return np.vstack(rows[:-1])


class MovingVolumes:
    """The link volumes following the arm: each volume's wireframe fixed in
    its frame, placed by the frame's pose at every drawn instant.

    geo: geometry() at joints q0; frames0: ArmFK's frames at the same q0."""

    def __init__(self, volumes, frames0):
        self.parts = []
        for s in volumes:
            k = int(s["frame"]) - 1
            F0 = np.asarray(frames0[k], dtype=float)
            rel = np.linalg.solve(F0, np.asarray(s["pose"], dtype=float))  # the volume in its frame
            for p in _local_lines(s["kind"], s["dim"]):
                self.parts.append((k, _apply(rel, p)))

    def lines(self, frames):
        """Polylines (world) with the frames' poses (ArmFK's frames at some q)."""
        return [_apply(np.asarray(frames[k], dtype=float), p) for k, p in self.parts]

    def points(self, frames):
        return joined(self.lines(frames))


def for_arm(fk, q, zones_file=None, zones=(), volumes=True):
    """(zones, MovingVolumes or None) of the arm of an ArmFK at joints q: the
    zones to draw, and its volumes set to follow its frames (volumes False,
    or an arm without volumes: None)."""
    if not volumes and not zones_file and not zones:
        return [], None
    geo = geometry(model=fk.model, model_file=fk.model_file, q=q, zones_file=zones_file, zones=zones, calc=fk.calc)
    moving = MovingVolumes(geo["volumes"], fk.frames(q)[1]) if volumes and geo["volumes"] else None
    return geo["zones"], moving
