# SPDX-License-Identifier: BSD-3-Clause
"""Extra 3-D geometry drawn by kinctl plot and kinctl view beside the arm
and the tool path (link volumes, forbidden zones, targets...).

A shape is anything with a method lines() that returns polylines: a list of
N x 3 arrays of points in the base frame (m), and optional attributes
color, alpha, lw and label. Polyline below is the plain one; other kinds
(boxes, cylinders from a zone file) only need to produce their edges.

    from kinctl.shapes import Polyline, box_edges
    plot_run(log, "run.png", shapes=[Polyline(box_edges((0.4, -0.2, 0), (0.6, 0.2, 0.3)), label="zone")])

draw3d() draws a shape into a matplotlib 3-D axes, draw_plane() onto a 2-D
axes as one coordinate plane (x, y, z = 0, 1, 2), draw_projected() through a
2 x 3 screen projection (kinctl.projection).
"""
import numpy as np


class Polyline:
    """Polylines in the base frame (m): lines, a list of N x 3 point arrays."""

    def __init__(self, lines, color="tab:red", alpha=0.7, lw=1.2, label=None):
        self._lines = [np.asarray(p, dtype=float).reshape(-1, 3) for p in lines]
        self.color, self.alpha, self.lw, self.label = color, alpha, lw, label

    def lines(self):
        return self._lines


def box_edges(lo, hi):
    """The 12 edges of the axis-aligned box lo..hi (each an array of 2 points)."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    c = np.array([[x, y, z] for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)])
    pairs = [(i, j) for i in range(8) for j in range(i + 1, 8) if bin(i ^ j).count("1") == 1]
    return [c[[i, j]] for i, j in pairs]


def _style(shape, first):
    return dict(color=getattr(shape, "color", "tab:red"), alpha=getattr(shape, "alpha", 0.7),
                lw=getattr(shape, "lw", 1.2), label=getattr(shape, "label", None) if first else None)


def draw3d(ax, shape):
    """Draws shape's polylines into a 3-D axes; returns the Line3D objects."""
    out = []
    for i, p in enumerate(shape.lines()):
        out += ax.plot(p[:, 0], p[:, 1], p[:, 2], **_style(shape, i == 0))
    return out


def draw_plane(ax, shape, iu, iv):
    """Draws shape's polylines onto a 2-D axes showing coordinates iu, iv (0 x, 1 y, 2 z)."""
    out = []
    for i, p in enumerate(shape.lines()):
        out += ax.plot(p[:, iu], p[:, iv], **_style(shape, i == 0))
    return out


def draw_projected(ax, shape, M):
    """Draws shape's polylines onto a 2-D axes through the 2 x 3 projection M."""
    out = []
    for i, p in enumerate(shape.lines()):
        uv = np.asarray(M) @ p.T
        out += ax.plot(uv[0], uv[1], **_style(shape, i == 0))
    return out
