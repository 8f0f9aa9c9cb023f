"""Open-set evaluation: each object left out in turn, the test views of the others known and its own unknown."""

import numpy as np
import pandas as pd
import pytest

import heatdata as hd
from heatdata.recognition.open_set import open_set_scores, open_set_summary, threshold_sides


def histograms(objects, views, noise, seed):
    """Rows of an ESF-like kind: each object a distinct histogram (its own bins), each view a noisy copy."""
    rng = np.random.default_rng(seed)
    rows = []
    for o in range(objects):
        base = np.full(64, 0.1)
        base[8 * o : 8 * o + 8] = 5.0
        for v in range(views):
            values = base * (1 + noise * rng.standard_normal(64)).clip(0.1)
            rows.append({"object": f"object-{o}", "view_id": f"object-{o}/{v}", "values": values})
    return pd.DataFrame(rows)


def test_objects_apart_are_told_known_or_unknown_whichever_is_left_out():
    library = histograms(4, 12, 0.05, seed=0)
    tests = histograms(4, 5, 0.05, seed=1)
    scores = open_set_scores(library, tests, "esf")
    assert len(scores) == 4 * len(tests) and scores["left_out"].nunique() == 4
    assert (~scores["known"]).sum() == len(tests)  # each test view unknown once, in its own object's fold
    summary = open_set_summary(scores)
    assert summary["auroc"] == 1.0 and summary["precision"] == 1.0
    assert summary["known_kept"] >= 0.95 and summary["unknown_rejected"] >= 0.9
    fixed = open_set_summary(open_set_scores(library, tests, "esf", threshold=0.0))
    assert fixed["known_kept"] == 1.0 and fixed["unknown_rejected"] == 0.0  # 0: nothing is ever unknown


def test_what_it_cannot_measure_is_refused():
    library = histograms(2, 4, 0.05, seed=0)
    with pytest.raises(hd.HeatdataError, match="needs three"):
        open_set_scores(library, library, "esf")
    with pytest.raises(hd.HeatdataError, match="time-scaled"):
        open_set_scores(library, library, "ft-pvhk")


def test_a_fold_may_leave_out_several_objects_together():
    """The learned kind's one fold: the objects its network was not trained on, all unknown at once."""
    library = histograms(5, 12, 0.05, seed=0)
    tests = histograms(5, 5, 0.05, seed=1)
    scores = open_set_scores(library, tests, "esf", folds=[["object-1", "object-3"]])
    assert len(scores) == len(tests) and set(scores["left_out"]) == {"object-1, object-3"}
    assert set(scores.loc[~scores["known"], "object"]) == {"object-1", "object-3"}
    assert set(scores["nearest"]) <= {"object-0", "object-2", "object-4"}
    assert open_set_summary(scores)["auroc"] == 1.0
    with pytest.raises(hd.HeatdataError, match="two must remain"):
        open_set_scores(library, tests, "esf", folds=[["object-0", "object-1", "object-2", "object-3"]])


def test_either_side_of_the_librarys_own_answers_may_set_the_threshold():
    """The known side keeps about KEPT of the known answers; the default side is the kind's (unknown for the ESF)."""
    library = histograms(4, 12, 0.05, seed=0)
    tests = histograms(4, 5, 0.05, seed=1)
    sides = threshold_sides(library, tests, "esf")
    assert set(sides) == {
        "auroc",
        "known_kept_unknown",
        "unknown_rejected_unknown",
        "known_kept_known",
        "unknown_rejected_known",
    }
    default = open_set_summary(open_set_scores(library, tests, "esf"))
    assert (sides["known_kept_unknown"], sides["unknown_rejected_unknown"]) == (
        default["known_kept"],
        default["unknown_rejected"],
    )
    known = open_set_scores(library, tests, "esf", side="known")
    stricter = (known["threshold"] > open_set_scores(library, tests, "esf")["threshold"]).all()
    assert stricter  # objects far apart: their own unknown answers lie far below the known ones
    assert sides["known_kept_known"] <= sides["known_kept_unknown"]
    assert sides["unknown_rejected_known"] >= sides["unknown_rejected_unknown"]
