"""The heat kinds (heatdata.descriptors.heat): PVHK, C-PVHK and FT-PVHK, time scales, part weights and the global
derivative (thesis ch. 2-3, 5), on analytic cases and against dense references."""

import logging

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse.linalg as sla
from conftest import grid_mesh, square_view
from lattices import lattice_view, squares

import heatdata as hd
import heatdata.descriptors.heat as descriptors
from heatdata.core.spectrum import lambda2, laplacian
from heatdata.descriptors import (
    global_derivative,
    heat_operator,
    object_time_scale,
    part_weights,
    source_vertex,
    view_time_scale,
)
from heatdata.descriptors.boundary import color_rates


@pytest.mark.parametrize("sampling", ["arclength", "polar"])
def test_disc_with_central_source_gives_flat_pvhk(disc, sampling):
    centre = source_vertex(disc, "center")
    assert np.hypot(*disc.vertices[centre, :2]) < 1e-9
    d = hd.pvhk(disc, 64, source="center", sampling=sampling)
    assert d.source == centre
    assert np.std(d.values) / np.mean(d.values) < 0.005  # measured 0.26%: the rings are only nearly round
    off = hd.pvhk(disc, 64, source=int(np.argmax(disc.vertices[:, 0] - 10 * np.abs(disc.vertices[:, 1]))))
    assert np.std(off.values) / np.mean(off.values) > 5 * np.std(d.values) / np.mean(d.values)


@pytest.mark.slow
def test_pvhk_matches_expm_reference(mug):
    view = hd.render_view(mug, 40.0, 30.0, 1.4, seed=3)
    d = hd.pvhk(view, samples=None)
    L = laplacian(view.vertices, view.edges)
    pulse = np.zeros(view.n_vertices)
    pulse[d.source] = 1.0
    exact = sla.expm_multiply(-d.time * L, pulse)[view.boundary] * view.n_vertices
    assert np.max(np.abs(d.values - exact)) < 1e-6
    assert d.time == pytest.approx(1.0 / d.lambda2)


def test_eigen_and_krylov_methods_agree(mug):
    view = hd.render_view(mug, 120.0, 30.0, 1.4, seed=4)
    fast = hd.pvhk(view, 64)
    thesis = hd.pvhk(view, 64, method="eigen", modes=30)
    assert np.max(np.abs(fast.values - thesis.values)) < 1e-6
    assert fast.lambda2 == pytest.approx(thesis.lambda2, rel=1e-9)


def test_constant_color_rates_give_the_plain_pvhk(mug):
    view = hd.render_view(mug, 10.0, 30.0, 1.4, seed=5)
    plain = hd.pvhk(view, 64)
    colored = hd.c_pvhk(view, 64, color_map=lambda rgb: np.full(len(rgb), 3.7))
    assert np.max(np.abs(plain.values - colored.values)) < 1e-7  # C = kI rescales time only
    assert colored.time == pytest.approx(3.7 * plain.time)


def test_the_shape_clock_sees_a_colour_the_same_all_over(mug):
    view = hd.render_view(mug, 10.0, 30.0, 1.4, seed=5)
    plain = hd.pvhk(view, 64)
    colored = hd.c_pvhk(view, 64, color_map=lambda rgb: np.full(len(rgb), 3.7), clock="shape")
    assert colored.time == pytest.approx(plain.time)  # the colourless view's 1/lambda_2
    later = hd.ft_pvhk(view, plain.time / 3.7, 64)  # C = kI: the coloured heat at t is the plain heat at t/k
    assert np.max(np.abs(colored.values - later.values)) < 1e-7
    assert np.max(np.abs(colored.values - plain.values)) > 1e-3


def test_sat_hue_gives_greys_one_rate_whatever_their_shade():
    vertices, faces = grid_mesh(11, 11)
    shades = np.linspace(0.1, 0.9, len(vertices))[:, None] * np.ones(3)
    view = hd.View.from_arrays(vertices, faces, shades)
    assert np.array_equal(color_rates(view, "sat-hue"), np.ones(len(vertices)))
    red, blue = (
        hd.View.from_arrays(vertices, faces, np.tile(c, (len(vertices), 1))) for c in ([1.0, 0, 0], [0, 0, 1.0])
    )
    assert color_rates(red, "sat-hue") == pytest.approx(1.0)
    assert color_rates(blue, "sat-hue") == pytest.approx(1.0 + 8.0 * 2.0 / 3.0)


def test_color_changes_the_descriptor():
    vertices, faces = grid_mesh(21, 21)
    colors = np.where(vertices[:, [0]] > 0, [[1.0, 0, 0]], [[0, 0, 1.0]])  # red right half, blue left
    view = hd.View.from_arrays(vertices, faces, colors)
    plain = hd.pvhk(view, 64, source="center")
    for name in ("c1", "c2", "c3", "c4", "hue", "sat-hue"):
        colored = hd.c_pvhk(view, 64, name, source="center")
        assert colored.kind == "c-pvhk" and colored.color_map == name
        assert np.max(np.abs(colored.values - plain.values)) > 1e-3


def test_bad_color_maps(square):
    with pytest.raises(hd.SpecError, match="colour map"):
        hd.c_pvhk(square, 64, "c9")
    with pytest.raises(hd.ViewError, match="positive"):
        hd.c_pvhk(square, 64, lambda rgb: -np.ones(len(rgb)))


def test_several_components_keep_the_source_component(caplog):
    caplog.set_level(logging.INFO, logger="heatdata.views.view")
    v1, f1 = grid_mesh(12, 12)
    v2, f2 = grid_mesh(8, 8)
    vertices = np.vstack([v1, v2 + [0.1, 0, 0.2]])  # second part farther from the camera
    view = hd.View.from_arrays(vertices, np.vstack([f1, f2 + len(v1)]))
    d = hd.pvhk(view, 32, source="closest")
    assert d.source < len(v1)
    assert any("kept the component" in r for r in d.repairs)
    assert "kept the component" in caplog.text
    alone = hd.pvhk(hd.View.from_arrays(v1, f1), 32, source="closest")
    assert np.allclose(d.values, alone.values, atol=1e-9)


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
