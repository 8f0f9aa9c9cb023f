"""Complex objects (thesis ch. 5): time scales, part weights, FT-PVHK, weighted MHD and PVST."""

import logging
import sys

import numpy as np
import pytest
import scipy.linalg
from conftest import square_view
from scipy.optimize import brentq

import heatdata as hd
import heatdata.descriptors.heat as descriptors
from heatdata.core.distances import mhd, mhd_matrix, weighted_mhd
from heatdata.core.spectrum import heat_model, lambda2
from heatdata.descriptors import (
    global_derivative,
    heat_kernel,
    heat_operator,
    object_time_scale,
    part_weights,
    view_time_scale,
)
from heatdata.descriptors.sources import candidate_descriptors


def lattice_view(mask: np.ndarray, spacing: float = 0.002, name: str = "lattice") -> hd.View:
    """A flat grid mesh over the True cells of a (rows, cols) mask (a cell needs all 4 corners)."""
    ny, nx = mask.shape
    index = -np.ones(mask.shape, int)
    index[mask] = np.arange(mask.sum())
    ys, xs = np.nonzero(mask)
    vertices = np.column_stack([(xs - nx / 2) * spacing, (ys - ny / 2) * spacing, np.ones(len(xs))])
    a, b, c, d = index[:-1, :-1], index[:-1, 1:], index[1:, :-1], index[1:, 1:]
    keep = (a >= 0) & (b >= 0) & (c >= 0) & (d >= 0)
    faces = np.concatenate([np.column_stack([a[keep], b[keep], c[keep]]), np.column_stack([b[keep], d[keep], c[keep]])])
    return hd.View.from_arrays(vertices, faces, view_id=name)


def squares(bottleneck: bool) -> np.ndarray:
    """Fig. 5.4: a 21x21 square, alone or joined to a 9x9 square by a one-cell-wide bottleneck."""
    mask = np.zeros((21, 42), bool)
    mask[:, :21] = True
    if bottleneck:
        mask[9:11, 21:33] = True
        mask[6:15, 33:42] = True
    return mask


def test_bottleneck_drops_lambda2_about_tenfold():
    alone = lambda2(heat_operator(lattice_view(squares(False))))
    joined = lambda2(heat_operator(lattice_view(squares(True))))
    assert 5 < alone / joined < 30  # the thesis's example: 9e-3 -> 8.4e-4, a factor 10.7


def test_global_derivative_is_largest_on_the_small_part():
    view = lattice_view(squares(True))
    delta = global_derivative(view, source=0)
    small = view.vertices[:, 0] > 12 * 0.002  # right of the bottleneck's middle
    assert delta[small].mean() > 10 * delta[~small].mean()


def test_global_derivative_matches_eq_5_11_by_dense_heat():
    view = square_view(9)
    L = heat_operator(view).L.toarray()
    n = len(L)
    t = 1.0 / np.sort(np.linalg.eigvalsh(L))[1]
    heat = scipy.linalg.expm(-t * L) * n  # column i: normalized temperatures with the source at i
    expected = 0.5 * np.einsum("ji,jk,ki->i", heat, L, heat)  # T_i^T L T_i / 2
    np.testing.assert_allclose(global_derivative(view, source=0), expected, rtol=1e-6)


def test_part_weights_follow_the_samples_and_lie_in_0_1():
    view = lattice_view(squares(True))
    w = part_weights(view, samples=64, source=0)
    assert w.shape == (64,) and np.all((w > 0) & (w <= 1))
    assert w.min() < 0.2 and np.median(w) > 0.9  # low on the small square, ~1 on the main one


def test_mostly_small_part_boundary_gets_unit_weights_and_a_warning(monkeypatch, caplog):
    view = lattice_view(squares(True))
    monkeypatch.setattr(descriptors, "MIN_MAIN_SHARE", 0.99)
    with caplog.at_level(logging.WARNING):
        w = part_weights(view, samples=64, source=0)
    assert np.all(w == 1.0)
    assert "unit weights" in caplog.text


def test_object_time_scale_is_the_smallest_view_time_scale():
    views = [lattice_view(squares(True), name="joined"), lattice_view(squares(False), name="alone")]
    scales = [view_time_scale(v, source=0) for v in views]
    assert object_time_scale(views, source=0) == min(scales) == scales[1]
    with pytest.raises(hd.ViewError):
        object_time_scale([])


def test_ft_pvhk_at_t_global_is_the_pvhk(mug):
    view = hd.render_view(mug, 30.0, 30.0, 1.0, seed=0)
    p = hd.pvhk(view, source="center")
    f = hd.ft_pvhk(view, time=p.time, source="center")
    np.testing.assert_allclose(f.values, p.values, atol=1e-6)
    assert f.kind == "ft-pvhk" and np.isnan(f.lambda2)
    many = hd.describe(view, [hd.DescriptorSpec("ft-pvhk", 64, "center")], times=[p.time / 4, p.time])
    assert len(many) == 2 and many[0].weights is not None
    np.testing.assert_allclose(many[1].values, p.values, atol=1e-6)


def test_weighted_mhd_reduces_to_mhd_and_ignores_zero_weight_points():
    rng = np.random.default_rng(0)
    z1, z2 = rng.random(32), rng.random(32)
    ones = np.ones(32)
    assert weighted_mhd(z1, z2, ones, ones) == pytest.approx(mhd(z1, z2))
    spike = z1.copy()
    spike[10] += 5.0
    w = ones.copy()
    w[10] = 0.0
    assert weighted_mhd(spike, z1, w, w) < 1e-12 < mhd(spike, z1)
    weights = rng.random((3, 32)) + 0.1
    queries, library = rng.random((3, 32)), rng.random((4, 32))
    lib_w = rng.random((4, 32)) + 0.1
    matrix = mhd_matrix(queries, library, query_weights=weights, library_weights=lib_w, dtype=np.float64)
    for i in range(3):
        for j in range(4):
            assert matrix[i, j] == pytest.approx(weighted_mhd(queries[i], library[j], weights[i], lib_w[j]))


def test_distances_refuse_nan_and_bad_weights():
    z = np.ones(8)
    with pytest.raises(hd.HeatdataError, match="NaN"):
        mhd_matrix(np.array([[np.nan] * 8]), z[None])
    with pytest.raises(hd.HeatdataError, match="non-negative"):
        weighted_mhd(z, z, -z, z)
    with pytest.raises(hd.HeatdataError, match="both"):
        mhd_matrix(z[None], z[None], query_weights=z[None])


def test_pvst_of_a_disc_with_central_source_is_constant(disc):
    d = hd.pvst(disc, samples=64, source="center")
    assert np.all(np.isfinite(d.values))
    spread = np.std(d.values) / np.mean(d.values)
    assert spread < 0.05  # measured 3.5%: the outer ring of 120 vertices is a polygon, and times are sensitive
    off = hd.pvst(disc, samples=64, source=int(np.argmin(np.abs(disc.vertices[:, 0] - 0.02))))
    assert np.std(off.values) / np.mean(off.values) > 5 * spread


def test_pvst_on_a_log_time_axis_is_a_tenth_of_the_decades_and_keeps_their_ratios(disc):
    linear = hd.pvst(disc, samples=64, source="center", sampling="polar")
    log = hd.pvst(disc, samples=64, source="center", sampling="polar", time_axis="log")
    np.testing.assert_allclose(log.values, 0.1 * np.log10(linear.values), rtol=0, atol=1e-12)
    assert log.time == linear.time and np.array_equal(log.positions, linear.positions)
    # a view scaled by s has times s^2 as long: on the log axis the curve moves up by 0.2 log10(s), its shape stays
    big = hd.View(vertices=2.0 * disc.vertices, faces=disc.faces, colors=disc.colors, view_id="disc x2")
    shifted = hd.pvst(big, samples=64, source="center", sampling="polar", time_axis="log").values - log.values
    np.testing.assert_allclose(shifted, 0.2 * np.log10(2.0), atol=1e-6)
    assert (
        hd.DescriptorSpec("pvst", 64, "interior", "polar", time_axis="log").name
        == "pvst/polar/interior/64/T0.75/log-time"
    )
    with pytest.raises(hd.SpecError, match="time_axis"):
        hd.DescriptorSpec("pvst", time_axis="ln")


def test_both_time_axes_of_a_source_share_one_search(disc, monkeypatch):
    pvst_module = sys.modules["heatdata.descriptors.stochastic_time"]
    searches, search = [], pvst_module._pvst_times
    monkeypatch.setattr(pvst_module, "_pvst_times", lambda *a: searches.append(a[3]) or search(*a))
    specs = [hd.DescriptorSpec("pvst", 64, "center", "polar", time_axis=axis) for axis in ("linear", "log")]
    linear, log = hd.describe(disc, specs)
    assert len(searches) == 1 and np.allclose(log.values, 0.1 * np.log10(linear.values))


def test_pvst_grows_with_distance_along_a_strip():
    mask = np.ones((5, 61), bool)
    view = lattice_view(mask)
    source = int(
        np.argmin(
            np.abs(view.vertices[:, 0] - view.vertices[:, 0].min() - 0.004)
            + np.abs(view.vertices[:, 1] - np.median(view.vertices[:, 1]))
        )
    )
    d = hd.pvst(view, samples=None, source=source)
    bottom = view.vertices[view.boundary, 1] == view.vertices[:, 1].min()
    x = view.vertices[view.boundary, 0][bottom]
    times = d.values[bottom][np.argsort(x)]
    far = np.sort(x) > view.vertices[source, 0]
    assert np.all(np.diff(times[far]) > 0)


@pytest.mark.parametrize("n, row", [(15, 7), (15, 1), (31, 1)])
def test_pvst_matches_a_dense_reference_to_1e_3(n, row):
    """Central source: one heat model. A source one cell from the edge: the window spans 10^4 or
    more in t, and the early chunks use shifted factorizations."""
    view = square_view(n)
    source = row * n + n // 2
    d = hd.pvst(view, samples=None, source=source)
    L = heat_operator(view).L.toarray()
    values, vectors = np.linalg.eigh(L)
    grid = np.geomspace(1e-10, d.time, 4000)
    decay = np.exp(-np.outer(grid, values))  # (grid, n)

    def temperature(t, i):
        return n * n * vectors[i] @ (np.exp(-values * t) * vectors[source])

    assert np.all(np.isfinite(d.values))
    for k, i in enumerate(view.boundary):
        # first crossing on a fine log grid, refined by brentq
        first = np.argmax(n * n * decay @ (vectors[i] * vectors[source]) >= 0.75)
        reference = brentq(lambda t, i=i: temperature(t, i) - 0.75, grid[first - 1], grid[first], xtol=1e-16)
        assert d.values[k] == pytest.approx(reference, rel=1e-3)


def test_a_shifted_factorization_gives_the_same_heat():
    op = heat_operator(square_view(15))
    times = np.array([1e-6, 1e-5, 1e-4])
    base = heat_model(op, 112, times, max_steps=200)(times)
    early = heat_model(op.shifted(1e6), 112, times)(times)
    assert np.allclose(base, early, atol=1e-6)


def test_pvst_unreached_threshold_is_nan_with_a_logged_reason(caplog):
    view = square_view(15)
    with caplog.at_level(logging.WARNING):
        d = hd.pvst(view, samples=None, source=7 * 15 + 7, t_final=3e-5)
    assert np.isnan(d.values).any()
    assert any("do not reach" in r for r in d.repairs) and "do not reach" in caplog.text


def test_pvst_source_on_the_boundary_is_an_error(square):
    with pytest.raises(hd.ViewError, match="interior source"):
        hd.pvst(square, source=int(square.boundary[3]))


def test_specs_check_kinds_and_thresholds(square):
    assert hd.DescriptorSpec("pvst", 64, "center", "polar").name == "pvst/polar/center/64/T0.75"
    with pytest.raises(hd.SpecError, match="threshold"):
        hd.DescriptorSpec("pvst", threshold=1.5)
    with pytest.raises(hd.SpecError, match="no threshold"):
        hd.DescriptorSpec("pvhk", threshold=0.5)
    with pytest.raises(hd.SpecError, match="times="):
        hd.describe(square, [hd.DescriptorSpec("ft-pvhk")])


def test_empty_or_bad_times_and_tiny_thresholds_are_clear_errors(square):
    for times in ([], [0.0], [float("nan")]):
        with pytest.raises(hd.ViewError, match="positive finite times"):
            heat_kernel(square, "center", times=times)
        with pytest.raises(hd.ViewError, match="positive finite times"):
            hd.describe(square, [hd.DescriptorSpec("ft-pvhk")], times=times)
    with pytest.raises(hd.ViewError, match="positive finite times"):
        candidate_descriptors(square, [220], hd.DescriptorSpec("ft-pvhk"), times=[])
    with pytest.raises(hd.SpecError, match="at least 0.01"):  # 1e-9 gave a false "does not reach T"
        hd.DescriptorSpec("pvst", threshold=1e-9)
    d = hd.pvst(square, 16, threshold=0.01, source="center")
    assert np.all(np.isfinite(d.values)) and d.repairs == ()


def test_the_pvst_s_default_source_is_off_the_outline_where_the_image_centre_is_on_it():
    mask = np.zeros((21, 21), bool)
    mask[:, :7] = mask[14:, :] = True  # an L: the image centre falls outside it, the nearest vertex on its outline
    view = lattice_view(mask)
    with pytest.raises(hd.ViewError, match="interior source"):
        hd.describe(view, [hd.DescriptorSpec("pvst", 16, "center")])
    spec = hd.DescriptorSpec("pvst", 16)
    assert spec.source == "interior" and hd.pvst(view, 16).source == hd.describe(view, [spec])[0].source
    assert np.isfinite(hd.describe(view, [spec])[0].values).all()
    assert hd.DescriptorSpec("pvhk").source == "closest"  # the other kinds keep theirs
