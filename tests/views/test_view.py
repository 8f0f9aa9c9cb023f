"""Views from raw arrays: cleaning, components, the boundary loop, saving."""

import numpy as np
import pytest
import trimesh
from conftest import grid_mesh

import heatdata as hd
from heatdata.core.spectrum import laplacian


def signed_area(points):
    x, y = points[:, 0], points[:, 1]
    return 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)


def test_boundary_is_the_outer_loop_counter_clockwise_from_the_x_axis():
    vertices, faces = grid_mesh(21, 21)
    hole = (np.abs(vertices[:, 0]) < 0.005) & (np.abs(vertices[:, 1]) < 0.005)
    faces = faces[~hole[faces].any(axis=1)]  # a hole in the middle: the outer loop must win
    view = hd.View.from_arrays(vertices, faces)
    loop = view.planar[view.boundary]
    assert len(view.boundary) == 80  # the 21 x 21 grid's rim
    assert signed_area(loop) > 0  # counter-clockwise with y up
    start = loop[0]
    assert start[0] > 0 and start[1] >= 0 and abs(start[1]) <= 2.0  # first vertex at the +x axis
    assert np.all(np.abs(np.diff(np.unwrap(np.arctan2(loop[:, 1], loop[:, 0])))) < 0.5)


def test_nan_coordinates_are_an_error():
    vertices, faces = grid_mesh(8, 8)
    vertices[5, 1] = np.nan
    with pytest.raises(hd.ViewError, match="NaN"):
        hd.View.from_arrays(vertices, faces, view_id="bad")


def test_duplicate_vertices_are_merged_and_recorded(caplog):
    vertices, faces = grid_mesh(8, 8)
    vertices = np.vstack([vertices, vertices[10]])
    rows, cols = np.nonzero(faces == 10)
    faces[rows[:2], cols[:2]] = len(vertices) - 1  # two faces use the copy, the others the original
    view = hd.View.from_arrays(vertices, faces)
    assert view.n_vertices == 64
    assert view.repairs == ["merged 1 duplicate vertices"]
    assert "merged 1 duplicate" in caplog.text
    assert np.allclose(laplacian(view.vertices, view.edges).sum(axis=1), 0, atol=1e-3)


def test_degenerate_faces_are_dropped():
    vertices, faces = grid_mesh(8, 8)
    faces = np.vstack([faces, [[3, 3, 4]]])
    view = hd.View.from_arrays(vertices, faces)
    assert "dropped 1 degenerate faces" in view.repairs


def test_too_few_vertices():
    vertices, faces = grid_mesh(4, 4)
    with pytest.raises(hd.ViewError, match="only 16 vertices"):
        hd.View.from_arrays(vertices, faces)


def test_bad_arrays():
    with pytest.raises(hd.ViewError, match="faces"):
        hd.View.from_arrays(np.zeros((40, 3)), np.zeros((0, 3)))
    with pytest.raises(hd.ViewError, match="outside"):
        hd.View.from_arrays(np.random.default_rng(0).random((40, 3)), np.array([[0, 1, 99]]))


def test_closed_surface_has_no_boundary():
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=0.1)
    view = hd.View.from_arrays(sphere.vertices + [0, 0, 1.0], sphere.faces)
    with pytest.raises(hd.ViewError, match="no boundary"):
        _ = view.boundary
    with pytest.raises(hd.ViewError, match="no boundary"):
        hd.pvhk(view)


def test_save_and_load_round_trip(tmp_path, mug):
    view = hd.render_view(mug, 20.0, 30.0, 1.4, seed=2)
    view.save(tmp_path / "v.npz")
    back = hd.View.load(tmp_path / "v.npz")
    assert np.array_equal(back.vertices, view.vertices) and np.array_equal(back.faces, view.faces)
    assert back.intrinsics == view.intrinsics and back.view_id == view.view_id
    assert (back.azimuth, back.elevation, back.distance) == (20.0, 30.0, 1.4)
    assert np.array_equal(hd.pvhk(back).values, hd.pvhk(view).values)


def test_loading_a_corrupt_view(tmp_path):
    path = tmp_path / "bad.npz"
    path.write_bytes(b"not a zip")
    with pytest.raises(hd.ViewError, match="not a readable"):
        hd.View.load(path)


def test_inconsistent_winding_is_made_consistent_and_recorded(caplog):
    """Every third face of a grid reversed gave an outer boundary of 42 instead of 76 vertices, PVHK off by 0.30."""
    vertices, faces = grid_mesh(20, 20)
    good = hd.View.from_arrays(vertices, faces)
    flipped = faces.copy()
    flipped[::3] = flipped[::3, ::-1]
    view = hd.View.from_arrays(vertices, flipped)
    assert len(view.boundary) == len(good.boundary) == 76
    assert view.repairs == [f"reversed {len(faces[::3])} faces whose winding disagreed with their neighbours'"]
    assert np.array_equal(hd.pvhk(view, 64, "center").values, hd.pvhk(good, 64, "center").values)
    assert "winding" in caplog.text and hd.View.from_arrays(vertices, faces).repairs == []


def test_bad_colours_and_face_indices_are_errors():
    vertices, faces = grid_mesh(8, 8)
    colors = np.full((len(vertices), 3), 0.5)
    colors[3, 0] = np.nan
    with pytest.raises(hd.ViewError, match="1 vertices have NaN or infinite colours"):
        hd.View.from_arrays(vertices, faces, colors)
    with pytest.raises(hd.ViewError, match=r"colors must be \(n, 3\)"):
        hd.View.from_arrays(vertices, faces, np.full((len(vertices) - 1, 3), 0.5))
    fractional = faces.astype(float)
    fractional[0, 0] += 0.7
    with pytest.raises(hd.ViewError, match="whole vertex indices"):
        hd.View.from_arrays(vertices, fractional)
    assert hd.View.from_arrays(vertices, faces.astype(float)).n_vertices == 64  # whole floats are indices


def test_zero_area_faces_are_dropped_and_recorded():
    vertices, faces = grid_mesh(8, 8)
    row = np.arange(3)  # three collinear vertices of the grid's first row
    view = hd.View.from_arrays(vertices, np.vstack([faces, row]))
    assert view.repairs == ["dropped 1 zero-area faces (collinear vertices)"] and len(view.faces) == len(faces)
