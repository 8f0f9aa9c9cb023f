"""The exact nearest-descriptor search under eq. 3.1 / 5.14 (heatdata.core.distances.nearest_mhd)."""

import importlib

import numpy as np
import pytest

import heatdata as hd
from heatdata.core.distances import chi_square_matrix, mhd_matrix, nearest_mhd, weighted_mhd
from heatdata.recognition.nearest import nearest_neighbors


def pvhk_like(rng, n, m=64):
    x = np.linspace(0, 2 * np.pi, m, endpoint=False)
    return 1 + 0.3 * rng.uniform(0.2, 1, (n, 1)) * np.sin(np.outer(rng.uniform(1, 4, n), x) + rng.uniform(0, 6, (n, 1)))


def reference(queries, library, wq=None, wl=None):
    """The plain definition, pair by pair (eq. 3.1 / 5.14 via weighted_mhd)."""
    wq = np.ones(queries.shape) if wq is None else wq
    wl = np.ones(library.shape) if wl is None else wl
    d = np.array([[weighted_mhd(q, z, a, b) for z, b in zip(library, wl)] for q, a in zip(queries, wq)])
    return np.argmin(d, axis=1), d.min(axis=1)


@pytest.mark.parametrize("block", [4096, 7])
def test_the_search_finds_the_plain_definition_s_nearest_item_and_distance(block, monkeypatch):
    # envelopes held 7 items at a time (the module: hd.distance is the descriptor-level function)
    monkeypatch.setattr(importlib.import_module("heatdata.core.distances"), "SEARCH_BLOCK", block)
    rng = np.random.default_rng(0)
    library, queries = pvhk_like(rng, 300), pvhk_like(rng, 12)
    index, distance = nearest_mhd(queries, library)
    expected_index, expected = reference(queries, library)
    np.testing.assert_array_equal(index, expected_index)
    np.testing.assert_allclose(distance, expected, rtol=1e-12)
    matrix = mhd_matrix(queries, library)  # float32: the same items
    np.testing.assert_array_equal(np.argmin(matrix, axis=1), index)


def test_part_weights_and_curves_of_other_lengths():
    rng = np.random.default_rng(1)
    library, queries = pvhk_like(rng, 80, 48), pvhk_like(rng, 6, 64)
    wq, wl = rng.uniform(0.1, 2, queries.shape), rng.uniform(0.1, 2, library.shape)
    index, distance = nearest_mhd(queries, library, query_weights=wq, library_weights=wl)
    expected_index, expected = reference(queries, library, wq, wl)
    np.testing.assert_array_equal(index, expected_index)
    np.testing.assert_allclose(distance, expected, rtol=1e-12)


def test_an_item_equal_to_the_query_is_found_at_distance_zero_and_ties_go_to_the_first():
    rng = np.random.default_rng(2)
    library = pvhk_like(rng, 50)
    library[30] = library[7]
    index, distance = nearest_mhd(library[[7, 12]], library)
    assert index.tolist() == [7, 12] and distance.tolist() == [0.0, 0.0]
    # a one-sample shift: every point has its twin 1/M away, so the distance is at most 1 (eq. 3.1 sums)
    shifted = np.roll(library[3], 1)[None]
    i, d = nearest_mhd(shifted, library)
    assert i[0] == 3 and d[0] <= 64 * (1 / 64) + 1e-12


def test_the_heat_kinds_and_the_recognizer_search_this_way():
    rng = np.random.default_rng(3)
    library, queries = pvhk_like(rng, 40), pvhk_like(rng, 5)
    index, distance = hd.descriptors.kind_of("pvhk").nearest(queries, library)
    nn = nearest_neighbors(queries, library)
    np.testing.assert_array_equal(nn.index, index)
    matrix = nearest_neighbors(queries, library, distance=mhd_matrix)  # any distance matrix still works
    np.testing.assert_array_equal(matrix.index, index)
    np.testing.assert_allclose(matrix.distance, distance, rtol=1e-5)


def test_bad_input():
    good = np.ones((2, 8))
    with pytest.raises(hd.HeatdataError, match="NaN"):
        nearest_mhd(np.full((1, 8), np.nan), good)
    with pytest.raises(hd.HeatdataError, match="library of one descriptor"):
        nearest_mhd(good, np.empty((0, 8)))
    with pytest.raises(hd.HeatdataError, match="both the queries and the library"):
        nearest_mhd(good, good, query_weights=good)


def test_other_kinds_search_their_distance_matrix_in_chunks():
    rng = np.random.default_rng(4)
    library, queries = rng.dirichlet(np.ones(16), 30), rng.dirichlet(np.ones(16), 9)
    index, distance = hd.descriptors.kind_of("esf").nearest(queries, library, chunk=4)
    d = chi_square_matrix(queries, library)
    np.testing.assert_array_equal(index, np.argmin(d, axis=1))
    np.testing.assert_allclose(distance, d.min(axis=1))


def test_within_seeks_only_items_nearer_than_a_given_distance():
    rng = np.random.default_rng(5)
    library, queries = pvhk_like(rng, 60), pvhk_like(rng, 8)
    index, distance = nearest_mhd(queries, library)
    within = np.where(np.arange(8) % 2 == 0, distance * 1.5, distance)  # odd queries: the nearest is not nearer
    i, d = nearest_mhd(queries, library, within=within)
    np.testing.assert_array_equal(i, np.where(np.arange(8) % 2 == 0, index, -1))
    np.testing.assert_allclose(d, distance)
    esf = hd.descriptors.kind_of("esf")  # the base class's matrix search means the same
    hist_l, hist_q = rng.dirichlet(np.ones(8), 20), rng.dirichlet(np.ones(8), 4)
    full = esf.nearest(hist_q, hist_l)
    j, e = esf.nearest(hist_q, hist_l, within=np.array([np.inf, 0.0, full.distance[2], 1.0]))
    assert j.tolist() == [full.index[0], -1, -1, full.index[3]] and e[1] == 0.0
    with pytest.raises(hd.HeatdataError, match="one distance per query"):
        nearest_mhd(queries, library, within=[1.0])
