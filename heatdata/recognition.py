"""Nearest-neighbour recognition and confusion matrices (thesis 3.1, 3.3.2, Fig. 3.5)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from .descriptors import stack_values
from .distance import SHORTLIST, nearest_mhd, nearest_pair_mhd
from .errors import HeatdataError


@dataclass
class NearestNeighbours:
    """For each query: the index of its nearest library descriptor and the distance."""

    index: np.ndarray
    distance: np.ndarray


def nearest_neighbours(queries: np.ndarray, library: np.ndarray, *, distance=None, **kwargs
                       ) -> NearestNeighbours:
    """Nearest library descriptor of each query (the first of equals), under eq. 3.1 or a kind's own distance.

    Parameters
    ----------
    queries : (Q, M) float, or a list of Descriptor
    library : (N, M') float, or a list of Descriptor
    distance : callable, optional
        ``distance(queries, library, **kwargs)`` -> (Q, N), e.g. a kind's
        :meth:`heatdata.descriptors.Kind.distance_matrix`. Default: eq. 3.1 (eq. 5.14 with
        ``query_weights`` and ``library_weights``) by the exact search of
        :func:`heatdata.distance.nearest_mhd`, which needs no distance matrix.

    Returns
    -------
    NearestNeighbours
        ``index`` (Q,) int and ``distance`` (Q,) float.
    """
    queries, library = stack_values(queries, "queries"), stack_values(library, "library")
    if distance is None:
        index, nearest = nearest_mhd(queries, library, **kwargs)
        return NearestNeighbours(index=index, distance=nearest)
    d = distance(queries, library, **kwargs)
    index = np.argmin(d, axis=1)
    return NearestNeighbours(index=index, distance=d[np.arange(len(index)), index])


def classify_candidates(candidates: np.ndarray, library: np.ndarray, labels: np.ndarray, *,
                        shortlist: int | None = SHORTLIST) -> tuple[object, int, int, float]:
    """Alg. 6.1: the label of the library descriptor nearest to any of a view's candidate descriptors.

    ``D(Z, z) = min_{z' in Z} d(z, z')`` (eq. 6.1), then the nearest library descriptor.

    Parameters
    ----------
    candidates : (s, M) float, or a list of Descriptor
        The observed view's descriptors, one per candidate source
        (:func:`heatdata.candidate_descriptors`).
    library : (N, M) float, or a list of Descriptor
    labels : (N,)
        Object (or class) of each library descriptor.
    shortlist : int or None
        As in :func:`heatdata.distance.nearest_pair_mhd`.

    Returns
    -------
    label, candidate, item, distance
        The predicted label, which candidate and which library descriptor matched, and their distance.
    """
    candidates, library = stack_values(candidates, "candidates"), stack_values(library, "library")
    labels = np.asarray(labels)
    if len(labels) != len(library):
        raise HeatdataError(f"{len(labels)} labels for {len(library)} library descriptors")
    candidate, item, distance = nearest_pair_mhd(candidates, library, shortlist=shortlist)
    return labels[item], candidate, item, distance


def confusion_matrix(true: pd.Series, predicted: pd.Series, labels: list | None = None) -> pd.DataFrame:
    """Counts of (true, predicted) pairs: rows are true objects, columns predicted."""
    labels = sorted(set(true) | set(predicted)) if labels is None else labels
    table = pd.crosstab(pd.Categorical(true, labels), pd.Categorical(predicted, labels), dropna=False)
    table.index.name, table.columns.name = "true", "predicted"
    return table


def precision_by(true: pd.Series, predicted: pd.Series) -> pd.Series:
    """Precision: the fraction of correct predictions per true label, plus ``"all"``."""
    correct = pd.Series(np.asarray(true) == np.asarray(predicted), index=np.asarray(true))
    per = correct.groupby(level=0).mean()
    per["all"] = correct.mean()
    return per
