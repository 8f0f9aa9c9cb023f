"""A view at a coarser resolution (heatdata.views.resolution.coarse_view): analytic grids, a step in depth, and a
rendered view."""

import numpy as np
import pytest

import heatdata as hd
from heatdata.descriptors.hgd import vertex_areas
from heatdata.views.depth import back_project, grid_view
from heatdata.views.resolution import coarse_view

INTRINSICS = {"fx": 500.0, "fy": 500.0, "cx": 49.5, "cy": 49.5, "width": 100, "height": 100}


def plane_view(depth: np.ndarray) -> hd.View:
    """The view of a depth image (metres, NaN where none) through :data:`INTRINSICS`, every piece kept."""
    return grid_view(back_project(depth, INTRINSICS), components="all", intrinsics=INTRINSICS, view_id="plane")


def test_a_view_within_the_budget_is_itself():
    view = plane_view(np.ones((10, 10)))
    assert coarse_view(view, 100) is view and coarse_view(view, 0) is view


def test_a_plane_of_100x100_pixels_is_seen_through_pixels_twice_as_wide():
    view = plane_view(np.ones((100, 100)))
    small = coarse_view(view, 2500)
    assert small.n_vertices == 2500 and len(small.faces) == 2 * 49 * 49
    # every kept vertex is one of the view's, at every other pixel
    pixels = np.round(small.pixels).astype(int)
    assert (pixels % 2 == 0).all() and len(np.unique(pixels, axis=0)) == 2500
    assert np.isin(small.vertices.view("f8,f8,f8"), view.vertices.view("f8,f8,f8")).all()
    # the surface's area: 98 x 98 pixel steps of 2 mm (at 1 m, 500 px) against the view's 99 x 99 of them
    assert vertex_areas(small.vertices, small.faces).sum() == pytest.approx((98 * 0.002) ** 2, rel=1e-9)
    assert vertex_areas(view.vertices, view.faces).sum() == pytest.approx((99 * 0.002) ** 2, rel=1e-9)
    assert "seen 2 times coarser a side: 2500 of 10000 vertices" in small.repairs[-1]


def test_the_stride_is_the_least_that_meets_the_budget():
    view = plane_view(np.ones((100, 100)))
    assert coarse_view(view, 2499).n_vertices == 34 * 34  # stride 3
    assert coarse_view(view, 1000).n_vertices == 25 * 25  # stride 4


def test_a_step_in_depth_stays_a_step():
    depth = np.ones((100, 100))
    depth[:, 50:] = 2.0  # a wall behind the right half
    small = coarse_view(plane_view(depth), 2500)
    assert small.n_components == 2 and small.n_vertices == 2500


def test_each_block_keeps_its_centre_and_of_two_surfaces_there_the_nearer():
    near, far = plane_view(np.ones((100, 100))), plane_view(np.full((100, 100), 2.0))  # on the same pixels
    both = hd.View.from_arrays(
        np.vstack([far.vertices, near.vertices]),
        np.vstack([far.faces, near.faces + far.n_vertices]),
        intrinsics=INTRINSICS,
    )
    small = coarse_view(both, 2300)  # stride 3: each block's centre pixel
    assert np.allclose(small.vertices[:, 2], 1.0) and small.n_vertices == 34 * 34
    pixels = np.round(small.pixels).astype(int)
    assert ((pixels % 3 == 1) | (pixels == 99)).all()  # the last block, of one pixel a side, keeps that one


def test_a_rendered_view_keeps_its_outline_and_ids():
    catalog = hd.read_catalog(hd.embedded_catalog())
    model = hd.load_catalog_model(catalog[catalog["object"] == "beer-mug"].iloc[0])
    view = hd.render_view(model, azimuth=30.0, elevation=30.0, distance=0.5, noise=False)
    small = coarse_view(view, 2000)
    assert 1000 <= small.n_vertices <= 2000 < view.n_vertices
    assert (small.view_id, small.object_id, small.azimuth) == (view.view_id, view.object_id, view.azimuth)
    area = vertex_areas(view.vertices, view.faces).sum()  # a noiseless view: noise adds area at the finest steps
    assert vertex_areas(small.vertices, small.faces).sum() == pytest.approx(area, rel=0.03)
    box = np.ptp(view.vertices, axis=0)
    assert np.allclose(np.ptp(small.vertices, axis=0), box, atol=0.01)


def test_a_view_projecting_far_beyond_its_image_is_kept_whole():
    view = plane_view(np.ones((100, 100)))
    near = view.vertices.copy()
    near[0] = [1.0, 1.0, 1e-6]  # a vertex a micrometre from the camera: a billion pixels out
    odd = hd.View.from_arrays(near, view.faces, intrinsics=INTRINSICS)
    assert coarse_view(odd, 2500) is odd
