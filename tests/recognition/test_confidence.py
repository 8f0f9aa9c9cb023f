"""Calibrated confidence: learned from a library's own views (leave one view out: known; leave its object out:
unknown), in [0, 1], lower the farther an answer lies, and refused where it cannot be learned."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import heatdata as hd
from heatdata.errors import HeatdataError
from heatdata.recognition.confidence import (
    CALIBRATION_VIEWS,
    Confidence,
    answer_features,
    calibrate,
    calibration_rows,
    checked_threshold,
    default_side,
    nearest_two,
)


def line_library(objects=3, views=10, spacing=0.01, gap=1.0):
    """Views on a line: each object's ``views`` a ``spacing`` apart, the objects ``gap`` apart; |x - y| distances."""
    x = np.concatenate([o * gap + spacing * np.arange(views) for o in range(objects)])
    names = np.repeat([f"object-{o}" for o in range(objects)], views)
    return np.abs(x[:, None] - x[None, :]), names


def test_nearest_two_finds_the_nearest_view_and_the_nearest_other_object():
    distance = np.array([[0.3, 0.1, 0.5, 0.2], [0.9, 0.8, 0.1, 0.7]])
    objects = np.array(["a", "a", "b", "c"])
    best, nearest, other = nearest_two(distance, objects)
    assert best.tolist() == [1, 2] and nearest.tolist() == [0.1, 0.1] and other.tolist() == [0.2, 0.7]
    _, _, alone = nearest_two(np.array([[0.1, 0.2]]), np.array(["a", "a"]))
    assert alone.tolist() == [np.inf]


def test_a_library_whose_objects_lie_apart_separates_known_from_unknown():
    distance, objects = line_library()
    confidence = calibrate(distance, objects, np.arange(len(objects)))
    assert confidence.auroc == 1.0 and confidence.known == confidence.unknown == 30
    assert confidence.coef[0] < 0  # farther: less sure
    near, far = confidence(0.01, 1.0), confidence(1.0, 1.0)
    assert near[0] > 0.9 and far[0] < 0.1


@given(st.lists(st.floats(1e-9, 1e3), min_size=1, max_size=20), st.floats(1e-9, 1e3))
def test_confidence_lies_in_zero_one_and_falls_as_the_answer_moves_away(nearest, other):
    distance, objects = line_library()
    confidence = calibrate(distance, objects, np.arange(len(objects)))
    d = np.sort(np.asarray(nearest))
    c = confidence(d, np.full(len(d), max(other, d.max())))
    assert np.all((c >= 0) & (c <= 1))
    assert np.all(np.diff(confidence(d, np.full(len(d), 1e3))) <= 1e-12)


def test_it_round_trips_through_a_library_file_metadata():
    distance, objects = line_library()
    confidence = calibrate(distance, objects, np.arange(len(objects)), threshold=0.3)
    again = Confidence.from_dict(confidence.to_dict())
    assert again == confidence and again.threshold == 0.3


def test_what_cannot_be_learned_or_used_is_refused():
    distance, objects = line_library(objects=1)
    with pytest.raises(hd.HeatdataError, match="one object"):
        calibrate(distance, objects, np.arange(len(objects)))
    for bad in (-0.1, 1.01, float("nan"), None, "sure"):
        with pytest.raises(hd.HeatdataError, match=r"threshold is a number in \[0, 1\]"):
            checked_threshold(bad)
    assert checked_threshold("0.25") == 0.25 and checked_threshold(1) == 1.0


def test_a_large_library_is_calibrated_on_a_seeded_sample():
    assert calibration_rows(10).tolist() == list(range(10))
    rows = calibration_rows(CALIBRATION_VIEWS * 3)
    assert len(rows) == CALIBRATION_VIEWS and np.all(np.diff(rows) > 0)
    assert np.array_equal(rows, calibration_rows(CALIBRATION_VIEWS * 3))


def test_an_exact_match_and_a_lone_object_have_finite_features():
    features = answer_features(np.array([0.0, 0.5]), np.array([np.inf, 1.0]))
    assert np.all(np.isfinite(features)) and features[1, 1] == pytest.approx(np.log(0.5))


def test_the_default_threshold_rejects_most_of_the_librarys_own_unknown_answers():
    distance, objects = line_library(objects=4, views=20, spacing=0.01, gap=0.3)
    confidence = calibrate(distance, objects, np.arange(len(objects)))
    lacking = np.where(objects[:, None] == objects[None, :], np.inf, distance)
    _, nearest, other = nearest_two(lacking, objects)
    rejected = np.mean(confidence(nearest, other) < confidence.threshold)
    assert 0.9 <= rejected <= 0.96  # REJECTED (0.95), to the quantile's step of 80 answers
    own = distance + np.diag(np.full(len(objects), np.inf))
    _, nearest, other = nearest_two(own, objects)
    assert np.mean(confidence(nearest, other) >= confidence.threshold) > 0.95  # the known ones kept


def test_a_learned_kinds_threshold_keeps_most_of_the_librarys_own_known_answers():
    steps = np.random.default_rng(0).uniform(0.005, 0.015, (4, 20))  # unequal neighbours: no ties among answers
    x = np.concatenate([o * 0.3 + np.cumsum(steps[o]) for o in range(4)])
    distance, objects = np.abs(x[:, None] - x[None, :]), np.repeat([f"object-{o}" for o in range(4)], 20)
    confidence = calibrate(distance, objects, np.arange(len(objects)), side="known")
    own = distance + np.diag(np.full(len(objects), np.inf))
    _, nearest, other = nearest_two(own, objects)
    kept = np.mean(confidence(nearest, other) >= confidence.threshold)
    assert 0.94 <= kept <= 0.97  # KEPT (0.95), to the quantile's step of 80 answers
    unknown_side = calibrate(distance, objects, np.arange(len(objects)))
    assert confidence.threshold > unknown_side.threshold  # far apart objects: the known side is the stricter
    assert default_side(learned=True) == "known" and default_side(learned=False) == "unknown"
    with pytest.raises(HeatdataError, match="side is one of unknown, known"):
        calibrate(distance, objects, np.arange(len(objects)), side="both")
