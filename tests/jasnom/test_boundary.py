"""JASNOM's boundaries (thesis 7.2): loops resampled by arc length, pinches split, normals out of the mesh."""

import numpy as np
import pytest

from heatdata.errors import StitchError
from heatdata.io.models import Model
from heatdata.jasnom.boundary import boundaries, boundary, resample_loop
from heatdata.jasnom.cuts import split_model


def test_resampling_is_uniform_by_arc_length_and_interpolates_normals():
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    normals = np.array([[0, -1, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0]], dtype=float)
    points, between = resample_loop(square, 8, normals)
    np.testing.assert_allclose(np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1), 0.5)
    np.testing.assert_allclose(between[1], [np.sqrt(0.5), -np.sqrt(0.5), 0.0])  # half-way from the first to the next
    assert resample_loop(square, 4)[1] is None
    with pytest.raises(StitchError, match="at least 3 samples"):
        resample_loop(square, 2)


def test_a_boundary_that_pinches_is_split_into_loops_that_visit_each_vertex_once():
    bowtie = Model.untextured(
        "bowtie", [[0, 0, 0], [1, 0, 0], [1, 1, 0], [-1, 0, 0], [-1, -1, 0]], [[0, 1, 2], [0, 3, 4]], (0.5, 0.5, 0.5)
    )  # two triangles that share a corner
    loops = boundaries(bowtie)
    assert sorted(sorted(b.loop.tolist()) for b in loops) == [[0, 1, 2], [0, 3, 4]]
    assert all(b.loops == 2 for b in loops)


def test_boundary_normals_point_out_of_the_mesh(ellipsoid):
    a, _ = split_model(ellipsoid, [0.0, 1.0, 0.0])  # the upper half: its boundary runs round the equator
    b = boundary(a)
    assert b.loops == 1 and np.allclose(np.linalg.norm(b.normals, axis=1), 1.0)
    assert np.mean(b.normals[:, 1]) < -0.5  # out of the upper half is downwards
    assert b.arclength[0] == 0.0 and np.all(np.diff(b.arclength) > 0) and b.arclength[-1] < 1.0
