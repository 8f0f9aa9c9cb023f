"""The virtual Kinect: depths against analytic answers, colours, noise and bad cameras."""

import logging

import numpy as np
import pytest
from conftest import colored_box, write_textured_quad

import heatdata as hd

TAU = 1.42e-3


@pytest.fixture
def cube(tmp_path):
    path = tmp_path / "cube.ply"
    colored_box().export(path)
    return hd.load_model(path, name="cube", label="box")


def test_unit_cube_front_face_depth_is_analytic(cube):
    view = hd.render_view(cube, 0.0, 0.0, 1.0, noise=False)
    # camera 1 m from the centre, front face 0.1 m closer: every hit is at z = 0.9
    assert np.allclose(view.vertices[:, 2], 0.9, atol=1e-6)
    # the face spans +-0.1 m, that is +-64.4 px about the principal point
    half_width = 0.1 * 580 / 0.9
    assert np.abs(view.pixels[:, 0] - 319.5).max() == pytest.approx(half_width, abs=1.0)
    assert view.n_vertices == pytest.approx((2 * half_width) ** 2, rel=0.03)


def test_noise_follows_the_kinect_model(cube):
    view = hd.render_view(cube, 0.0, 0.0, 1.0, noise=True, seed=1)
    residual = view.vertices[:, 2] - 0.9
    sigma = 0.9**2 * TAU  # z = z0 + z0^2 eps, eps ~ N(0, tau^2)
    assert np.std(residual) == pytest.approx(sigma, rel=0.05)
    assert abs(np.mean(residual)) < 5 * sigma / np.sqrt(len(residual))


def test_oblique_view_lies_on_the_cube_surface(cube):
    view = hd.render_view(cube, 35.0, 40.0, 1.0, noise=False)
    pose = view.pose
    model_points = view.vertices @ pose[:3, :3].T + pose[:3, 3]
    assert np.allclose(np.abs(model_points).max(axis=1), 0.1, atol=1e-5)
    seen = np.abs(model_points).argmax(axis=1)
    assert set(seen.tolist()) == {0, 1, 2}  # three faces visible from above and aside
    assert view.n_components == 1 and len(view.boundary) > 100


def test_same_seed_same_view_and_different_seed_different_view(cube):
    a = hd.render_view(cube, 10.0, 20.0, seed=7)
    b = hd.render_view(cube, 10.0, 20.0, seed=7)
    c = hd.render_view(cube, 10.0, 20.0, seed=8)
    assert np.array_equal(a.vertices, b.vertices)
    assert not np.array_equal(a.vertices, c.vertices)


def test_colors_from_faces_and_textures(cube, tmp_path):
    view = hd.render_view(cube, 0.0, 0.0, noise=False)
    assert np.allclose(view.colors, np.array([200, 50, 50]) / 255, atol=0.01)
    quad = hd.load_model(write_textured_quad(tmp_path), scale=0.2)
    view = hd.render_view(quad, 0.0, 0.0, noise=False)
    left = view.vertices[:, 0] < -0.01
    right = view.vertices[:, 0] > 0.01
    assert np.allclose(view.colors[left], [1, 0, 0]) and np.allclose(view.colors[right], [0, 0, 1])


def test_view_metadata(cube):
    view = hd.render_view(cube, 30.0, 45.0, 1.0, seed=0)
    assert view.intrinsics == {"fx": 580.0, "fy": 580.0, "cx": 319.5, "cy": 239.5, "width": 640, "height": 480}
    assert (view.azimuth, view.elevation, view.distance) == (30.0, 45.0, 1.0)
    assert view.object_id == "cube" and view.label == "box"
    assert view.vertices.dtype == np.float64 and view.faces.dtype == np.int64
    assert view.colors.shape == view.vertices.shape


def test_depth_jumps_split_the_mesh_and_the_largest_part_is_kept(tmp_path, caplog):
    caplog.set_level(logging.INFO, logger="heatdata.views.view")
    import trimesh

    near = trimesh.creation.box(extents=(0.1, 0.1, 0.02))
    far = trimesh.creation.box(extents=(0.3, 0.3, 0.02))
    far.apply_translation([0, 0, -0.2])  # behind, 18 cm deeper: a depth jump all around the near box
    path = tmp_path / "two.ply"
    trimesh.util.concatenate([near, far]).export(path)
    view = hd.render_view(hd.load_model(path), 0.0, 0.0, 1.0, noise=False)
    assert any("kept the largest of 2 components" in r for r in view.repairs)
    assert "kept the largest" in caplog.text
    assert np.allclose(view.vertices[:, 2], view.vertices[:, 2].max(), atol=1e-5)  # the far board
    whole = hd.render_view(hd.load_model(path), 0.0, 0.0, 1.0, noise=False, components="all")
    assert whole.n_components == 2 and whole.n_vertices > view.n_vertices and not whole.repairs
    assert whole.largest_component().n_vertices == view.n_vertices
    with pytest.raises(hd.ViewError, match="components must be"):
        hd.render_view(hd.load_model(path), 0.0, 0.0, 1.0, components="some")


def test_bad_cameras(cube):
    with pytest.raises(hd.RenderError, match="elevation"):
        hd.render_view(cube, 0.0, 90.0)
    with pytest.raises(hd.RenderError, match="inside or behind"):
        hd.render_view(cube, 0.0, 0.0, 0.05)
    with pytest.raises(hd.RenderError, match="positive"):
        hd.render_view(cube, 0.0, 0.0, -1.0)


def test_a_tiny_object_gives_a_clear_error(tmp_path):
    path = tmp_path / "grain.ply"
    colored_box((0.004, 0.004, 0.004)).export(path)
    with pytest.raises(hd.HeatdataError, match="vertices"):
        hd.render_view(hd.load_model(path), 0.0, 0.0, 1.0)


@pytest.mark.parametrize("side", [0.004, 0.2, 20.0])
def test_the_fitted_distance_frames_a_grain_a_box_and_a_house_alike(tmp_path, side):
    from heatdata.views.render import FIT_SHARE, camera_distance
    from heatdata.views.view import kinect_intrinsics

    path = tmp_path / "box.ply"
    colored_box((side, side, side)).export(path)
    box = hd.load_model(path)
    half = kinect_intrinsics(0.5)
    distance = camera_distance(box, "fit", half)
    # the bounding sphere (radius side sqrt(3) / 2) spans FIT_SHARE of the 240 rows: tan(asin(r / d)) fy = 0.6 x 120
    assert np.tan(np.arcsin(side * np.sqrt(3) / 2 / distance)) * half["fy"] == pytest.approx(FIT_SHARE * 120)
    view = hd.render_view(box, 0.0, 0.0, distance, noise=False, intrinsics=half)
    # the front face (half side s / 2, at d - s / 2) spans the same pixels at every size
    face = side * 290 / (distance - side / 2)  # pixels, about 94 at every size
    assert np.abs(view.pixels[:, 0] - 159.5).max() == pytest.approx(face / 2, abs=1)
    assert view.n_vertices == pytest.approx(face**2, rel=0.03)
    assert camera_distance(box, 2.5) == 2.5
    for wrong in ("near", 0.0, -1.0):
        with pytest.raises(hd.RenderError, match="'fit'"):
            camera_distance(box, wrong)


def test_half_scale_image_has_a_quarter_of_the_vertices(cube):
    from heatdata.views.view import kinect_intrinsics

    assert kinect_intrinsics(1.0) == hd.render_view(cube, 0.0, 0.0).intrinsics
    half = kinect_intrinsics(0.5)
    assert (half["width"], half["height"], half["fx"], half["cx"]) == (320, 240, 290.0, 159.5)
    full = hd.render_view(cube, 0.0, 0.0, 1.0, noise=False)
    small = hd.render_view(cube, 0.0, 0.0, 1.0, noise=False, intrinsics=half)
    assert small.n_vertices / full.n_vertices == pytest.approx(0.25, rel=0.05)
    assert np.allclose(small.vertices[:, 2], 0.9)  # the same front face
    with pytest.raises(hd.ViewError, match="image_scale"):
        kinect_intrinsics(0.0)
