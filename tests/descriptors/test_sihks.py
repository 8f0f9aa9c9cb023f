"""SI-HKS bag of words: exact scale invariance, fitting before use, bad input."""

import numpy as np
import pytest
from conftest import square_view

import heatdata as hd
from heatdata.descriptors.sihks import signatures
from heatdata.descriptors.work import ViewWork


def test_signatures_are_scale_invariant():
    """With 1/d^2 edge weights eigenvalues scale by 1/s^2 under x -> s x and the times with them: the same
    signatures."""
    view = square_view(25, 0.004)
    big = hd.View.from_arrays(3.0 * view.vertices, view.faces)
    a, _, _ = signatures(ViewWork(view), 30, 6)
    b, _, _ = signatures(ViewWork(big), 30, 6)
    assert a.shape == (view.n_vertices, 6)
    np.testing.assert_allclose(a, b, rtol=1e-6, atol=1e-9)


def test_fit_then_describe(mug):
    views = [hd.render_view(mug, az, 30.0, 1.0, seed=k) for k, az in enumerate((0.0, 90.0, 180.0))]
    spec = hd.DescriptorSpec("si-hks", words=8, modes=30, fit_vertices=100)
    with pytest.raises(hd.SpecError, match="fitted on library views first"):
        hd.describe(views[0], [spec])
    fitted = hd.fit_spec(spec, views)
    assert fitted == spec and fitted.name == "si-hks/words=8/modes=30/fit_vertices=100"
    assert fitted.fitted["words"].shape == (8, 6)
    again = hd.fit_spec(spec, views)
    assert np.array_equal(fitted.fitted["words"], again.fitted["words"])  # seeded
    d = hd.describe(views[1], [fitted])[0]
    assert d.values.shape == (8,) and d.values.sum() == pytest.approx(1.0) and d.lambda2 > 0
    with pytest.raises(hd.SpecError, match=r"the fitted words is \(8, 6\), not finite \(4, 6\)"):
        hd.DescriptorSpec("si-hks", words=4, modes=30).with_fitted(fitted.fitted)
    with pytest.raises(hd.SpecError, match="the fitted mean"):
        spec.with_fitted({**fitted.fitted, "mean": np.full(6, np.nan)})
    with pytest.raises(hd.SpecError, match="a fit of"):
        spec.with_fitted({"words": fitted.fitted["words"]})
    with pytest.raises(hd.ViewError, match="at least one library view"):
        hd.fit_spec(spec, [])
