"""Surfaces cut where objects meet (heatdata.segmentation.surfaces), on analytic grids: a valley is a concave
crease and a ridge is not, a depth step parts two surfaces, small pieces rejoin their neighbour."""

import numpy as np
import pytest

from heatdata.segmentation.settings import SegmentSettings
from heatdata.segmentation.surfaces import creases, grid_normals, join_small, split_surfaces, steps

F = 500.0  # pixels: a camera's focal length


def grid(depth: np.ndarray) -> np.ndarray:
    """(h, w, 3) camera-frame points of a depth image seen by a pinhole of focal ``F`` centred on the image."""
    h, w = depth.shape
    v, u = np.mgrid[0:h, 0:w].astype(float)
    return np.stack([(u - w / 2) * depth / F, (v - h / 2) * depth / F, depth], axis=-1)


def folded(angle: float, valley: bool, size: int = 60) -> np.ndarray:
    """A surface folded along the image's middle column, its two halves turned ``angle`` degrees from facing the
    camera: a valley (the middle farthest) or a ridge (the middle nearest)."""
    u = np.abs(np.arange(size) - size / 2) / F  # lateral offset at 1 m
    slope = np.tan(np.radians(angle)) * (-1 if valley else 1)
    return grid(np.tile(1.0 + slope * u, (size, 1)))


@pytest.mark.parametrize("angle", [20.0, 35.0])
def test_a_valley_is_a_concave_crease_and_a_ridge_is_not(angle):
    region = np.ones((60, 60), bool)
    for valley in (True, False):
        points = folded(angle, valley)
        found = creases(points, grid_normals(points, 0.02), region, 0.02, 15.0)
        middle = found[10:-10, 28:33].any(axis=1)
        assert middle.all() if valley else not found.any()
        assert not found[:, :20].any() and not found[:, -20:].any()  # flat on either side


def test_a_shallow_valley_is_below_the_concavity():
    points = folded(5.0, True)
    assert not creases(points, grid_normals(points, 0.02), np.ones((60, 60), bool), 0.02, 20.0).any()


def test_a_depth_step_parts_two_surfaces():
    depth = np.ones((40, 40))
    depth[:, 20:] = 1.1  # 10 cm behind: a 10% step
    found = steps(grid(depth), np.ones((40, 40), bool), 0.02)
    assert found[:, 19].all() and found[:, 20].all() and found.sum() == 80


def test_two_boxes_side_by_side_are_cut_at_their_seam_and_every_pixel_is_labelled():
    # two faces meeting in a valley of 2 x 35 deg: two boxes' fronts turned towards each other
    points = folded(35.0, True, size=80)
    region = np.ones((80, 80), bool)
    labels = split_surfaces(points, region, region, SegmentSettings())
    assert set(np.unique(labels)) == {1, 2}
    assert len(np.unique(labels[:, :35])) == 1 and len(np.unique(labels[:, 45:])) == 1
    assert labels[0, 0] != labels[0, -1]
    # without the concave cut (a frame of one object), one surface
    assert set(np.unique(split_surfaces(points, region, region, SegmentSettings(), concave=False))) == {1}


def test_a_small_piece_joins_the_neighbour_it_borders_longest_but_not_across_a_step():
    depth = np.ones((60, 60))
    labels = np.ones((60, 60), np.int64)
    labels[:, 40:] = 2
    labels[25:35, 10:20] = 3  # 100 pixels inside piece 1
    labels[25:35, 55:60] = 4  # 50 pixels inside piece 2, but 5 cm nearer: a step
    depth[25:35, 55:60] = 0.95
    area = 200.0  # pixels at 1 m
    joined = join_small(labels, grid(depth), 0.015, area)
    assert (joined[25:35, 10:20] == joined[0, 0]).all()
    assert (joined[25:35, 55:60] != joined[0, -1]).all()  # parted by the step: it stays
    assert len(np.unique(joined)) == 3
    # the area is the camera's footprint: at 2 m a pixel covers four times as much, and piece 3 is large
    far = join_small(labels, grid(2 * depth), 0.015, area)
    assert (far[25:35, 10:20] != far[0, 0]).all()
