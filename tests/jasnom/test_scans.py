"""A scan's loops classed (heatdata.jasnom.scans): the silhouette and the holes the scanner left inside it."""

import numpy as np
import pytest
from conftest import range_grid_ply

import heatdata as hd
from heatdata.jasnom.scans import _manifold_patches, _projected_area, close_holes, is_scan_file, read_scan, scan_loops


def test_a_square_s_signed_area_in_the_image_plane():
    square = np.array([[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    assert _projected_area(square) == pytest.approx(0.5 * 2)  # (x / z, y / z): side 1, area 1, counted once
    assert _projected_area(square[::-1]) == pytest.approx(-1.0)
    assert _projected_area(2 * square) == pytest.approx(1.0)  # twice as far and twice as large: the same image


def test_a_range_grid_with_two_holes_has_one_silhouette_and_two_holes(tmp_path):
    holes = {(5, 5), (5, 6), (6, 5), (6, 6), (12, 20), (12, 21), (13, 20), (13, 21)}
    path = range_grid_ply(tmp_path / "scan.ply", holes=holes)
    assert is_scan_file(path)
    model = read_scan(path)
    loops = scan_loops(model)
    assert len(loops.holes) == 2 and all(len(b.loop) == 8 for b in loops.holes)  # a 2 x 2 hole: 8 cells round it
    assert len(loops.outer.loop) == 2 * (20 - 1) + 2 * (30 - 1)  # the grid's rim
    assert loops.outer.length > sum(b.length for b in loops.holes)


def test_holes_up_to_a_length_are_closed_with_faces_coloured_as_their_corners(tmp_path):
    holes = {(5, 5), (5, 6), (6, 5), (6, 6), (12, 20), (12, 21), (13, 20), (13, 21)}
    grid = read_scan(range_grid_ply(tmp_path / "scan.ply", holes=holes))
    shade = (grid.vertices[:, 0] - grid.vertices[:, 0].min()) / np.ptp(grid.vertices[:, 0])  # a colour per vertex
    model = hd.Model.untextured("scan", grid.vertices, grid.faces, np.repeat(shade[grid.faces][..., None], 3, -1))
    kept, none = close_holes(model, 7)  # each hole is a loop of 8 edges
    assert none == 0 and len(kept.faces) == len(model.faces) and not kept.repairs
    closed, filled = close_holes(model, 8)
    assert filled == 2 and len(scan_loops(closed).holes) == 0 and len(scan_loops(closed).outer.loop) == 96
    np.testing.assert_array_equal(closed.faces[: len(model.faces)], model.faces)  # the scan's faces as they were
    patch = closed.faces[len(model.faces) :]
    assert len(patch) == 2 * (8 - 2)  # a loop of 8 vertices is closed by 6 triangles, twice
    np.testing.assert_allclose(closed.corner_colors[len(model.faces) :, :, 0], shade[patch], rtol=1e-6)
    assert closed.repairs == ["2 hole(s) of up to 8 edges closed (12 faces)"]
    with pytest.raises(hd.StitchError, match="at least 3 edges"):
        close_holes(model, 2)


def test_a_patch_that_would_give_an_edge_a_third_face_is_left_out_whole():
    scan = np.array([[0, 1, 2], [1, 0, 3]])
    over = np.array([[0, 1, 4], [4, 1, 5]])  # its first face is a third on edge 0-1; its second shares vertices 1, 4
    fine = np.array([[6, 7, 8]])
    np.testing.assert_array_equal(_manifold_patches(np.vstack([scan, over, fine]), 2, 9), fine)
    np.testing.assert_array_equal(_manifold_patches(np.vstack([scan, fine]), 2, 9), fine)


def test_mesh_files_are_not_scans_and_a_scan_behind_its_camera_is_refused(tmp_path, square):
    mesh = tmp_path / "mesh.ply"
    import trimesh

    trimesh.Trimesh(square.vertices, square.faces).export(mesh)
    assert not is_scan_file(mesh) and not is_scan_file(tmp_path / "missing.ply") and is_scan_file("x.pcd")
    behind = hd.Model.untextured(
        "behind", square.vertices * [1, 1, -1], square.faces, np.ones((len(square.faces), 3, 3))
    )
    with pytest.raises(hd.StitchError, match="behind the camera"):
        scan_loops(behind)
