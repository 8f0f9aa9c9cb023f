"""Open-set evaluation: does a library's confidence tell its own objects from objects it lacks?

Each object is left out of the library in turn: the library without it is calibrated as
:func:`heatdata.recognition.confidence.calibrate` does (from its own views), and the run's *test* views are answered
by it, the left-out object's as unknown objects, every other object's as known ones. Pooled over the folds:

- ``auroc``: how well the confidence ranks known answers above unknown ones (1: always, 0.5: chance);
- ``known_kept`` and ``unknown_rejected`` at each fold's default threshold;
- ``precision``: the closed-set object precision (the nearest object, nothing ever unknown), and
  ``precision_open``: the share of known test views named right *and* kept, what the threshold costs;
- ``accepted_precision``: of the known answers kept, the share named right.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from heatdata.descriptors import kind_of
from heatdata.errors import HeatdataError
from heatdata.recognition.confidence import SIDES, calibrate, calibration_rows, default_side, nearest_two


def open_set_scores(
    library: pd.DataFrame,
    tests: pd.DataFrame,
    kind: str,
    threshold: float | None = None,
    folds: list[list[str]] | None = None,
    side: str | None = None,
) -> pd.DataFrame:
    """One row per fold (objects left out) and test view: its answer and confidence.

    Parameters
    ----------
    library : pandas.DataFrame
        The library views (``object``, ``values``), one descriptor's.
    tests : pandas.DataFrame
        Test views of the same descriptor (``object``, ``view_id``, ``values``).
    kind : str
        The descriptor kind, for its distance (not a time-scaled one).
    threshold : float in [0, 1], optional
        One threshold for every fold (default: each fold's library's own).
    folds : list of lists of str, optional
        The objects each fold leaves out (default: each object alone). A learned kind is measured on one fold, the
        objects its network was not trained on.
    side : {"unknown", "known"}, optional
        Which of each fold's library's own answers set its threshold
        (:func:`heatdata.recognition.confidence.calibrate`; default: the kind's, as its library files do).

    Returns
    -------
    pandas.DataFrame
        ``left_out, view_id, object, known, nearest, confidence, threshold``; ``left_out`` names a fold's objects,
        joined by ``", "``.

    Raises
    ------
    HeatdataError
        A time-scaled kind, or a library of fewer than three objects (two must remain when one is left out).
    """
    impl = kind_of(kind)
    if impl.time_scaled:
        raise HeatdataError(f"{kind}: a time-scaled kind's test views are compared per time scale; not measured here")
    objects = library["object"].to_numpy()
    names = sorted(set(objects))
    if len(names) < 3:
        raise HeatdataError(f"open-set evaluation leaves one object out and needs three, got {len(names)}")
    values = np.stack(library["values"].to_numpy())
    queries = np.stack(tests["values"].to_numpy())
    among = impl.distance_matrix(values, values)
    answers = impl.distance_matrix(queries, values)
    truth = tests["object"].to_numpy()
    rows = []
    for fold in folds if folds is not None else [[name] for name in names]:
        unknown = np.isin(truth, fold)
        kept = np.flatnonzero(~np.isin(objects, fold))
        if len(set(objects[kept])) < 2:
            raise HeatdataError(f"leaving out {len(fold)} objects leaves {len(set(objects[kept]))}; two must remain")
        chosen = kept[calibration_rows(len(kept))]
        confidence = calibrate(
            among[np.ix_(chosen, kept)],
            objects[kept],
            np.searchsorted(kept, chosen),
            threshold=threshold,
            side=side or default_side(impl.learned),
        )
        best, nearest, other = nearest_two(answers[:, kept], objects[kept])
        sure = confidence(nearest, other)
        rows.append(
            pd.DataFrame(
                {
                    "left_out": ", ".join(fold),
                    "view_id": tests["view_id"].to_numpy(),
                    "object": truth,
                    "known": ~unknown,
                    "nearest": objects[kept][best],
                    "confidence": sure,
                    "threshold": confidence.threshold,
                }
            )
        )
    return pd.concat(rows, ignore_index=True)


def open_set_summary(scores: pd.DataFrame) -> dict:
    """The pooled measures of :func:`open_set_scores` (the module's list).

    Parameters
    ----------
    scores : pandas.DataFrame
        Its rows.

    Returns
    -------
    dict
        ``objects, known, unknown, auroc, known_kept, unknown_rejected, precision, precision_open,
        accepted_precision``.
    """
    from sklearn.metrics import roc_auc_score

    known = scores[scores["known"]]
    unknown = scores[~scores["known"]]
    kept = known["confidence"] >= known["threshold"]
    right = known["nearest"] == known["object"]
    return {
        "objects": int(scores["left_out"].nunique()),
        "known": len(known),
        "unknown": len(unknown),
        "auroc": float(roc_auc_score(scores["known"], scores["confidence"])),
        "known_kept": float(kept.mean()),
        "unknown_rejected": float((unknown["confidence"] < unknown["threshold"]).mean()),
        "precision": float(right.mean()),
        "precision_open": float((right & kept).mean()),
        "accepted_precision": float(right[kept].mean()) if kept.any() else float("nan"),
    }


def threshold_sides(
    library: pd.DataFrame, tests: pd.DataFrame, kind: str, folds: list[list[str]] | None = None
) -> dict:
    """The open set under each way a library sets its threshold (:data:`heatdata.recognition.confidence.SIDES`).

    Parameters
    ----------
    library, tests : pandas.DataFrame
        As for :func:`open_set_scores`.
    kind : str
        The descriptor kind.
    folds : list of lists of str, optional
        As for :func:`open_set_scores`.

    Returns
    -------
    dict
        ``auroc`` (the same for both) and, for each side, ``known_kept_<side>`` and ``unknown_rejected_<side>``.
    """
    out: dict[str, float] = {}
    for side in SIDES:
        summary = open_set_summary(open_set_scores(library, tests, kind, folds=folds, side=side))
        out |= {
            "auroc": summary["auroc"],
            f"known_kept_{side}": summary["known_kept"],
            f"unknown_rejected_{side}": summary["unknown_rejected"],
        }
    return out
