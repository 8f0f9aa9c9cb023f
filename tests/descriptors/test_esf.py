"""ESF (PCL's algorithm, numpy and numba): invariances, the in/out/mixed split of Fig. 3.15, the kernels, bad input."""

import numpy as np
import pytest
from conftest import square_view

import heatdata as hd
from heatdata.core.distances import chi_square_matrix
from heatdata.descriptors import esf
from heatdata.descriptors.esf import esf_histogram


def holed(view: hd.View, radius: float) -> hd.View:
    keep = np.linalg.norm(view.vertices[:, :2], axis=1) > radius
    return hd.View.from_arrays(view.vertices, view.faces[np.all(keep[view.faces], axis=1)], view_id="holed")


def rows(view, **options):
    return hd.describe(view, [hd.DescriptorSpec("esf", **options)])[0].values.reshape(10, 64).sum(axis=1)


def test_esf_is_640_bins_summing_to_one_and_seeded():
    view = square_view(31, 0.004)
    d = hd.describe(view, [hd.DescriptorSpec("esf")])[0]
    assert d.values.shape == (640,) and d.values.sum() == pytest.approx(1.0) and d.kind == "esf"
    again = hd.describe(view, [hd.DescriptorSpec("esf")])[0]
    other = hd.describe(view, [hd.DescriptorSpec("esf", seed=1)])[0]
    assert np.array_equal(d.values, again.values) and not np.array_equal(d.values, other.values)
    assert hd.distance(d, other) < 0.02  # another sample of the same shape functions


def test_esf_ignores_scale_and_position():
    points = square_view(31, 0.004).vertices
    base = esf_histogram(points)
    assert np.array_equal(base, esf_histogram(2.0 * points))  # scaled to the voxel grid: exactly the same
    assert np.abs(base - esf_histogram(points + [0.3, -0.1, 0.5])).sum() < 0.02  # rounding at voxel edges only


def test_plane_lines_are_all_in_until_a_hole_is_cut():
    """Fig. 3.15: on a plane every line runs over the surface; a hole sends some through it (mixed)."""
    plane = square_view(41, 0.004)
    full, cut = rows(plane), rows(holed(plane, 0.03))
    assert full[8] == 0 and full[9] == 0 and full[6] > 0.45  # D2 in: half the weight; no mixed line
    assert cut[8] > 0.1 and cut[9] > 0.1 and cut[6] < full[6] - 0.15
    assert chi_square_matrix(full[None], cut[None])[0, 0] > 0.1


def test_too_small_or_flat_views_are_errors():
    with pytest.raises(hd.ViewError, match="too few for an esf"):
        hd.describe(square_view(6), [hd.DescriptorSpec("esf")])
    line = np.column_stack([np.linspace(0, 0.1, 100), np.zeros(100), np.ones(100)])
    with pytest.raises(hd.ViewError, match="too small or flat"):
        esf_histogram(line, name="line")
    with pytest.raises(hd.SpecError, match="triplets"):
        hd.DescriptorSpec("esf", triplets=10)


def numpy_trace(grid, start, end):
    """The vectorized line trace the kernel replaced (issue 28): every line's voxels at once."""
    delta = end - start
    steps = np.maximum(np.abs(delta).max(axis=1), 1)
    k = np.arange(int(steps.max()))
    along = np.rint(start[:, None, :] + delta[:, None, :] * (k[None, :, None] / steps[:, None, None])).astype(int)
    along = np.clip(along, 0, grid.shape[0] - 1)
    inside = grid[along[..., 0], along[..., 1], along[..., 2]] & (k[None, :] < steps[:, None])
    return steps, inside.sum(axis=1)


def test_compiled_trace_and_occupancy_match_the_vectorized_numpy():
    rng = np.random.default_rng(5)
    points = rng.normal(0.0, 9.0, (400, 3)).clip(-31.9, 31.9)
    grid = esf._occupancy(points)
    voxels = esf._voxels(points)
    expected = np.zeros_like(grid)
    for offset in np.stack(np.meshgrid([-1, 0, 1], [-1, 0, 1], [-1, 0, 1], indexing="ij"), -1).reshape(-1, 3):
        v = voxels + offset
        ok = np.all((v >= 0) & (v < esf.GRID), axis=1)
        expected[v[ok, 0], v[ok, 1], v[ok, 2]] = True
    assert np.array_equal(grid, expected) and 0 < grid.sum() < grid.size
    start, end = rng.integers(0, 64, (3000, 3)), rng.integers(0, 64, (3000, 3))
    end[:5] = start[:5]  # zero-length lines visit their one voxel
    count, occupied = esf._trace(grid, start, end)
    want_count, want_occupied = numpy_trace(grid, start, end)
    assert np.array_equal(count, want_count) and np.array_equal(occupied, want_occupied)
    assert occupied.max() > 0 and (occupied < count).any()
