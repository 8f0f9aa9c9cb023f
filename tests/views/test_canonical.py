"""The canonical frame (eq. 2.8, 2.3.3): the camera turned to face the segment, so that where an object stands in
the image does not change how it is described."""

import numpy as np
import pytest
from conftest import grid_mesh
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import heatdata as hd
from heatdata.core.geometry import rotation_between
from heatdata.descriptors import source_vertex
from heatdata.views.view import _image_hull


def bumpy_view(shift=(0.0, 0.0)) -> hd.View:
    vertices, faces = grid_mesh(31, 21, spacing=0.004)
    x, y = vertices[:, 0], vertices[:, 1]
    vertices[:, 2] += 0.02 * np.exp(-((x - 0.01) ** 2 + y**2) / 0.002) + 0.3 * x  # a bump, and a tilt
    vertices[:, :2] += shift
    return hd.View.from_arrays(vertices, faces, view_id="bump")


def turned(view: hd.View, rotation: np.ndarray) -> hd.View:
    """The same surface seen by the camera turned about its optical centre (the points turn the other way)."""
    return hd.View.from_arrays(view.vertices @ rotation.T, view.faces, view.colors, view_id="turned")


def test_the_image_box_of_the_canonical_frame_is_centred_on_the_optical_axis():
    view = bumpy_view(shift=(0.15, -0.08))
    x = view.canonical_vertices
    image = 580.0 * x[:, :2] / x[:, 2:]
    assert np.abs((image.min(axis=0) + image.max(axis=0)) / 2).max() < 1e-3
    rotation = view.canonical_rotation
    assert np.allclose(rotation @ rotation.T, np.eye(3)) and np.linalg.det(rotation) == pytest.approx(1.0)


def test_a_centred_view_barely_turns():
    view = bumpy_view()
    angle = np.degrees(np.arccos(np.clip((np.trace(view.canonical_rotation) - 1) / 2, -1, 1)))
    assert angle < 1.0


@settings(max_examples=25, deadline=None)
@given(st.floats(-0.45, 0.45), st.floats(-0.35, 0.35))  # radians of tilt and pan: anywhere in a Kinect's image
def test_turning_the_camera_turns_the_canonical_frame_with_it(tilt, pan):
    view = bumpy_view()
    rx = rotation_between([0, 0, 1], [0, np.sin(tilt), np.cos(tilt)])
    ry = rotation_between([0, 0, 1], [np.sin(pan), 0, np.cos(pan)])
    other = turned(view, ry @ rx)
    a, b = view.canonical_vertices, other.canonical_vertices
    # the canonical frames differ by a turn about the optical axis, and the image box's centre by the sliver of
    # roll two smallest rotations leave (below 1 mm on this 12 cm surface): distance from the axis and depth agree
    assert np.allclose(np.hypot(a[:, 0], a[:, 1]), np.hypot(b[:, 0], b[:, 1]), atol=1e-3)
    assert np.allclose(a[:, 2], b[:, 2], atol=1e-3)
    assert source_vertex(view, "center") == source_vertex(other, "center")
    assert set(view.boundary) == set(other.boundary)


def test_an_off_axis_rendering_is_described_as_the_centred_one(mug):
    spec = hd.DescriptorSpec("pvhk", 64, "center", "polar")
    centred = hd.render_view(mug, 100.0, 30.0, 1.0, noise=False)
    off_axis = hd.render_view(mug, 100.0, 30.0, 1.0, noise=False, image_offset=(87.0, -40.0))  # 15 cm right at 1 m
    assert np.abs(off_axis.pixels.mean(axis=0) - centred.pixels.mean(axis=0) - [87.0, -40.0]).max() < 10.0
    near = hd.distance(hd.describe(centred, [spec])[0], hd.describe(off_axis, [spec])[0])
    other_angle = hd.distance(
        hd.describe(centred, [spec])[0], hd.describe(hd.render_view(mug, 109.0, 30.0, 1.0, noise=False), [spec])[0]
    )
    assert near < 0.5 * other_angle  # the pixel grid's sampling, well below a 9 degree turn of the object


def test_a_view_behind_the_camera_is_an_error():
    vertices, faces = grid_mesh(7, 7)
    vertices[:, 2] -= 2.0
    view = hd.View.from_arrays(vertices, faces)
    with pytest.raises(hd.ViewError, match="behind the camera"):
        _ = view.canonical_rotation


@settings(max_examples=80, deadline=None)
@given(st.integers(3, 300), st.floats(0.0, 0.6), st.integers(0, 2**31))
def test_a_turned_image_s_box_is_that_of_the_image_hull_s_points(n, angle, seed):
    # the canonical rotation iterates on the hull's points only: a turn of the camera must not move the box off them
    rng = np.random.default_rng(seed)
    depth = rng.uniform(0.5, 3.0, n)  # within a 58 x 58 deg field of view, so that every point stays in front
    points = np.column_stack([rng.uniform(-0.55, 0.55, (n, 2)) * rng.uniform(0.05, 1.0, 2) * depth[:, None], depth])
    hull = _image_hull(points)
    turn = Rotation.from_rotvec(angle * np.append(rng.normal(size=2), 0.0) / np.sqrt(2)).as_matrix()
    turned = points @ turn.T
    assert (turned[:, 2] > 0).all()
    image = turned[:, :2] / turned[:, 2:]
    assert np.array_equal(image.min(axis=0), image[hull].min(axis=0))
    assert np.array_equal(image.max(axis=0), image[hull].max(axis=0))
