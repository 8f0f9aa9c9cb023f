"""Calibrated confidence: how likely an answer's object is in the library at all, and "unknown" below a threshold.

The thesis's recognition (Alg. 3.1) always names the nearest library object, so an object no library holds is
named too. A library learns, from its own views only, what its answers look like in both cases, as open-set
recognition does with leave-one-class-out:

- **known**: each library view against the library without that view (leave-one-view-out): the nearest view is
  then of its own object, seen from a neighbouring angle;
- **unknown**: each library view against the library without its object (leave-one-object-out): the nearest view
  is of another object, as it is for an object the library lacks.

An answer is described by two features of its distances: ``log d1``, the distance to the nearest library view,
and ``log(d1 / d2)``, against ``d2``, the nearest view of any other object (Lowe's ratio: a known object lies much
nearer its own views than any other object's; an unknown one lies about as far from two objects). A logistic
regression on the two, the classes weighed equally, maps them to the **confidence** in [0, 1] that the object is
known. Below the library's threshold the answer is ``unknown``: by default the confidence under which
:data:`REJECTED` of the library's own unknown answers fall. That threshold lies as near the unknown answers as it
can and still reject most of them, for a known object seen otherwise than the library's views were rendered (from
another elevation or distance, through another sensor) lies farther from them than they lie from each other. No
test view is used.

A learned kind's library takes its threshold from the other side: the confidence above which :data:`KEPT` of its
own known answers lie. Its network was trained to set exactly the library's objects apart, so their
leave-one-object-out answers lie farther than an object it never saw, and a threshold learned from them is too
lenient (measured on the learned kind's page, ``docs/guide/learned.md``).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from heatdata.errors import HeatdataError

#: distances below this count as this (the log of an exact match)
TINY = 1e-12
#: the library views calibration describes as queries, at most (a seeded sample of a larger library)
CALIBRATION_VIEWS = 2000
#: the share of a library's own unknown answers (leave-one-object-out) its default threshold rejects
REJECTED = 0.95
#: the share of a learned kind's library's own known answers (leave-one-view-out) its default threshold keeps
KEPT = 0.95
#: which of a library's own answers set its default threshold: ``unknown`` (:data:`REJECTED` of them rejected) or
#: ``known`` (:data:`KEPT` of them kept)
SIDES = ("unknown", "known")


@dataclass(frozen=True)
class Confidence:
    """A library's calibrated confidence (:func:`calibrate`).

    Attributes
    ----------
    coef : (2,) float
        The logistic regression's weights of ``log d1`` and ``log(d1 / d2)``.
    intercept : float
        Its intercept.
    threshold : float
        Answers less confident than this are ``unknown``.
    known, unknown : int
        The calibration's answers of each case.
    auroc : float
        How well the confidence separates them on the calibration itself (1: perfectly, 0.5: not at all).
    """

    coef: tuple[float, float]
    intercept: float
    threshold: float
    known: int
    unknown: int
    auroc: float

    def __call__(self, nearest: np.ndarray | float, other: np.ndarray | float) -> np.ndarray:
        """The confidence of answers whose nearest library view lies at ``nearest`` and the nearest of another
        object at ``other`` (inf when the library holds one object).

        Parameters
        ----------
        nearest, other : (k,) float or float

        Returns
        -------
        (k,) float in [0, 1]
        """
        features = answer_features(np.atleast_1d(nearest), np.atleast_1d(other))
        score = features @ np.asarray(self.coef) + self.intercept
        return 1.0 / (1.0 + np.exp(-score))

    def to_dict(self) -> dict:
        """As plain types, for a library file's metadata.

        Returns
        -------
        dict
            ``coef, intercept, threshold, known, unknown, auroc``.
        """
        return {key: (list(value) if isinstance(value, tuple) else value) for key, value in asdict(self).items()}

    @classmethod
    def from_dict(cls, data: dict) -> Confidence:
        """From :meth:`to_dict`.

        Parameters
        ----------
        data : dict
            What :meth:`to_dict` gave.

        Returns
        -------
        Confidence

        Raises
        ------
        HeatdataError
            A threshold outside [0, 1].
        """
        return cls(
            coef=(float(data["coef"][0]), float(data["coef"][1])),
            intercept=float(data["intercept"]),
            threshold=checked_threshold(data["threshold"]),
            known=int(data["known"]),
            unknown=int(data["unknown"]),
            auroc=float(data["auroc"]),
        )


def checked_threshold(value) -> float:
    """``value`` as a threshold in [0, 1]; a :class:`HeatdataError` for anything else (NaN included)."""
    try:
        threshold = float(value)
    except (TypeError, ValueError):
        threshold = float("nan")
    if not 0.0 <= threshold <= 1.0:  # NaN fails too
        raise HeatdataError(f"the confidence threshold is a number in [0, 1], got {value!r}")
    return threshold


def answer_features(nearest: np.ndarray, other: np.ndarray) -> np.ndarray:
    """(k, 2): ``log d1`` and ``log(d1 / d2)`` of answers (``d2`` inf: the ratio's log taken as ``log TINY``)."""
    d1 = np.log(np.maximum(np.asarray(nearest, dtype=np.float64), TINY))
    d2 = np.log(np.maximum(np.asarray(other, dtype=np.float64), TINY))
    ratio = np.where(np.isfinite(d2), d1 - d2, np.log(TINY))
    return np.stack([d1, ratio], axis=1)


def nearest_two(distance: np.ndarray, objects: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per query: the nearest library view, its distance and the distance to the nearest view of another object.

    Parameters
    ----------
    distance : (q, N) float
        Queries against library views (inf where a view is left out).
    objects : (N,) str
        The library views' objects.

    Returns
    -------
    best : (q,) int
        The nearest view.
    nearest, other : (q,) float
        Its distance; the nearest view of any other object's (inf when there is none).
    """
    best = np.argmin(distance, axis=1)
    nearest = distance[np.arange(len(distance)), best]
    other = np.where(objects[None, :] == objects[best][:, None], np.inf, distance).min(axis=1)
    return best, nearest, other


def calibrate(
    distance: np.ndarray,
    objects: np.ndarray,
    rows: np.ndarray,
    threshold: float | None = None,
    side: str = "unknown",
) -> Confidence:
    """Learn a library's confidence from its own views (the module's leave-one-view-out and leave-one-object-out).

    Parameters
    ----------
    distance : (q, N) float
        Some library views (``rows`` of them) against every library view, by the kind's distance.
    objects : (N,) str
        The library views' objects.
    rows : (q,) int
        Which library view each query is.
    threshold : float in [0, 1], optional
        The threshold stored with it (default: set by ``side``).
    side : {"unknown", "known"}
        Which answers set the default threshold: the confidence under which :data:`REJECTED` of the unknown
        answers fall, or the one above which :data:`KEPT` of the known answers lie (a learned kind's).

    Returns
    -------
    Confidence

    Raises
    ------
    HeatdataError
        A library of one object (nothing to leave it out against), distances that are not finite, or another side.
    """
    from sklearn.linear_model import LogisticRegression
    from sklearn.metrics import roc_auc_score

    if side not in SIDES:
        raise HeatdataError(f"the threshold's side is one of {', '.join(SIDES)}, got {side!r}")
    objects = np.asarray(objects)
    if len(np.unique(objects)) < 2:
        raise HeatdataError("a library of one object cannot learn what an unknown object looks like")
    own = distance.astype(np.float64, copy=True)
    own[np.arange(len(rows)), rows] = np.inf  # leave the view out
    _, known_d1, known_d2 = nearest_two(own, objects)
    lacking = np.where(objects[None, :] == objects[rows][:, None], np.inf, own)  # leave its object out
    _, unknown_d1, unknown_d2 = nearest_two(lacking, objects)
    features = answer_features(np.r_[known_d1, unknown_d1], np.r_[known_d2, unknown_d2])
    truth = np.r_[np.ones(len(rows)), np.zeros(len(rows))]
    usable = np.all(np.isfinite(features), axis=1)
    if not usable.all():
        raise HeatdataError(f"{int((~usable).sum())} calibration answers have distances that are not finite")
    model = LogisticRegression(class_weight="balanced").fit(features, truth)
    scores = model.decision_function(features)
    if threshold is None:
        confidence = 1.0 / (1.0 + np.exp(-scores))
        if side == "unknown":
            threshold = float(np.quantile(confidence[truth == 0], REJECTED))
        else:
            threshold = float(np.quantile(confidence[truth == 1], 1.0 - KEPT))
    return Confidence(
        coef=(float(model.coef_[0, 0]), float(model.coef_[0, 1])),
        intercept=float(model.intercept_[0]),
        threshold=checked_threshold(threshold),
        known=len(rows),
        unknown=len(rows),
        auroc=float(roc_auc_score(truth, scores)),
    )


def default_side(learned: bool) -> str:
    """Which of a library's own answers set its default threshold: ``known`` for a learned kind (the module
    docstring), ``unknown`` for every other."""
    return "known" if learned else "unknown"


def calibration_rows(n_views: int, seed: int = 0) -> np.ndarray:
    """(q,) int: the library views calibration describes: all, or a seeded :data:`CALIBRATION_VIEWS` of them."""
    if n_views <= CALIBRATION_VIEWS:
        return np.arange(n_views)
    return np.sort(np.random.default_rng(seed).choice(n_views, CALIBRATION_VIEWS, replace=False))
