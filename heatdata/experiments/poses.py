"""How right the poses are, and what verification adds to the confidence, on a run's rendered test views.

- :func:`pose_scores`: each test view answered by the library (every answer posed and verified, whatever its
  confidence), its pose scored against the renderer's (:func:`heatdata.recognition.pose.pose_errors`: ADD-S, the
  error of the object's centre, the rotation error up to the object's symmetries), and the time the pose adds;
- :func:`verified_open_set`: each object left out of the library in turn (:meth:`Library.without`), its test views
  answered as unknown objects, the others' by the whole library as known ones; an answer is kept when its
  confidence reaches the library's threshold (the confidence alone), when that and a candidate's pose explaining the
  view both hold (with verification), and when a candidate's pose explains it (verification alone: the default of a
  library with surface samples, :meth:`heatdata.recognition.library.Library.threshold`);
- :func:`pose_summary` and :func:`verified_open_set_summary` pool them.

The views are renderings through a sensor profile, not sensor data.
"""

from __future__ import annotations

import logging
import time
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from heatdata.errors import HeatdataError

if TYPE_CHECKING:
    from heatdata.recognition.library import Library
    from heatdata.views.view import View

log = logging.getLogger(__name__)


def evenly(views: list[View], per_object: int) -> list[View]:
    """``per_object`` of each object's views, evenly spaced in their order (all when it has fewer)."""
    by_object: dict[str, list[View]] = {}
    for view in views:
        by_object.setdefault(view.object_id, []).append(view)
    chosen = []
    for own in by_object.values():
        picks = np.unique(np.linspace(0, len(own) - 1, min(per_object, len(own))).round().astype(int))
        chosen += [own[i] for i in picks]
    return chosen


def pose_scores(library: Library, views: list[View]) -> pd.DataFrame:
    """Each view answered and posed by ``library`` (at threshold 0: every answer posed), its pose scored.

    Parameters
    ----------
    library : Library
        With surface samples.
    views : list of View
        Rendered views of the library's objects (their ``pose`` the renderer's camera-to-model transform).

    Returns
    -------
    pandas.DataFrame
        ``view_id, object, nearest, posed, verified, fitness, explained, in_front, add_s, add_s_ok, translation,
        rotation, symmetric, diameter, seconds`` (the time the pose and verification added), the errors NaN where
        the pose is of another object.
    """
    from heatdata.recognition.pose import pose_errors, symmetry_turns

    if not library.surfaces:
        raise HeatdataError(library.no_surfaces())
    turns = {obj: symmetry_turns(surface) for obj, surface in library.surfaces.items()}
    rows = []
    for number, view in enumerate(views):
        tic = time.perf_counter()
        library.recognize(view, threshold=0.0, pose=False)
        plain = time.perf_counter() - tic
        tic = time.perf_counter()
        answer = library.recognize(view, threshold=0.0)
        seconds = time.perf_counter() - tic - plain
        pose = answer.pose
        row = {
            "view_id": view.view_id,
            "object": view.object_id,
            "nearest": answer.best.object,
            "posed": "" if pose is None else pose.object,
            "verified": answer.verified,
            "fitness": np.nan if pose is None else pose.fitness,
            "explained": np.nan if pose is None else pose.explained,
            "in_front": np.nan if pose is None else pose.in_front,
            "add_s": np.nan,
            "add_s_ok": False,
            "translation": np.nan,
            "rotation": np.nan,
            "symmetric": len(turns.get(view.object_id, [0.0])) > 1,
            "diameter": np.nan,
            "seconds": seconds,
        }
        if pose is not None and pose.object == view.object_id:
            surface = library.surfaces[pose.object]
            errors = pose_errors(pose.matrix, np.linalg.inv(view.pose), surface, turns[pose.object])
            row.update(errors, diameter=surface.diameter)
        rows.append(row)
        if (number + 1) % 50 == 0:
            log.info("%d of %d views posed", number + 1, len(views))
    return pd.DataFrame(rows)


def pose_summary(scores: pd.DataFrame) -> dict:
    """The pooled pose measures of :func:`pose_scores`.

    Returns
    -------
    dict
        ``views``, ``posed`` (posed as their own object), ``add_s`` (the share of those within 10% of the
        diameter), ``translation`` (median, metres), ``rotation`` (median, degrees, objects that are not
        symmetric), ``rotation_views`` (how many), ``verified`` (the share of those posed right that verification
        accepts), ``median_ms`` and ``p90_ms`` (what the pose and verification add per view).
    """
    posed = scores[scores["add_s"].notna()]
    turned = posed[~posed["symmetric"]]
    return {
        "views": len(scores),
        "posed": len(posed),
        "add_s": float(posed["add_s_ok"].mean()) if len(posed) else np.nan,
        "translation": float(posed["translation"].median()) if len(posed) else np.nan,
        "rotation": float(turned["rotation"].median()) if len(turned) else np.nan,
        "rotation_views": len(turned),
        "verified": float(posed["verified"].mean()) if len(posed) else np.nan,
        "median_ms": float(1000 * scores["seconds"].median()),
        "p90_ms": float(1000 * scores["seconds"].quantile(0.9)),
    }


def verified_open_set(library: Library, views: list[View], threshold: float | None = None) -> pd.DataFrame:
    """Known and unknown objects answered with and without verification (see the module docstring).

    Parameters
    ----------
    library : Library
        With surface samples, of at least three objects.
    views : list of View
        Test views of its objects.
    threshold : float in [0, 1], optional
        One threshold for every fold (default: each library's own).

    Returns
    -------
    pandas.DataFrame
        ``left_out`` ("" for a known answer), ``view_id, object, known, nearest, answer`` (the verified answer's
        object, "" when none is verified), ``confidence, threshold, verified``.
    """
    if len(library.objects) < 3:
        raise HeatdataError(f"open-set evaluation leaves one object out and needs three, got {len(library.objects)}")
    folds = [("", library, [v for v in views if v.object_id in library.objects])]
    for obj in library.objects:
        folds.append((obj, library.without([obj]), [v for v in views if v.object_id == obj]))
    rows = []
    for left_out, fold, own in folds:
        for view in own:
            answer = fold.recognize(view, threshold=0.0)
            rows.append(
                {
                    "left_out": left_out,
                    "view_id": view.view_id,
                    "object": view.object_id,
                    "known": not left_out,
                    "nearest": answer.best.object,
                    "answer": answer.answer.object if answer.verified else "",
                    "confidence": answer.confidence,
                    "threshold": fold.threshold(threshold),
                    "verified": answer.verified,
                }
            )
        log.info("%s: %d views answered", left_out or "every object known", len(own))
    return pd.DataFrame(rows)


def verified_open_set_summary(scores: pd.DataFrame) -> dict:
    """The pooled measures of :func:`verified_open_set`.

    Returns
    -------
    dict
        ``known, unknown``; ``known_kept`` and ``unknown_rejected`` by the confidence alone, with ``_verified``
        with verification as well, with ``_pose_check`` by verification alone; ``precision`` (the nearest object,
        closed set), ``accepted_precision``, ``accepted_precision_verified`` and ``accepted_precision_pose_check``
        (of the known answers kept, the share named right).
    """
    known = scores[scores["known"]]
    unknown = scores[~scores["known"]]
    sure = known["confidence"] >= known["threshold"]
    kept = sure & known["verified"]
    right = known["nearest"] == known["object"]
    rejected = unknown["confidence"] < unknown["threshold"]
    return {
        "known": len(known),
        "unknown": len(unknown),
        "known_kept": float(sure.mean()),
        "unknown_rejected": float(rejected.mean()),
        "known_kept_verified": float(kept.mean()),
        "unknown_rejected_verified": float((rejected | ~unknown["verified"]).mean()),
        "precision": float(right.mean()),
        "accepted_precision": float(right[sure].mean()) if sure.any() else np.nan,
        "accepted_precision_verified": float((known["answer"] == known["object"])[kept].mean())
        if kept.any()
        else np.nan,
        "known_kept_pose_check": float(known["verified"].mean()),
        "unknown_rejected_pose_check": float((~unknown["verified"]).mean()),
        "accepted_precision_pose_check": float((known["answer"] == known["object"])[known["verified"]].mean())
        if known["verified"].any()
        else np.nan,
    }
