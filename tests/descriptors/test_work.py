"""A view's shared heat work (heatdata.descriptors.work): heat_kernel and the checks of its times."""

import numpy as np
import pytest

import heatdata as hd
from heatdata.descriptors import (
    heat_kernel,
    source_vertex,
)
from heatdata.descriptors.sources import candidate_descriptors


def test_heat_kernel_public_api(disc):
    temps = heat_kernel(disc, source="center", times=[1e-4, 1e-3])
    assert temps.shape == (2, disc.n_vertices)
    centre = source_vertex(disc, "center")
    assert temps[0, centre] > temps[1, centre] > 1.0  # cooling at the source
    assert np.allclose(temps.mean(axis=1), 1.0, atol=1e-9)  # heat conserved (c = 1)


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
