"""A scan's loops classed (heatdata.jasnom.scans): the silhouette and the holes the scanner left inside it."""

import numpy as np
import pytest
from conftest import range_grid_ply

import heatdata as hd
from heatdata.jasnom.scans import _projected_area, is_scan_file, read_scan, scan_loops


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
