"""The modified Hausdorff distance of eq. 3.1 and its batched form."""

import numpy as np
import pytest

import heatdata as hd
from heatdata.core.distances import Nearest, NearestPair, mhd, mhd_matrix, nearest_pair_mhd, weighted_mhd
from heatdata.descriptors.sources import candidate_descriptors, candidate_sources
from heatdata.recognition.metrics import confusion_matrix, precision_by
from heatdata.recognition.nearest import classify_candidates, nearest_neighbors


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


def test_nearest_neighbors_and_confusion():
    library = np.array([[0.0] * 8, [1.0] * 8])
    queries = np.array([[0.1] * 8, [0.9] * 8, [0.2] * 8])
    nn = nearest_neighbors(queries, library)
    assert nn.index.tolist() == [0, 1, 0]
    table = confusion_matrix(["a", "b", "b"], ["a", "b", "a"])
    assert table.loc["b", "a"] == 1 and table.loc["a", "a"] == 1
    precision = precision_by(np.array(["a", "b", "b"]), np.array(["a", "b", "a"]))
    assert precision["a"] == 1.0 and precision["b"] == 0.5 and precision["all"] == pytest.approx(2 / 3)


def test_bad_input():
    with pytest.raises(hd.HeatdataError):
        mhd(np.zeros((2, 2)), np.zeros(2))


def test_l1_bounds_the_mhd_from_above(curves):
    a, b = curves
    assert mhd(a, b) <= np.abs(a - b).sum() + 1e-12


def test_nearest_pair_over_a_set_of_candidates():
    rng = np.random.default_rng(4)
    library = np.cumsum(rng.normal(size=(50, 32)), axis=1) * 0.05
    candidates = np.cumsum(rng.normal(size=(30, 32)), axis=1) * 0.05
    candidates[17] = library[23] + 1e-4
    pair = nearest_pair_mhd(candidates, library)
    distance = pair.distance
    assert (pair.query, pair.index, pair.label) == (17, 23, None) and distance == pytest.approx(32e-4, rel=1e-3)
    full = mhd_matrix(candidates, library)
    assert nearest_pair_mhd(candidates, library, shortlist=None).distance == pytest.approx(full.min(), rel=1e-6)
    with pytest.raises(hd.HeatdataError, match="one length"):
        nearest_pair_mhd(candidates, library[:, :16])
    match = classify_candidates(candidates, library, np.arange(50) // 10)
    assert (match.label, match.query, match.index) == (2, 17, 23)
    assert isinstance(match, NearestPair) and match.distance == distance
    with pytest.raises(hd.HeatdataError, match="49 labels for 50"):
        classify_candidates(candidates, library, np.arange(49))
    with pytest.raises(hd.HeatdataError, match="NaN"):
        nearest_pair_mhd(np.full((1, 32), np.nan), library)


def test_recognition_takes_the_descriptor_lists_the_api_returns(disc, square):
    spec = hd.DescriptorSpec("pvhk", 32, "center", "polar")
    library = hd.describe(disc, [spec]) + hd.describe(square, [spec])
    nn = nearest_neighbors(hd.describe(square, [spec]), library)
    assert nn.index.tolist() == [1] and nn.distance[0] == 0.0 and isinstance(nn, Nearest)
    candidates = candidate_descriptors(square, candidate_sources(square, 5), spec)
    match = classify_candidates(candidates, library, ["disc", "square"])
    assert (match.label, match.index) == ("square", 1)
    with pytest.raises(hd.HeatdataError, match="several kinds"):
        classify_candidates(candidates, library + hd.describe(disc, [hd.DescriptorSpec("esf")]), ["a"] * 3)
    with pytest.raises(hd.HeatdataError, match="candidates: nothing to stack"):
        classify_candidates([], library, ["disc", "square"])


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
