"""The PVST (heatdata.descriptors.stochastic_time, thesis 5.4): analytic cases, a dense reference, its options and
its interior source."""

import logging
import sys

import numpy as np
import pytest
from conftest import square_view
from lattices import lattice_view
from scipy.optimize import brentq

import heatdata as hd
from heatdata.descriptors import (
    heat_operator,
)


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
