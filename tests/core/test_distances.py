"""The modified Hausdorff distance of eq. 3.1 and its batched form."""

import numpy as np
import pytest

import heatdata as hd
from heatdata.core.distances import mhd, mhd_matrix, weighted_mhd


@pytest.fixture
def curves():
    rng = np.random.default_rng(0)
    x = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    return 1.0 + 0.2 * np.sin(3 * x) + 0.01 * rng.standard_normal(64), 1.0 + 0.2 * np.cos(2 * x)


def test_zero_on_identical_curves(curves):
    a, _ = curves
    assert mhd(a, a) == 0.0


def test_symmetric(curves):
    a, b = curves
    assert mhd(a, b) == pytest.approx(mhd(b, a))


def test_small_for_a_one_sample_shift(curves):
    x = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    a, b = 1.0 + 0.2 * np.sin(3 * x), curves[1]
    shifted = np.roll(a, 1)
    # a shift of the boundary parameterization (3.2): every point has its twin 1/M away
    assert mhd(a, shifted) <= 64 * (1 / 64) + 1e-12
    assert mhd(a, shifted) < 0.5 * np.abs(a - shifted).sum()
    assert mhd(a, shifted) < 0.3 * mhd(a, b)


def test_matches_definition_on_a_hand_example():
    z1, z2 = np.array([0.0, 1.0]), np.array([0.0, 0.0, 1.0])
    x1, x2 = np.array([0.5, 1.0]), np.array([1 / 3, 2 / 3, 1.0])
    d = np.hypot(x1[:, None] - x2[None, :], z1[:, None] - z2[None, :])
    expected = min(d.min(axis=1).sum(), d.min(axis=0).sum())
    assert mhd(z1, z2) == pytest.approx(expected)


def test_matrix_equals_pairwise_and_chunks_do_not_matter():
    rng = np.random.default_rng(1)
    queries, library = rng.random((7, 16)), rng.random((23, 16))
    pairwise = np.array([[mhd(q, x) for x in library] for q in queries])
    assert np.allclose(mhd_matrix(queries, library, dtype=np.float64), pairwise)
    assert np.allclose(mhd_matrix(queries, library, chunk_elements=300), pairwise, atol=1e-5)
    longer = rng.random((5, 24))  # different lengths take the full-tensor path
    assert np.allclose(mhd_matrix(queries, longer, dtype=np.float64), [[mhd(q, x) for x in longer] for q in queries])


def test_matrix_on_descriptor_like_curves():
    rng = np.random.default_rng(2)
    x = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    curves = 1 + 0.3 * np.sin(np.outer(rng.uniform(1, 4, 30), x) + rng.uniform(0, 6, (30, 1)))
    curves[5] = curves[4] + 1e-3  # near neighbours stop the offset loop early
    pairwise = np.array([[mhd(p, q) for q in curves] for p in curves[:8]])
    assert np.allclose(mhd_matrix(curves[:8], curves, dtype=np.float64), pairwise, rtol=1e-12)


def test_bad_input():
    with pytest.raises(hd.HeatdataError):
        mhd(np.zeros((2, 2)), np.zeros(2))


def test_l1_bounds_the_mhd_from_above(curves):
    a, b = curves
    assert mhd(a, b) <= np.abs(a - b).sum() + 1e-12


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
