"""Cyberware range grids (heatdata.frames.range_grid): a PLY whose range_grid element lists each grid cell's vertex,
triangulated from its grid like any range map."""

import numpy as np
import pytest
from conftest import range_grid_ply

import heatdata as hd
from heatdata.frames.clouds import read_cloud_grid


def test_a_range_grid_is_triangulated_from_its_grid(tmp_path):
    path = range_grid_ply(tmp_path / "scan.ply", holes={(5, 5), (5, 6)})
    points, colors, _ = read_cloud_grid(path)
    assert points.shape == (20, 30, 3) and colors is None
    assert np.isnan(points[20 - 1 - 5, 5]).all() and np.isfinite(points).all(axis=2).sum() == 598
    # the file's y up is the image's down: row 0 of the grid is the scan's top
    assert points[0, 0, 1] < points[-1, 0, 1]
    view = hd.read_organized_cloud(path)
    assert view.n_vertices == 598
    # a full grid would have 2 (rows - 1)(cols - 1) triangles; the two holes take out the ones around them
    assert 2 * 19 * 29 - 12 <= len(view.faces) < 2 * 19 * 29
    # distances are the file's: the grid's step stays 0.5 mm
    assert np.linalg.norm(points[0, 1] - points[0, 0]) == pytest.approx(0.0005 * np.hypot(1, 0.2), rel=1e-4)


def test_a_range_grid_of_the_wrong_size_is_refused(tmp_path):
    with pytest.raises(hd.ViewError, match="range_grid has 500 cells, but num_rows x num_cols is 20x30"):
        read_cloud_grid(range_grid_ply(tmp_path / "short.ply", cells=500))
