# SPDX-License-Identifier: BSD-3-Clause
"""`kinctl import-urdf`: a robot description file (models/README.md, read by
core/desc) from a URDF, parsed with yourdfpy.

The chain from the base link to the tool link becomes `elements`: the
elementary transforms Rx Ry Rz Tx Ty Tz of seed 003. A URDF joint is

    T_parent_child(q) = Trans(xyz) Rz(yaw) Ry(pitch) Rx(roll) M(axis, q)

with M a rotation about (revolute, continuous) or a translation along
(prismatic) the unit vector `axis`, or the identity (fixed). The elements
only move about or along z, so an axis a is first turned onto z by a
constant rotation A = Rz(phi) Ry(theta) (A z = a): M(a, q) = A Mz(q) A^T.
Every constant between two joints (the fixed joints, the next origin, the
A^T of one joint and the A of the next) is multiplied into one rigid
transform and written as at most Tx Ty Tz Rz Ry Rx; what follows the last
joint is the description's tool transform. Each joint ends a frame, so
`kinctl-calc fk --frames` gives the pose of every moving link's frame A.

Limits: q and qd as the URDF gives them (qd of --vel where it gives none);
qdd, which URDF has not, is --acc, or ACC_PER_VEL times the joint's qd.

Link volumes (kinctl/zone.h) come from the links' <collision> geometry: a
link rigidly behind joint k (through fixed joints) lies in frame k, at
A_k^T (the rotation that turned the axis onto z, undone) times the fixed
origins times the collision's own origin. sphere -> sphere, cylinder (axis
z, length l) -> cylinder from -l/2 to l/2, capsule (a <capsule radius
length> as Drake's URDFs write it; yourdfpy drops it, so the XML is read
directly) -> capsule, box (full size) -> box with half the size. Meshes and
links before the first joint (they never move) give none; the summary and
the file's header name the links without a volume.
"""
import math
import os
import sys

import numpy as np

SUPPORTED = ("revolute", "continuous", "prismatic", "fixed")
ACC_PER_VEL = 5.0  # qdd = 5 x qd (1/s) where --acc is not given
MAX_VOLUMES = 32  # KC_MAX_VOLUMES (core/include/kinctl/chain.h)
ZERO = 1e-15  # a constant this small (m or rad) is rounding: left out


class URDFError(ValueError):
    """A URDF that cannot become a serial chain: exit 2 with the text."""


def load(path):
    import yourdfpy
    import xml.etree.ElementTree as ET
    if not os.path.isfile(path):
        raise URDFError(f"{path}: no such file")
    try:  # the plain XML first: yourdfpy logs its own parse errors before raising
        root = ET.parse(path).getroot()
    except (ET.ParseError, UnicodeDecodeError) as e:
        raise URDFError(f"{path}: not a readable URDF (not XML: {e})") from None
    if root.tag != "robot":
        raise URDFError(f"{path}: not a URDF (its root element is <{root.tag}>, not <robot>)")
    # yourdfpy refuses <capsule> (not in ROS's URDF, written by Drake's): the
    # chain does not need collisions, which collisions() reads from the XML.
    source = path
    capsules = [c for link in root.findall("link") for c in link.findall("collision")
                if c.find("geometry/capsule") is not None]
    if capsules:
        for link in root.findall("link"):
            for c in link.findall("collision"):
                if c in capsules:
                    link.remove(c)
        import io
        source = io.BytesIO(ET.tostring(root))
    try:
        return yourdfpy.URDF.load(source, build_scene_graph=True, load_meshes=False, load_collision_meshes=False)
    except Exception as e:  # yourdfpy raises lxml and its own errors
        raise URDFError(f"{path}: not a readable URDF ({type(e).__name__}: {e})") from None


def chain_joints(robot, base=None, tip=None):
    """The joints from base to tip, in order. Raises URDFError naming the
    links to choose from when base or tip is unknown or ambiguous."""
    joints = robot.robot.joints
    links = [link.name for link in robot.robot.links]
    by_child = {j.child: j for j in joints}
    parents = {j.parent for j in joints}
    root = robot.base_link
    base = base or root
    for what, name in (("--base", base), ("--tip", tip)):
        if name is not None and name not in links:
            raise URDFError(f"{what} {name}: no such link (links: {', '.join(links)})")
    if tip is None:
        leaves = [link for link in links if link not in parents and link != base]
        if len(leaves) != 1:
            raise URDFError(f"the URDF has {len(leaves)} end links: give --tip (one of {', '.join(leaves)})")
        tip = leaves[0]
    path = []
    link = tip
    while link != base:
        if link not in by_child:
            raise URDFError(f"link {tip} is not below {base}: no chain between them")
        j = by_child[link]
        path.append(j)
        link = j.parent
    path.reverse()
    for j in path:
        if j.type not in SUPPORTED:
            raise URDFError(f"joint {j.name}: type {j.type} is not supported (revolute, continuous, prismatic, fixed)")
        if j.mimic is not None and j.type != "fixed":
            raise URDFError(f"joint {j.name} mimics {j.mimic.joint}: a mimic joint on the chain is not supported")
    return base, tip, path


def _rot(axis, angle):
    c, s = math.cos(angle), math.sin(angle)
    if axis == "x":
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == "y":
        return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def _homog(R=None, p=None):
    T = np.eye(4)
    if R is not None:
        T[:3, :3] = R
    if p is not None:
        T[:3, 3] = p
    return T


def align_z(axis):
    """A = Rz(phi) Ry(theta) with A z = axis (a unit vector); returns (phi, theta)."""
    a = np.asarray(axis, dtype=float)
    norm = np.linalg.norm(a)
    if not (norm > 0 and abs(norm - 1.0) < 1e-6):
        raise URDFError(f"joint axis {list(a)} is not a unit vector")
    a = a / norm
    theta = math.acos(max(-1.0, min(1.0, a[2])))
    phi = math.atan2(a[1], a[0]) if math.hypot(a[0], a[1]) > 1e-15 else 0.0
    return phi, theta


def rpy_of(R):
    """[roll, pitch, yaw] with R = Rz(yaw) Ry(pitch) Rx(roll) (URDF's and the description's order)."""
    pitch = math.atan2(-R[2, 0], math.hypot(R[0, 0], R[1, 0]))
    if math.hypot(R[0, 0], R[1, 0]) > 1e-9:
        yaw = math.atan2(R[1, 0], R[0, 0])
        roll = math.atan2(R[2, 1], R[2, 2])
    else:  # pitch = +-90 deg: only roll -+ yaw is defined; take yaw = 0
        yaw = 0.0
        roll = math.atan2(-R[1, 2], R[1, 1])
    return [roll, pitch, yaw]


def _num(v):
    v = float(v)
    return repr(0.0 if v == 0 else v)


def _constant_elements(T):
    """Tx Ty Tz Rz Ry Rx (non-zero ones) whose product is the rigid transform T."""
    out = []
    for op, v in zip(("tx", "ty", "tz"), T[:3, 3]):
        if abs(v) > ZERO:
            out.append((op, float(v)))
    roll, pitch, yaw = rpy_of(T[:3, :3])
    for op, v in (("rz", yaw), ("ry", pitch), ("rx", roll)):
        if abs(v) > ZERO:
            out.append((op, v))
    return out


def _origin(elem):
    """URDF <origin xyz rpy>: Trans(xyz) Rz(yaw) Ry(pitch) Rx(roll)."""
    o = elem.find("origin") if elem is not None else None
    xyz = [float(v) for v in (o.get("xyz", "0 0 0") if o is not None else "0 0 0").split()]
    rpy = [float(v) for v in (o.get("rpy", "0 0 0") if o is not None else "0 0 0").split()]
    return _homog(_rot("z", rpy[2]) @ _rot("y", rpy[1]) @ _rot("x", rpy[0]), xyz)


def collisions(path):
    """{link name: [(origin 4x4 in the link frame, kind, {attribute: value})]} of every
    <collision>; kind is sphere, cylinder, capsule, box, or mesh (not converted)."""
    import xml.etree.ElementTree as ET
    out = {}
    for link in ET.parse(path).getroot().findall("link"):
        for col in link.findall("collision"):
            geo = col.find("geometry")
            shape = next(iter(geo), None) if geo is not None else None
            if shape is None:
                continue
            kind = shape.tag if shape.tag in ("sphere", "cylinder", "capsule", "box") else "mesh"
            attrs = {k: [float(v) for v in shape.get(k).split()] for k in ("radius", "length", "size")
                     if shape.get(k) is not None}
            out.setdefault(link.get("name"), []).append((_origin(col), kind, attrs))
    return out


def _vec(v):
    return "[" + ", ".join(_num(x) for x in v) + "]"


def _volume(name, frame, T, kind, a):
    """One volumes entry: the collision shape at T in frame `frame`, or None (a mesh)."""
    head = f'    {{ name = "{name[:63]}"; frame = {frame}; shape = '
    if kind == "sphere":
        return head + f'"sphere"; xyz = {_vec(T[:3, 3])}; radius = {_num(a["radius"][0])}; }},'
    if kind in ("cylinder", "capsule"):
        half = a["length"][0] / 2.0
        ends = [T @ np.array([0.0, 0.0, z, 1.0]) for z in (-half, half)]
        return head + (f'"{kind}"; from = {_vec(ends[0][:3])}; to = {_vec(ends[1][:3])}; '
                       f'radius = {_num(a["radius"][0])}; }},')
    if kind == "box":
        return head + (f'"box"; xyz = {_vec(T[:3, 3])}; rpy = {_vec(rpy_of(T[:3, :3]))}; '
                       f'half = {_vec([v / 2.0 for v in a["size"]])}; }},')
    return None


def convert(path, base=None, tip=None, name=None, vel=None, acc=None, warn=None):
    """The description file's text for the URDF's chain, and a one-line summary.
    warn(text) is told of links without a volume and joints without limits
    (default: a line on stderr)."""
    robot = load(path)
    base, tip, joints = chain_joints(robot, base, tip)
    moving = [j for j in joints if j.type != "fixed"]
    if not moving:
        raise URDFError(f"no moving joint between {base} and {tip}")
    if len(moving) > 16:
        raise URDFError(f"{len(moving)} moving joints between {base} and {tip}: at most 16")
    name = name or robot.robot.name or os.path.splitext(os.path.basename(path))[0]
    name = "".join(c if c.isalnum() or c in "_-." else "_" for c in name)[:63]

    lines = []
    pending = np.eye(4)  # constant transform since the last joint
    no_vel = []
    frame = 0  # the frame the links behind the current joint are rigid in
    in_frame = np.eye(4)  # frame -> the current link
    placed = {base: (0, np.eye(4))}  # link -> (frame, frame -> link)
    for j in joints:
        origin = np.asarray(j.origin if j.origin is not None else np.eye(4), dtype=float)
        pending = pending @ origin
        if j.type == "fixed":
            in_frame = in_frame @ origin
            placed[j.child] = (frame, in_frame)
            continue
        phi, theta = align_z(j.axis if j.axis is not None else [1.0, 0.0, 0.0])
        A = _homog(_rot("z", phi) @ _rot("y", theta))
        pending = pending @ A
        for op, v in _constant_elements(pending):
            lines.append(f'    {{ op = "{op}"; value = {_num(v)}; }},')
        limits = []
        lim = j.limit
        if j.type != "continuous" and lim is not None and lim.lower is not None and lim.upper is not None \
                and lim.upper > lim.lower:
            limits.append(f"q = [{_num(lim.lower)}, {_num(lim.upper)}];")
        qd = lim.velocity if lim is not None and lim.velocity else vel
        if qd:
            limits.append(f"qd = {_num(qd)};")
        else:
            no_vel.append(j.name)
        qdd = acc or (ACC_PER_VEL * qd if qd else None)
        if qdd:
            limits.append(f"qdd = {_num(qdd)};")
        op = "tz" if j.type == "prismatic" else "rz"
        lines.append(f'    {{ op = "{op}"; joint = true; offset = 0.0; name = "{j.name[:63]}";'
                     + (f" limits = {{ {' '.join(limits)} }};" if limits else "") + " },")
        pending = _homog(A[:3, :3].T)
        frame += 1
        in_frame = _homog(A[:3, :3].T)
        placed[j.child] = (frame, in_frame)
    tool = pending
    volumes, no_volume, meshes = [], [], []
    cols = collisions(path)
    for link, (k, T_link) in placed.items():
        shapes = cols.get(link, [])
        made = 0
        for T_col, kind, attrs in shapes:
            if kind == "mesh":
                meshes.append(link)
                continue
            if k == 0:
                continue
            vname = link if made == 0 else f"{link}_{made + 1}"
            volumes.append(_volume(vname, k, T_link @ T_col, kind, attrs))
            made += 1
        if not made:
            no_volume.append(link)
    if len(volumes) > MAX_VOLUMES:
        raise URDFError(f"{len(volumes)} collision shapes on the chain: at most {MAX_VOLUMES} link volumes")
    tool_rpy = rpy_of(tool[:3, :3])
    lines[-1] = lines[-1].rstrip(",")
    skipped = [j.name for j in robot.robot.joints if j not in joints]
    head = [f"# {name}: from {os.path.basename(path)} by kinctl import-urdf (yourdfpy),",
            f"# the chain from link {base} to link {tip}: {len(moving)} joints "
            f"({', '.join(j.name for j in moving)}).",
            "# Each joint's axis is turned onto z by constant rotations (elements only move about or",
            "# along z); every constant between joints is one rigid transform Tx Ty Tz Rz Ry Rx.",
            "# Frames: one after each joint; the tool is the transform from the last joint to the tip."]
    if skipped:
        head.append(f"# Not on the chain, left out: {', '.join(skipped)}.")
    if acc:
        head.append(f"# Acceleration limits (URDF has none): qdd = {_num(acc)} for every joint (--acc).")
    else:
        head.append(f"# Acceleration limits (URDF has none): qdd = {_num(ACC_PER_VEL)} x qd (import with --acc to"
                    " choose one).")
    if no_vel:
        head.append(f"# No velocity limit in the URDF for: {', '.join(no_vel)} (import with --vel to set one);")
        head.append(f"# kinctld needs qd and qdd on every joint: without them it refuses this file.")
    if volumes:
        head.append(f"# Link volumes from the URDF's collision geometry: {len(volumes)} (forbidden zones are checked"
                    " against them).")
    if no_volume:
        head.append(f"# WARNING: no link volume for {', '.join(no_volume)} (no collision sphere, cylinder, capsule or")
        head.append("# box): forbidden zones do not guard these links; add volumes (models/README.md) by hand.")
    text = "\n".join(head) + "\n\nrobot = {\n" + f'  name = "{name}";\n  angles = "rad";\n'
    text += (f"  tool = {{ xyz = [{', '.join(_num(v) for v in tool[:3, 3])}]; "
             f"rpy = [{', '.join(_num(v) for v in tool_rpy)}]; }};\n")
    text += "  elements = (\n" + "\n".join(lines) + "\n  );\n"
    if volumes:
        volumes[-1] = volumes[-1].rstrip(",")
        text += "  volumes = (\n" + "\n".join(volumes) + "\n  );\n"
    text += "};\n"
    info = f"{name}, {len(moving)} joints from {base} to {tip}" + (f", {len(skipped)} joints off the chain left out"
                                                                   if skipped else "")
    info += f", {len(volumes)} link volumes"
    warn = warn or (lambda m: print(f"kinctl import-urdf: warning: {m}", file=sys.stderr, flush=True))
    if no_volume:
        warn(f"no link volume for {', '.join(no_volume)}" + (" (their collision geometry is a mesh, which is not "
             "converted, or none)" if meshes else " (no collision geometry)") + ": forbidden zones do not guard "
             "these links")
    if no_vel:
        warn(f"no velocity (and so no acceleration) limit for {', '.join(no_vel)}: kinctld refuses the file until "
             "they have one (--vel)")
    return text, info


def fk_reference(robot, joint_names, q, base, tip):
    """The URDF's own forward kinematics (yourdfpy): base -> tip at q (by joint name)."""
    cfg = {n: np.float64(v) for n, v in zip(joint_names, q)}
    robot.update_cfg(cfg)
    return robot.get_transform(frame_to=tip, frame_from=base)
