# SPDX-License-Identifier: BSD-3-Clause
"""Screen projections of seed 001 lab 3: 3-D points (X, Y, Z) to screen (u, v).

    from kinctl import projection as pj
    M = pj.matrix("frontal_dimetric")            # 2 x 3
    uv = pj.project(M, points_3xN, pj.result(psi=0, theta=90, phi=90, deg=True))

The three projections, [u; v] = M [X; Y; Z] (3.1):

- frontal dimetric (3.2): M = [[e cos a, 1, 0], [e sin a, 0, 1]], e = 0.5,
  a = 225 deg: Y to the right, Z up, X receding down-left at half length
  (the matrix scales the X column, whatever (3.3) says about e2);
- horizontal isometric (3.4): M = [[-sin w, cos w, 0], [-cos w, -sin w, 1]],
  w = 20 deg (the angle between the image of Y and the screen's u axis);
- orthographic (3.6): M = [[0, 1, 0], [0, 0, 1]], the view along -X: the
  X axis collapses to a point.

A moving body is drawn as M (Result [X; Y; Z]) (3.8-3.10), Result the
roll-pitch-yaw rotation (3.7) Rot(z, phi) Rot(y, theta) Rot(x, psi): psi
about OX, theta about OY, phi about OZ (the names of the matrix, which lab
3's text swaps). tests/viz/test_projection.py checks all of this against
tests/vectors/projections.json.
"""
import math

import numpy as np

# Lab 3's parameters, as the lab's program uses them.
DIMETRIC_E = 0.5
DIMETRIC_A_DEG = 225.0
ISOMETRIC_W_DEG = 20.0

NAMES = ("frontal_dimetric", "horizontal_isometric", "orthographic")
TITLES = {"frontal_dimetric": "frontal dimetric", "horizontal_isometric": "horizontal isometric",
          "orthographic": "orthographic (view along -X)"}


def frontal_dimetric(e=DIMETRIC_E, a_deg=DIMETRIC_A_DEG):
    """(3.2): 2 x 3."""
    a = math.radians(a_deg)
    return np.array([[e * math.cos(a), 1.0, 0.0], [e * math.sin(a), 0.0, 1.0]])


def horizontal_isometric(w_deg=ISOMETRIC_W_DEG):
    """(3.4): 2 x 3."""
    w = math.radians(w_deg)
    return np.array([[-math.sin(w), math.cos(w), 0.0], [-math.cos(w), -math.sin(w), 1.0]])


def orthographic():
    """(3.6): 2 x 3."""
    return np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])


def matrix(name):
    """The 2 x 3 matrix of a projection by name (one of NAMES)."""
    makers = {"frontal_dimetric": frontal_dimetric, "horizontal_isometric": horizontal_isometric,
              "orthographic": orthographic}
    if name not in makers:
        raise ValueError(f"unknown projection '{name}' (one of {', '.join(NAMES)})")
    return makers[name]()


def _rot(axis, angle):
    c, s = _cos_sin(angle)
    if axis == "x":
        return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    if axis == "y":
        return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _cos_sin(angle):
    """cos, sin, exact at multiples of a quarter turn (so that a body turned
    by 90 or 180 degrees lands exactly where the seed's tables put it)."""
    quarter = angle / (math.pi / 2)
    k = round(quarter)
    if abs(quarter - k) < 1e-12:
        return ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[k % 4]
    return math.cos(angle), math.sin(angle)


def result(psi=0.0, theta=0.0, phi=0.0, deg=False):
    """(3.7) Result = Rot(z, phi) Rot(y, theta) Rot(x, psi): 3 x 3.
    psi about OX, theta about OY, phi about OZ; radians unless deg."""
    k = math.pi / 180.0 if deg else 1.0
    return _rot("z", phi * k) @ _rot("y", theta * k) @ _rot("x", psi * k)


def project(M, points, R=None):
    """(3.8-3.10): u, v of points (3 x N, or N x 3 when N != 3 is ambiguous:
    pass 3 x N) as a 2 x N array, after the rotation R (3 x 3) if given."""
    P = np.asarray(points, dtype=float)
    if P.ndim == 1:
        P = P.reshape(3, 1)
    if P.shape[0] != 3:
        raise ValueError(f"points must be 3 x N (X, Y, Z rows), got shape {P.shape}")
    if R is not None:
        P = np.asarray(R, dtype=float) @ P
    return np.asarray(M, dtype=float) @ P

