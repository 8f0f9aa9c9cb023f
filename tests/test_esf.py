"""ESF (PCL's algorithm in numpy): invariances, the in/out/mixed split of Fig. 3.15, bad input."""

import numpy as np
import pytest

import heatdata as hd
from conftest import square_view
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
    assert hd.chi_square_matrix(full[None], cut[None])[0, 0] > 0.1


def test_too_small_or_flat_views_are_errors():
    with pytest.raises(hd.ViewError, match="too few for an esf"):
        hd.describe(square_view(6), [hd.DescriptorSpec("esf")])
    line = np.column_stack([np.linspace(0, 0.1, 100), np.zeros(100), np.ones(100)])
    with pytest.raises(hd.ViewError, match="too small or flat"):
        esf_histogram(line, name="line")
    with pytest.raises(hd.ViewError, match="triplets"):
        hd.DescriptorSpec("esf", triplets=10)
