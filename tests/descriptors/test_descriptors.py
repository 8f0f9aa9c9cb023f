"""PVHK and C-PVHK: analytic cases, options and bad input."""

import logging

import numpy as np
import pytest
import scipy.sparse.linalg as sla
from conftest import grid_mesh

import heatdata as hd
from heatdata.core.spectrum import laplacian
from heatdata.descriptors import heat_kernel, sample_boundary, source_vertex
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


def test_source_rules():
    vertices, faces = grid_mesh(15, 15)
    vertices[:, 2] += 0.5 * vertices[:, 0] + 0.01 * (vertices[:, 0] ** 2 + vertices[:, 1] ** 2)
    vertices[:, :2] += 0.004  # the optical axis is off the grid centre
    view = hd.View.from_arrays(vertices, faces)
    closest = source_vertex(view, "closest")
    center = source_vertex(view, "center")
    assert closest == np.argmin(np.linalg.norm(view.vertices, axis=1))  # eq. 2.7
    # eq. 2.8 in the camera frame turned to face the segment: its image's bounding box centred on the optical axis
    turned = view.vertices @ view.canonical_rotation.T
    image = turned[:, :2] / turned[:, 2:]
    assert np.allclose(image.min(axis=0) + image.max(axis=0), 0.0, atol=1e-5)
    assert center == np.argmin(np.hypot(turned[:, 0], turned[:, 1]))
    assert closest != center
    with pytest.raises(hd.ViewError, match="source rule"):
        source_vertex(view, "nearest")
    with pytest.raises(hd.ViewError, match="not in"):
        source_vertex(view, 10_000)


def test_samples_none_gives_one_value_per_boundary_vertex(disc):
    d = hd.pvhk(disc, samples=None)
    assert d.values.shape == disc.boundary.shape
    assert d.positions[0] == 0.0 and np.all(np.diff(d.positions) > 0) and d.positions[-1] < 1.0


def test_arclength_samples_interpolate_per_vertex_values(disc):
    full = hd.pvhk(disc, samples=None)
    sampled = hd.pvhk(disc, samples=32)
    closed_pos = np.append(full.positions, 1.0)
    closed_val = np.append(full.values, full.values[0])
    assert np.allclose(sampled.values, np.interp(sampled.positions, closed_pos, closed_val))


def test_polar_samples_follow_the_angle(square):
    view = square
    temps = view.planar[view.boundary, 0]  # value = x coordinate of the boundary point
    values, positions = sample_boundary(view, view.boundary, temps, 8, "polar")
    theta = 2 * np.pi * positions
    # rays at 0, 45, 90 ... deg cross the square's boundary where x = r cos(theta)
    assert values[0] > 0 and values[4] < 0 and abs(values[2]) < 1e-9 and abs(values[6]) < 1e-9
    assert np.allclose(values[[1, 3, 5, 7]], values[0] * np.sign(np.cos(theta[[1, 3, 5, 7]])), atol=1e-9)


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


def test_describe_shares_work_and_matches_single_calls(mug):
    view = hd.render_view(mug, 200.0, 30.0, 1.4, seed=6)
    specs = [hd.DescriptorSpec("pvhk", 64, s, p) for s in ("closest", "center") for p in ("arclength", "polar")]
    specs.append(hd.DescriptorSpec("c-pvhk", 64, "center", "polar", "c3"))
    together = hd.describe(view, specs)
    for spec, d in zip(specs, together, strict=True):
        if spec.kind == "pvhk":
            alone = hd.pvhk(view, 64, spec.source, sampling=spec.sampling)
        else:
            alone = hd.c_pvhk(view, 64, "c3", spec.source, sampling=spec.sampling)
        assert np.array_equal(d.values, alone.values)
    assert specs[-1].name == "c-pvhk/polar/center/64/c3"


def test_descriptor_spec_validation():
    with pytest.raises(hd.SpecError, match="kind"):
        hd.DescriptorSpec("shot")
    with pytest.raises(hd.SpecError, match="color_map"):
        hd.DescriptorSpec("c-pvhk")
    with pytest.raises(hd.SpecError, match="sampling"):
        hd.DescriptorSpec(sampling="random")


def test_heat_kernel_public_api(disc):
    temps = heat_kernel(disc, source="center", times=[1e-4, 1e-3])
    assert temps.shape == (2, disc.n_vertices)
    centre = source_vertex(disc, "center")
    assert temps[0, centre] > temps[1, centre] > 1.0  # cooling at the source
    assert np.allclose(temps.mean(axis=1), 1.0, atol=1e-9)  # heat conserved (c = 1)


def test_interior_source_is_farthest_from_the_outline(square, disc):
    assert source_vertex(disc, "interior") == 0  # the disc's centre
    s = source_vertex(square, "interior")
    assert np.allclose(square.vertices[s, :2], 0.0)  # the square's centre
    assert s not in set(square.boundary)
