"""Nearest-neighbour recognition of descriptors (thesis 3.1, 3.3.2) and of candidate sets (Alg. 6.1)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from heatdata.core.distances import SHORTLIST, Nearest, NearestPair, nearest_mhd, nearest_pair_mhd
from heatdata.descriptors import stack_values
from heatdata.errors import HeatdataError


def nearest_neighbors(
    queries: np.ndarray, library: np.ndarray, *, distance: Callable[..., np.ndarray] | None = None, **kwargs: Any
) -> Nearest:
    """Nearest library descriptor of each query (the first of equals), under eq. 3.1 or a kind's own distance.

    Parameters
    ----------
    queries : (Q, M) float, or a list of Descriptor
    library : (N, M') float, or a list of Descriptor
    distance : callable, optional
        ``distance(queries, library, **kwargs)`` -> (Q, N), e.g. a kind's
        :meth:`heatdata.descriptors.Kind.distance_matrix`. Default: eq. 3.1 (eq. 5.14 with
        ``query_weights`` and ``library_weights``) by the exact search of
        :func:`heatdata.core.distances.nearest_mhd`, which needs no distance matrix.

    Returns
    -------
    Nearest
        ``index`` (Q,) int and ``distance`` (Q,) float.
    """
    queries, library = stack_values(queries, "queries"), stack_values(library, "library")
    if distance is None:
        return nearest_mhd(queries, library, **kwargs)
    d = distance(queries, library, **kwargs)
    index = np.argmin(d, axis=1)
    return Nearest(index, d[np.arange(len(index)), index])


def classify_candidates(
    candidates: np.ndarray, library: np.ndarray, labels: np.ndarray, *, shortlist: int | None = SHORTLIST
) -> NearestPair:
    """Alg. 6.1: the label of the library descriptor nearest to any of a view's candidate descriptors.

    ``D(Z, z) = min_{z' in Z} d(z, z')`` (eq. 6.1), then the nearest library descriptor.

    Parameters
    ----------
    candidates : (s, M) float, or a list of Descriptor
        The observed view's descriptors, one per candidate source
        (:func:`heatdata.descriptors.sources.candidate_descriptors`).
    library : (N, M) float, or a list of Descriptor
    labels : (N,)
        Object (or class) of each library descriptor.
    shortlist : int or None
        As in :func:`heatdata.core.distances.nearest_pair_mhd`.

    Returns
    -------
    NearestPair
        Which candidate (``query``) and which library descriptor (``index``) matched, their
        ``distance``, and the predicted ``label``.
    """
    candidates, library = stack_values(candidates, "candidates"), stack_values(library, "library")
    labels = np.asarray(labels)
    if len(labels) != len(library):
        raise HeatdataError(f"{len(labels)} labels for {len(library)} library descriptors")
    pair = nearest_pair_mhd(candidates, library, shortlist=shortlist)
    return replace(pair, label=labels[pair.index])
