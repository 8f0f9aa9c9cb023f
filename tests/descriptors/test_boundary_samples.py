"""Heat sources and boundary samples (heatdata.descriptors.boundary): the source rules, arc-length and polar samples.

Named apart from tests/jasnom/test_boundary.py: pytest's default import mode needs test files' names unique."""

import numpy as np
import pytest
from conftest import grid_mesh

import heatdata as hd
from heatdata.descriptors import sample_boundary, source_vertex


def test_source_rules():
    vertices, faces = grid_mesh(15, 15)
    vertices[:, 2] += 0.5 * vertices[:, 0] + 0.01 * (vertices[:, 0] ** 2 + vertices[:, 1] ** 2)
    vertices[:, :2] += 0.004  # the optical axis is off the grid centre
    view = hd.View.from_arrays(vertices, faces)
    closest = source_vertex(view, "closest")
    center = source_vertex(view, "center")
    assert closest == np.argmin(np.linalg.norm(view.vertices, axis=1))  # eq. 2.7
    # eq. 2.8 in the camera frame turned to face the segment: its image's bounding box centred on the optical axis
    turned = view.vertices @ view.canonical_rotation.T
    image = turned[:, :2] / turned[:, 2:]
    assert np.allclose(image.min(axis=0) + image.max(axis=0), 0.0, atol=1e-5)
    assert center == np.argmin(np.hypot(turned[:, 0], turned[:, 1]))
    assert closest != center
    with pytest.raises(hd.ViewError, match="source rule"):
        source_vertex(view, "nearest")
    with pytest.raises(hd.ViewError, match="not in"):
        source_vertex(view, 10_000)


def test_samples_none_gives_one_value_per_boundary_vertex(disc):
    d = hd.pvhk(disc, samples=None)
    assert d.values.shape == disc.boundary.shape
    assert d.positions[0] == 0.0 and np.all(np.diff(d.positions) > 0) and d.positions[-1] < 1.0


def test_arclength_samples_interpolate_per_vertex_values(disc):
    full = hd.pvhk(disc, samples=None)
    sampled = hd.pvhk(disc, samples=32)
    closed_pos = np.append(full.positions, 1.0)
    closed_val = np.append(full.values, full.values[0])
    assert np.allclose(sampled.values, np.interp(sampled.positions, closed_pos, closed_val))


def test_polar_samples_follow_the_angle(square):
    view = square
    temps = view.planar[view.boundary, 0]  # value = x coordinate of the boundary point
    values, positions = sample_boundary(view, view.boundary, temps, 8, "polar")
    theta = 2 * np.pi * positions
    # rays at 0, 45, 90 ... deg cross the square's boundary where x = r cos(theta)
    assert values[0] > 0 and values[4] < 0 and abs(values[2]) < 1e-9 and abs(values[6]) < 1e-9
    assert np.allclose(values[[1, 3, 5, 7]], values[0] * np.sign(np.cos(theta[[1, 3, 5, 7]])), atol=1e-9)


def test_interior_source_is_farthest_from_the_outline(square, disc):
    assert source_vertex(disc, "interior") == 0  # the disc's centre
    s = source_vertex(square, "interior")
    assert np.allclose(square.vertices[s, :2], 0.0)  # the square's centre
    assert s not in set(square.boundary)
