"""Nearest neighbours (heatdata.recognition.nearest): Alg. 3.1 over a library, and Alg. 6.1 over a view's candidates."""

import numpy as np
import pytest

import heatdata as hd
from heatdata.core.distances import Nearest, NearestPair, mhd_matrix, nearest_pair_mhd
from heatdata.descriptors.sources import candidate_descriptors, candidate_sources
from heatdata.recognition.metrics import confusion_matrix, precision_by
from heatdata.recognition.nearest import classify_candidates, nearest_neighbors


def test_nearest_neighbors_and_confusion():
    library = np.array([[0.0] * 8, [1.0] * 8])
    queries = np.array([[0.1] * 8, [0.9] * 8, [0.2] * 8])
    nn = nearest_neighbors(queries, library)
    assert nn.index.tolist() == [0, 1, 0]
    table = confusion_matrix(["a", "b", "b"], ["a", "b", "a"])
    assert table.loc["b", "a"] == 1 and table.loc["a", "a"] == 1
    precision = precision_by(np.array(["a", "b", "b"]), np.array(["a", "b", "a"]))
    assert precision["a"] == 1.0 and precision["b"] == 0.5 and precision["all"] == pytest.approx(2 / 3)


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
