"""The modified Hausdorff distance between descriptors (thesis 3.2, eq. 3.1, Alg. 3.1).

A descriptor z in R^M becomes the curve eta = {(i/M, z_i), i = 1..M}; two curves are
compared point to nearest point, so that a small shift of the boundary
parameterization costs little (Fig. 3.2):

    d(z, z') = min( sum_{x in eta} min_{y in eta'} ||x - y||,  sum_{y in eta'} min_{x in eta} ||x - y|| )

:func:`mhd_matrix` evaluates it between many queries and a whole library in chunks,
in float32 by default (the distances need no more; memory and time halve).

The weighted version of eq. 5.14 (Alg. 5.2) multiplies each point's distance to the
other curve by its part weight rho. heatdata rescales each descriptor's weights to mean
1 before summing, so unit weights give eq. 3.1 exactly and a view cannot come closer
to everything just by having small weights (eq. 5.14 as printed sums raw weights).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import DTypeLike
from scipy.spatial.distance import cdist

from heatdata.errors import HeatdataError

SHORTLIST = 64  # pairs nearest in L1 whose exact MHD :func:`nearest_pair_mhd` computes
WARM_START = 4  # items nearest in L1 that :func:`nearest_mhd` tries first
BOUND_WINDOW = 3  # samples either side of a point inside the lower bound's envelope (:func:`nearest_mhd`)
SEARCH_BLOCK = 4096  # library items whose envelopes :func:`nearest_mhd` holds at once


@dataclass(frozen=True)
class Nearest:
    """Each query's nearest library item (the first of equals): every nearest-neighbour search returns this.

    It unpacks as ``index, distance = nearest_mhd(queries, library)``.
    """

    index: np.ndarray
    """(Q,) int: the library row; -1 where a ``within`` bound left none."""
    distance: np.ndarray
    """(Q,) float: its distance."""

    def __iter__(self) -> Iterator[np.ndarray]:
        return iter((self.index, self.distance))


@dataclass(frozen=True)
class NearestPair:
    """The closest (query, library item) pair of a set of queries: eq. 6.1's ``min`` over a view's candidates."""

    query: int
    """Which query (candidate) matched."""
    index: int
    """Which library row."""
    distance: float
    """Their distance."""
    label: Any = None
    """The library row's label, when the search was given labels
    (:func:`~heatdata.recognition.nearest.classify_candidates`)."""


def _curve_x(m: int, dtype) -> np.ndarray:
    return (np.arange(1, m + 1) / m).astype(dtype)


def _check_finite(array: np.ndarray, what: str) -> None:
    bad = ~np.isfinite(array)
    if bad.any():
        rows = int(np.any(bad.reshape(len(array), -1), axis=1).sum()) if array.ndim > 1 else 1
        raise HeatdataError(
            f"{what}: {rows} descriptor(s) hold NaN or infinite values (e.g. a PVST whose "
            "threshold was not reached: see the repairs column); drop or recompute them"
        )


def _unit_mean(weights: np.ndarray, what: str) -> np.ndarray:
    weights = np.atleast_2d(np.asarray(weights, dtype=np.float64))
    _check_finite(weights, what)
    if np.any(weights < 0) or np.any(weights.sum(axis=1) <= 0):
        raise HeatdataError(f"{what}: part weights must be non-negative and not all zero")
    return weights / weights.mean(axis=1, keepdims=True)


def _weights(
    query_weights, library_weights, queries: np.ndarray, library: np.ndarray, dtype
) -> tuple[np.ndarray, np.ndarray]:
    """The part weights of queries and library rescaled to mean 1 (unit weights if neither is given)."""
    if (query_weights is None) != (library_weights is None):
        raise HeatdataError("give part weights for both the queries and the library, or for neither")
    if query_weights is None:
        return np.ones(queries.shape, dtype), np.ones(library.shape, dtype)
    wq = _unit_mean(query_weights, "query weights").astype(dtype)
    wl = _unit_mean(library_weights, "library weights").astype(dtype)
    if wq.shape != queries.shape or wl.shape != library.shape:
        raise HeatdataError(
            f"weights of shapes {wq.shape}, {wl.shape} do not match descriptors of shapes "
            f"{queries.shape}, {library.shape}"
        )
    return wq, wl


def mhd(z1: np.ndarray, z2: np.ndarray) -> float:
    """Modified Hausdorff distance of eq. 3.1 between two descriptors.

    Parameters
    ----------
    z1 : (M,) float
    z2 : (M',) float
        Descriptors; the lengths may differ (each is parameterized on (0, 1]).

    Returns
    -------
    float
        The distance, >= 0.
    """
    return weighted_mhd(z1, z2, np.ones(len(z1)), np.ones(len(z2)))


def weighted_mhd(z1: np.ndarray, z2: np.ndarray, w1: np.ndarray, w2: np.ndarray) -> float:
    """Part-weighted modified Hausdorff distance of eq. 5.14 (Alg. 5.2).

    ``min(sum_i w1_i min_j ||eta_i - eta'_j||, sum_j w2_j min_i ||eta_i - eta'_j||)`` with
    each weight vector rescaled to mean 1; unit weights give :func:`mhd`.

    Parameters
    ----------
    z1 : (M,) float
    z2 : (M',) float
    w1 : (M,) float
    w2 : (M',) float
        Non-negative part weights (:func:`heatdata.descriptors.part_weights`).

    Returns
    -------
    float
        The weighted distance (eq. 5.14), >= 0.
    """
    z1, z2 = np.asarray(z1, float), np.asarray(z2, float)
    if z1.ndim != 1 or z2.ndim != 1 or len(z1) == 0 or len(z2) == 0:
        raise HeatdataError("mhd takes two non-empty 1-D descriptors")
    if np.shape(w1) != z1.shape or np.shape(w2) != z2.shape:
        raise HeatdataError(
            f"weights of shapes {np.shape(w1)}, {np.shape(w2)} do not match descriptors of "
            f"shapes {z1.shape}, {z2.shape}"
        )
    for z in (z1, z2):
        _check_finite(z, "mhd")
    w1, w2 = _unit_mean(w1, "weighted_mhd")[0], _unit_mean(w2, "weighted_mhd")[0]
    dx = _curve_x(len(z1), float)[:, None] - _curve_x(len(z2), float)[None, :]
    d = np.sqrt(dx**2 + (z1[:, None] - z2[None, :]) ** 2)
    return float(min(d.min(axis=1) @ w1, d.min(axis=0) @ w2))


def mhd_matrix(
    queries: np.ndarray,
    library: np.ndarray,
    *,
    query_weights: np.ndarray | None = None,
    library_weights: np.ndarray | None = None,
    chunk_elements: int = 2**16,
    dtype: DTypeLike = np.float32,
) -> np.ndarray:
    """Eq. 3.1 (or, with weights, eq. 5.14) between every query and every library descriptor.

    Parameters
    ----------
    queries : (Q, M) float
    library : (N, M') float
    query_weights : (Q, M) float, optional
    library_weights : (N, M') float, optional
        Part weights; both or neither.
    chunk_elements : int
        Size of the work arrays (about 4 bytes each); small enough to stay in cache.

    Returns
    -------
    (Q, N) float64

    Notes
    -----
    With M = M' the point-to-curve minima are accumulated one index offset
    ``k = j - i`` at a time over contiguous slices, and the loop stops once
    ``(k/M)^2`` exceeds every current minimum (no farther point can be nearer); this
    is exact and several times faster than the full (Q, N, M, M) tensor, which is used
    only for descriptors of different lengths.
    """
    queries = np.atleast_2d(np.asarray(queries, dtype))
    library = np.atleast_2d(np.asarray(library, dtype))
    _check_finite(queries, "queries")
    _check_finite(library, "library")
    wq, wl = _weights(query_weights, library_weights, queries, library, dtype)
    m, m2 = queries.shape[1], library.shape[1]
    kernel = _mhd_offsets if m == m2 else _mhd_tensor
    out = np.empty((len(queries), len(library)))
    n_block = max(1, min(len(library), chunk_elements // (m * m2 if kernel is _mhd_tensor else m)))
    q_block = max(1, chunk_elements // ((m * m2 if kernel is _mhd_tensor else m) * n_block))
    for q0 in range(0, len(queries), q_block):
        for n0 in range(0, len(library), n_block):
            q, n = slice(q0, q0 + q_block), slice(n0, n0 + n_block)
            out[q, n] = kernel(queries[q, None, :], library[None, n, :], wq[q, None, :], wl[None, n, :])
    return out


def nearest_mhd(
    queries: np.ndarray,
    library: np.ndarray,
    *,
    query_weights: np.ndarray | None = None,
    library_weights: np.ndarray | None = None,
    within: np.ndarray | None = None,
) -> Nearest:
    """The nearest library descriptor of each query under eq. 3.1 (or, with weights, eq. 5.14): exact.

    The same answer as ``argmin`` over :func:`mhd_matrix` in float64 (the first of equally
    near items), without the matrix. A compiled loop keeps each query's best distance so
    far, starting from its :data:`WARM_START` items nearest in L1. For descriptors of one
    length, an item is skipped when a lower bound of both directed sums exceeds that best
    (LB_Keogh's envelope over :data:`BOUND_WINDOW` samples: a point farther in index lies at
    least ``window / M`` away in abscissa); otherwise the directed sums are summed point by
    point, each point's nearest point sought outwards from the nearest abscissa until the
    abscissa gap alone is larger, and abandoned once over the best. Memory: the inputs and
    the envelopes of :data:`SEARCH_BLOCK` library items.

    Parameters
    ----------
    queries : (Q, M) float
    library : (N, M') float
        N >= 1; the lengths may differ (no bound is used then).
    query_weights : (Q, M) float, optional
    library_weights : (N, M') float, optional
        Part weights (each rescaled to mean 1, as :func:`mhd_matrix`); both or neither.
    within : (Q,) float, optional
        Seek only items nearer than this to each query (e.g. the best of an earlier search:
        Alg. 5.2 searches object by object); default infinity.

    Returns
    -------
    Nearest
        ``index`` (Q,) int64, -1 for a query no item is nearer to than ``within``; ``distance`` (Q,)
        float64, ``within`` for those.
    """
    from heatdata.core._mhd_kernel import nearest

    queries = np.ascontiguousarray(np.atleast_2d(queries), np.float64)
    library = np.ascontiguousarray(np.atleast_2d(library), np.float64)
    _check_finite(queries, "queries")
    _check_finite(library, "library")
    if not library.size:
        raise HeatdataError("nearest_mhd needs a library of one descriptor or more")
    wq, wl = _weights(query_weights, library_weights, queries, library, np.float64)
    within = np.full(len(queries), np.inf) if within is None else np.asarray(within, np.float64).reshape(-1)
    if within.shape != (len(queries),):
        raise HeatdataError(f"within needs one distance per query ({len(queries)}), got {within.shape}")
    same = queries.shape[1] == library.shape[1]
    warm = min(WARM_START, len(library))
    first = np.zeros((len(queries), warm if same else 1), np.int64)  # tried first: the items nearest in L1
    if same:
        step = max(1, 2**22 // len(library))
        for q0 in range(0, len(queries), step):
            l1 = cdist(queries[q0 : q0 + step], library, "cityblock")
            first[q0 : q0 + step] = np.argpartition(l1, warm - 1, axis=1)[:, :warm]
    index, distance = np.empty(len(queries), np.int64), np.empty(len(queries))
    nearest(
        queries,
        library,
        np.ascontiguousarray(wq),
        np.ascontiguousarray(wl),
        _curve_x(queries.shape[1], float),
        _curve_x(library.shape[1], float),
        within,
        first,
        BOUND_WINDOW if same else 0,
        SEARCH_BLOCK,
        index,
        distance,
    )
    return Nearest(index, distance)


def _mhd_offsets(a: np.ndarray, b: np.ndarray, wa: np.ndarray, wb: np.ndarray) -> np.ndarray:
    """(q, 1, M) and (1, n, M) descriptors of equal length, and their weights -> (q, n) distances."""
    m = a.shape[-1]
    forward = a - b
    forward *= forward
    backward = forward.copy()
    for k in range(1, m):
        step = (k / m) ** 2
        if step >= max(forward.max(), backward.max()):
            break
        for ai, bi, fi, bk in (
            (slice(None, m - k), slice(k, None), slice(None, m - k), slice(k, None)),
            (slice(k, None), slice(None, m - k), slice(k, None), slice(None, m - k)),
        ):
            term = a[..., ai] - b[..., bi]
            term *= term
            term += step
            np.minimum(forward[..., fi], term, out=forward[..., fi])
            np.minimum(backward[..., bk], term, out=backward[..., bk])
    return np.minimum((np.sqrt(forward) * wa).sum(axis=-1), (np.sqrt(backward) * wb).sum(axis=-1))


def _mhd_tensor(a: np.ndarray, b: np.ndarray, wa: np.ndarray, wb: np.ndarray) -> np.ndarray:
    """(q, 1, M) and (1, n, M') descriptors and weights -> (q, n) distances via the full tensor."""
    dx2 = (_curve_x(a.shape[-1], a.dtype)[:, None] - _curve_x(b.shape[-1], a.dtype)[None, :]) ** 2
    d2 = (a[..., :, None] - b[..., None, :]) ** 2 + dx2  # (q, n, M, M')
    return np.minimum((np.sqrt(d2.min(axis=3)) * wa).sum(axis=2), (np.sqrt(d2.min(axis=2)) * wb).sum(axis=2))


def nearest_pair_mhd(
    queries: np.ndarray, library: np.ndarray, *, shortlist: int | None = SHORTLIST, dtype: DTypeLike = np.float32
) -> NearestPair:
    """The closest (query, library) pair under eq. 3.1, searched on the ``shortlist`` pairs nearest in L1.

    Eq. 6.1 and Alg. 6.1: a view described from many sources is as near to a library
    descriptor as its nearest candidate. Exact when the nearest pair under the MHD is
    among the shortlist (``shortlist=None``: all pairs).

    Parameters
    ----------
    queries : (Q, M) float
    library : (N, M) float

    Returns
    -------
    NearestPair
        ``query`` and ``index`` (int) of the closest pair, and their ``distance``.
    """
    queries = np.atleast_2d(np.asarray(queries, dtype))
    library = np.atleast_2d(np.asarray(library, dtype))
    _check_finite(queries, "queries")
    _check_finite(library, "library")
    if queries.shape[1] != library.shape[1]:
        raise HeatdataError(
            f"nearest_pair_mhd needs descriptors of one length, got {queries.shape[1]} and {library.shape[1]}"
        )
    l1 = cdist(queries, library, "cityblock").ravel()
    pairs = (
        np.arange(len(l1))
        if shortlist is None or shortlist >= len(l1)
        else np.argpartition(l1, shortlist - 1)[:shortlist]
    )
    q, n = np.unravel_index(pairs, (len(queries), len(library)))
    ones = np.ones((1, 1, queries.shape[1]), dtype)
    d = np.concatenate(
        [
            _mhd_offsets(queries[q[k : k + 4096], None, :], library[n[k : k + 4096], None, :], ones, ones)[:, 0]
            for k in range(0, len(pairs), 4096)
        ]
    )
    best = int(np.argmin(d))
    return NearestPair(int(q[best]), int(n[best]), float(d[best]))


def chi_square_matrix(queries: np.ndarray, library: np.ndarray, *, chunk_elements: int = 2**22) -> np.ndarray:
    """The chi-square distance ``sum_k (a_k - b_k)^2 / (a_k + b_k) / 2`` between histograms (0/0 counts 0).

    The customary distance of histogram descriptors (VFH, FPFH, ESF, bags of words); 0
    for equal histograms and 1 for normalized histograms with disjoint support.

    Parameters
    ----------
    queries : (Q, D) float
    library : (N, D) float
        Non-negative histograms.
    chunk_elements : int
        The most values a work array holds (queries x library rows x bins): memory stays bounded at any library size.

    Returns
    -------
    (Q, N) float64
    """
    queries = np.atleast_2d(np.asarray(queries, np.float64))
    library = np.atleast_2d(np.asarray(library, np.float64))
    _check_finite(queries, "queries")
    _check_finite(library, "library")
    if queries.shape[1] != library.shape[1]:
        raise HeatdataError(f"histograms of {queries.shape[1]} and {library.shape[1]} bins cannot be compared")
    if np.any(queries < 0) or np.any(library < 0):
        raise HeatdataError("chi-square distances need non-negative histograms")
    out = np.empty((len(queries), len(library)))
    width = max(1, queries.shape[1])
    block = max(1, chunk_elements // max(1, len(library) * width))  # queries at a time
    rows = max(1, chunk_elements // (block * width))  # library views at a time: the work arrays stay chunk-sized
    for q0 in range(0, len(queries), block):
        a = queries[q0 : q0 + block, None, :]
        for n0 in range(0, len(library), rows):
            part = library[None, n0 : n0 + rows, :]
            total = a + part
            with np.errstate(divide="ignore", invalid="ignore"):
                out[q0 : q0 + block, n0 : n0 + rows] = 0.5 * np.where(total > 0, (a - part) ** 2 / total, 0.0).sum(2)
    return out
