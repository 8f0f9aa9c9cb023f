"""HGD (heat-geodesic distribution): analytic cases of the Euclidean / geodesic ratio, components, options."""

import numpy as np
import pytest
from conftest import grid_mesh, square_view

import heatdata as hd
from heatdata.core.distances import chi_square_matrix
from heatdata.core.mesh import farthest_points
from heatdata.descriptors.hgd import RATIO_EDGES, hgd_histogram


def ratio_shares(view: hd.View, **options) -> np.ndarray:
    """(4,) the HGD's mass in each ratio bin (other component / round a gap / bent / straight)."""
    d = hd.describe(view, [hd.DescriptorSpec("hgd", **options)])[0]
    return d.values.reshape(-1, len(RATIO_EDGES) - 1).sum(axis=0)


def folded(n: int = 41, spacing: float = 0.004, gap: float = 0.02) -> hd.View:
    """A U: two parallel plates ``gap`` apart, joined along one edge by a strip (a chair's seat and back, flat)."""
    vertices, faces = grid_mesh(n, n, spacing)
    x = vertices[:, 0] - vertices[:, 0].min()
    half = x.max() / 2
    # bend the grid's x into a U: the first half lies at depth 1, the second comes back at depth 1 + gap
    back = x > half
    out = vertices.copy()
    out[:, 0] = np.where(back, 2 * half - x, x)
    out[:, 2] = 1.0 + np.where(back, gap, 0.0)
    out[np.isclose(x, half), 2] = 1.0 + gap / 2
    return hd.View.from_arrays(out, faces, view_id="folded")


def test_hgd_is_a_normalized_histogram_of_four_ratio_bins_per_distance_bin():
    view = square_view(31, 0.004)
    d = hd.describe(view, [hd.DescriptorSpec("hgd", bins=8)])[0]
    assert d.kind == "hgd" and d.values.shape == (32,) and d.values.sum() == pytest.approx(1.0)
    assert np.array_equal(d.values, hd.describe(view, [hd.DescriptorSpec("hgd", bins=8)])[0].values)  # no seed


def test_on_a_plane_heat_runs_straight():
    """A flat square: the geodesic is the straight line, so almost all mass is in the last ratio bin."""
    assert ratio_shares(square_view(41, 0.004))[-1] > 0.9


def test_a_fold_sends_pairs_round_and_another_component_counts_as_unreachable():
    flat = ratio_shares(square_view(41, 0.004))
    u = ratio_shares(folded())
    assert u[-1] < flat[-1] - 0.2 and u[:2].sum() > 0.15  # across the U, heat goes round the bend
    vertices, faces = grid_mesh(21, 21, 0.004)
    apart = np.vstack([vertices, vertices + [0.2, 0.0, 0.0]])
    two = hd.View.from_arrays(apart, np.vstack([faces, faces + len(vertices)]), view_id="two")
    shares = ratio_shares(two, sources=8)
    assert two.n_components == 2 and 0.3 < shares[0] < 0.7  # half the pairs lie on the other plate


def test_distance_is_in_metres_so_size_matters():
    small, large = square_view(31, 0.002), square_view(31, 0.006)
    a, b = (hgd_histogram(v) for v in (small, large))
    assert chi_square_matrix(a[None], b[None])[0, 0] > 0.3


def test_farthest_points_spread_and_stop_at_the_point_count():
    points = np.array([[0.0, 0, 0], [1, 0, 0], [0.5, 0, 0], [0.9, 0, 0]])
    assert farthest_points(points, [0], 3) == [0, 1, 2]
    assert len(farthest_points(points, [0], 10)) == 4


def test_bad_options_and_small_views_are_errors():
    with pytest.raises(hd.SpecError, match="near .* must be below far"):
        hd.DescriptorSpec("hgd", near=1.0, far=0.5)
    with pytest.raises(hd.SpecError, match="sources"):
        hd.DescriptorSpec("hgd", sources=0)
    with pytest.raises(hd.ViewError, match="too few for an hgd"):
        hd.describe(square_view(6), [hd.DescriptorSpec("hgd")])


def test_the_colour_part_tells_a_hue_from_another_and_ignores_the_hue_of_greys():
    view = square_view(31, 0.004)
    red, green, grey, dark = ([1.0, 0.1, 0.1], [0.1, 1.0, 0.1], [0.5, 0.5, 0.5], [0.2, 0.2, 0.2])

    def described(rgb):
        coloured = hd.View.from_arrays(view.vertices, view.faces, np.tile(rgb, (view.n_vertices, 1)))
        return hd.describe(coloured, [hd.DescriptorSpec("hgd", color="hue-saturation")])[0]

    a, b, c, d = map(described, (red, green, grey, dark))
    assert a.values.shape == (4 * 32 + 25,) and a.values.sum() == pytest.approx(1.0)
    assert a.values[:128].sum() == pytest.approx(0.5)  # shape and colour weigh the same by default
    assert hd.distance(a, b) > 0.4 and hd.distance(c, d) == 0.0  # two hues apart; greys are greys
    assert hd.DescriptorSpec("hgd", color="hue-saturation").name == "hgd/color=hue-saturation"
