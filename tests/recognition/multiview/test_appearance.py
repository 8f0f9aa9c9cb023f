"""The appearance model of thesis 4.3 (heatdata.recognition.multiview.appearance): the set distance (eq. 4.4), its
scale (eq. 4.5) and the similarity between library views (eq. 4.6)."""

import numpy as np
import pandas as pd
import pytest
from cupmug import cup_mug, cup_mug_similarity

from heatdata.core.distances import mhd
from heatdata.recognition.multiview.appearance import (
    appearance_model,
    learn_similarity,
    set_distance,
    similarity_matrix,
)
from heatdata.recognition.multiview.filters import ParticleFilter


def test_set_distance_is_eq_4_4():
    assert set_distance(np.array([[1.0, 2.0], [3.0, 0.5]])) == pytest.approx(1.5)
    assert set_distance(np.array([[1.0, 3.0]])) == pytest.approx(1.0)  # min(1, 1 + 3): sets of other sizes


def test_alpha_is_the_mean_leave_one_out_distance_eq_4_5():
    rows = pd.DataFrame({"object": "a", "azimuth": 0.0, "values": [np.zeros(8), np.full(8, 0.1)]})
    model = appearance_model(pd.concat([rows, rows.assign(azimuth=90.0)]))
    first = mhd(np.zeros(8), np.full(8, 0.1))
    np.testing.assert_allclose(model.alpha, [first, first])
    single = appearance_model(
        pd.DataFrame(
            {"object": "a", "azimuth": [0.0, 90.0, 180.0], "values": [np.zeros(8), np.full(8, 0.1), np.full(8, 0.3)]}
        )
    )
    # one view per angle: the distance to the nearest neighbouring angle
    np.testing.assert_allclose(single.alpha, [first, first, mhd(np.full(8, 0.1), np.full(8, 0.3))])
    assert appearance_model(rows, alpha=0.08).alpha.tolist() == [0.08]


def test_alpha_learned_from_independent_views_is_their_mean_distance_to_the_library_view():
    library = pd.DataFrame({"object": "a", "azimuth": [0.0, 180.0], "values": [np.zeros(8), np.ones(8)]})
    views = pd.DataFrame(
        {"object": "a", "azimuth": [2.0, 358.0, 181.0], "values": [np.full(8, 0.1), np.full(8, 0.3), np.full(8, 1.2)]}
    )
    model = appearance_model(library, views=views)
    expected = [
        (mhd(np.zeros(8), np.full(8, 0.1)) + mhd(np.zeros(8), np.full(8, 0.3))) / 2,
        mhd(np.ones(8), np.full(8, 1.2)),
    ]
    np.testing.assert_allclose(model.alpha, expected, rtol=1e-6)  # mhd_matrix works in float32 chunks
    two = pd.concat([library, library.assign(object="b")])
    similarity = learn_similarity(two, pd.concat([views, views.assign(object="b")]))
    f = ParticleFilter(two, similarity, particles=4, seed=0)
    np.testing.assert_allclose(f.model.alpha, expected * 2, rtol=1e-6)  # the filter takes the learned alpha
    assert ParticleFilter(two, similarity, particles=4, alpha=0.5, seed=0).model.alpha.tolist() == [0.5] * 4


def test_similarity_is_high_between_look_alike_views():
    library, similarity = cup_mug(), cup_mug_similarity()
    model = appearance_model(library)
    mu = similarity_matrix(model, similarity)
    at = {(o, a): k for k, (o, a) in enumerate(zip(model.labels["object"], model.labels["azimuth"]))}
    assert mu[at["mug", 0.0], at["cup", 0.0]] > 0.5 * mu[at["mug", 0.0], at["mug", 0.0]]  # handle hidden
    assert mu[at["mug", 120.0], at["cup", 120.0]] < 1e-6 * mu[at["mug", 120.0], at["mug", 120.0]]  # handle seen
    assert list(similarity.columns) == [
        "object",
        "azimuth",
        "similar_object",
        "similar_azimuth",
        "similarity",
        "similar_alpha",
    ]
