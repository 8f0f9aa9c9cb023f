"""Kinds combined: the parts' scales and weights learned on library views, the self-describing header, errors."""

import numpy as np
import pytest
from conftest import disc_view, square_view

import heatdata as hd
from heatdata.core.distances import mhd_matrix
from heatdata.descriptors.combined import layout, simplex_grid

PARTS = [{"kind": "hgd", "bins": 8}, {"kind": "pvhk", "samples": 16, "source": "center", "sampling": "polar"}]


def library() -> list[hd.View]:
    """Two objects that differ in size only (a square plate of 4 and of 6 cm), two noisy views each, and a disc."""
    rng = np.random.default_rng(0)
    views = []
    for name, make in (
        ("small", lambda: square_view(21, 0.002)),
        ("large", lambda: square_view(21, 0.003)),
        ("disc", lambda: disc_view(10, 0.002)),
    ):
        for k in range(2):
            base = make()
            jitter = base.vertices + rng.normal(0.0, 2e-5, base.vertices.shape)
            views.append(hd.View.from_arrays(jitter, base.faces, view_id=f"{name}-{k}", object_id=name))
    return views


def test_the_weights_learned_on_library_views_favour_the_part_that_tells_them_apart():
    """The PVHK is scale-free (stopped at 1/lambda_2), so only the HGD tells the two plates apart."""
    views = library()
    pvhk = np.stack([hd.describe(v, [hd.DescriptorSpec(**PARTS[1])])[0].values for v in views])
    d = mhd_matrix(pvhk, pvhk) + np.diag(np.full(len(views), np.inf))
    objects = np.array([v.object_id for v in views])
    assert np.mean(objects[d.argmin(axis=1)] == objects) < 1.0  # the PVHK alone confuses the plates
    spec = hd.fit_spec(hd.DescriptorSpec("combined", parts=PARTS), views)
    weights, scales = spec.fitted["weights"], spec.fitted["scales"]
    assert weights.sum() == pytest.approx(1.0) and weights[0] > 0 and np.all(scales > 0)
    assert spec.fitted["leave_one_out"] == 1.0
    assert np.allclose(spec.fitted["coefficients"], weights / scales)
    assert spec.name == "combined/hgd/bins=8+pvhk/polar/center/16"


def test_the_distance_is_the_sum_of_the_scaled_part_distances_read_from_the_header():
    views = library()
    spec = hd.fit_spec(hd.DescriptorSpec("combined", parts=PARTS, how="sum"), views)
    assert np.array_equal(spec.fitted["weights"], [1.0, 1.0])
    a, b = (hd.describe(v, [spec])[0] for v in (views[0], views[2]))
    hgd, pvhk = (hd.describe(v, [hd.DescriptorSpec(**p) for p in PARTS]) for v in (views[0], views[2]))
    kinds, slices, coefficients = layout(a.values)
    assert [k.name for k in kinds] == ["hgd", "pvhk"] and np.array_equal(a.values[slices[1]], hgd[1].values)
    expected = sum(c * hd.distance(x, y) for c, x, y in zip(coefficients, hgd, pvhk, strict=True))
    assert hd.distance(a, b) == pytest.approx(expected)
    assert hd.distance(a, a) == 0.0


def test_descriptors_of_another_fit_or_parts_are_not_compared():
    views = library()
    one = hd.fit_spec(hd.DescriptorSpec("combined", parts=PARTS), views)
    other = hd.fit_spec(hd.DescriptorSpec("combined", parts=PARTS, how="sum"), views)
    a, b = hd.describe(views[0], [one])[0], hd.describe(views[0], [other])[0]
    with pytest.raises(hd.HeatdataError, match="different parts, lengths or fits"):
        hd.distance(a, b)


def test_bad_parts_are_config_errors():
    with pytest.raises(hd.SpecError, match="parts is needed"):
        hd.DescriptorSpec("combined")
    with pytest.raises(hd.SpecError, match="two or more parts"):
        hd.DescriptorSpec("combined", parts=[{"kind": "hgd"}])
    with pytest.raises(hd.SpecError, match="si-hks cannot be a part"):
        hd.DescriptorSpec("combined", parts=[{"kind": "hgd"}, {"kind": "si-hks"}])
    with pytest.raises(hd.SpecError, match="same part twice"):
        hd.DescriptorSpec("combined", parts=[{"kind": "hgd"}, {"kind": "hgd"}])
    with pytest.raises(hd.SpecError, match="must be fitted"):
        hd.describe(library()[0], [hd.DescriptorSpec("combined", parts=PARTS)])


def test_the_weight_grid_covers_the_simplex():
    grid = simplex_grid(3)
    assert len(grid) == 66 and all(sum(w) == pytest.approx(1.0) for w in grid) and (1.0, 0.0, 0.0) in grid
