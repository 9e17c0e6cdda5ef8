# SPDX-License-Identifier: BSD-3-Clause
"""kinctl.projection against tests/vectors/projections.json (seed 001 lab 3)."""
import json
import os

import numpy as np
import pytest

from kinctl import projection as pj

VECTORS = os.environ.get("KINCTL_VECTORS",
                         os.path.join(os.path.dirname(__file__), "..", "vectors"))
with open(os.path.join(VECTORS, "projections.json")) as f:
    REF = json.load(f)
TOL = REF["tolerance"]["abs"]
AXIS_KEY = {"OX": "psi", "OY": "theta", "OZ": "phi"}


def close(a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape, (a.shape, b.shape)
    err = float(np.max(np.abs(a - b))) if a.size else 0.0
    assert err <= TOL, f"max error {err:.3g} > {TOL}"


@pytest.mark.parametrize("name", pj.NAMES)
def test_matrices(name):
    close(pj.matrix(name), REF["matrices"][name])
    # The images of the unit axes are the matrix's columns.
    close(pj.project(pj.matrix(name), np.eye(3)), REF["unit_axis_images"][name]["e1_e2_e3_images_2x3"])


def test_default_parameters_are_the_labs():
    close(pj.frontal_dimetric(0.5, 225.0), REF["matrices"]["frontal_dimetric"])
    close(pj.horizontal_isometric(20.0), REF["matrices"]["horizontal_isometric"])
    # A different parameter gives a different matrix (the parameters are used).
    assert abs(pj.frontal_dimetric(0.6)[0, 0] - REF["matrices"]["frontal_dimetric"][0][0]) > 0.01


@pytest.mark.parametrize("case", REF["axes_table_3_1"], ids=lambda c: f"axes{c['variant']}")
def test_table_3_1_axes(case):
    axis = AXIS_KEY[case["rotation_axis"]]
    for step in case["steps"]:
        R = pj.result(**{axis: step["angle_deg"]}, deg=True)
        close(R, step["Result"])
        close(R @ np.asarray(case["points_3x4"]), step["rotated_points_3x4"])
        for name in pj.NAMES:
            close(pj.project(pj.matrix(name), case["points_3x4"], R), step["uv"][name])


@pytest.mark.parametrize("case", REF["figures_table_3_2"], ids=lambda c: f"fig{c['variant']}")
def test_table_3_2_figures(case):
    assert len(case["steps"]) == 5
    for step in case["steps"]:
        R = pj.result(**{AXIS_KEY[a]: v for a, v in step["angles_deg"].items()}, deg=True)
        close(R, step["Result"])
        close(pj.project(pj.matrix(case["projection"]), case["vertices_3xN"], R), step["uv_table_projection"])
        for name in pj.NAMES:
            close(pj.project(pj.matrix(name), case["vertices_3xN"], R), step["uv_all"][name])


def test_result_is_rz_ry_rx():
    # Three different angles: the order of the factors shows.
    R = pj.result(psi=0.1, theta=0.2, phi=0.3)
    c, s = np.cos, np.sin
    rx = np.array([[1, 0, 0], [0, c(0.1), -s(0.1)], [0, s(0.1), c(0.1)]])
    ry = np.array([[c(0.2), 0, s(0.2)], [0, 1, 0], [-s(0.2), 0, c(0.2)]])
    rz = np.array([[c(0.3), -s(0.3), 0], [s(0.3), c(0.3), 0], [0, 0, 1]])
    assert np.max(np.abs(R - rz @ ry @ rx)) < 1e-15
    assert np.max(np.abs(R - rx @ ry @ rz)) > 1e-3


def test_bad_input_says_what_is_wrong():
    with pytest.raises(ValueError, match="unknown projection 'cabinet'"):
        pj.matrix("cabinet")
    with pytest.raises(ValueError, match="3 x N"):
        pj.project(pj.orthographic(), np.zeros((4, 2)))
