"""Compiled kernels of the exact nearest-descriptor search under eq. 3.1 / 5.14 (numba; cached on disk).

Imported by :func:`heatdata.core.distances.nearest_mhd` only, so ``import heatdata`` does not load numba.
"""

from math import sqrt

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def directed(a, xa, b, xb, w, limit):  # pragma: no cover - compiled
    """``sum_i w_i min_j ||(xa_i, a_i) - (xb_j, b_j)||``, abandoned once the partial sum exceeds ``limit``.

    ``xb`` is increasing: each point's search starts at the nearest abscissa and walks both
    ways until the abscissa gap alone exceeds the best distance (nothing farther is nearer).
    """
    n = b.shape[0]
    total = 0.0
    for i in range(a.shape[0]):
        x, z = xa[i], a[i]
        j0 = min(max(int(x * n + 0.5) - 1, 0), n - 1)  # the abscissa (j + 1) / n nearest x
        d = (x - xb[j0]) ** 2 + (z - b[j0]) ** 2
        for step in (-1, 1):
            j = j0 + step
            while 0 <= j < n:
                gap = (x - xb[j]) ** 2
                if gap >= d:
                    break
                e = gap + (z - b[j]) ** 2
                d = min(d, e)
                j += step
        total += w[i] * sqrt(d)
        if total > limit:
            return total
    return total


@njit(cache=True, nogil=True)
def envelope(z, window, low, high):  # pragma: no cover - compiled
    """``low[i], high[i]``: the least and greatest ``z[j]`` for ``|i - j| < window``."""
    m = z.shape[0]
    for i in range(m):
        low[i] = high[i] = z[i]
        for j in range(max(0, i - window + 1), min(m, i + window)):
            low[i] = min(low[i], z[j])
            high[i] = max(high[i], z[j])


@njit(cache=True, nogil=True)
def bound(a, w, low, high, cap, limit):  # pragma: no cover - compiled
    """A lower bound of :func:`directed` from ``a`` to a curve of the same length with envelope ``low, high``.

    A point j with ``|i - j| >= window`` lies ``window / M = cap`` away in abscissa; a nearer
    one no nearer than ``a_i``'s gap to the envelope. Abandoned once over ``limit``.
    """
    total = 0.0
    for i in range(a.shape[0]):
        gap = low[i] - a[i] if a[i] < low[i] else a[i] - high[i]
        if gap > 0.0:
            total += w[i] * min(gap, cap)
            if total > limit:
                return total
    return total


@njit(cache=True, nogil=True)
def nearest(queries, library, wq, wl, xq, xl, within, first, window, block, index, distance):  # pragma: no cover
    """For each query row, the library row of least ``min(forward, backward)`` (the first of equals) among those
    nearer than ``within`` (Q,); none: index -1, distance ``within``.

    ``first`` (Q, W): rows tried first, for a small best distance early. With ``window > 0``
    (equal lengths), a row is skipped when both directed bounds exceed the best distance;
    the library's envelopes are built ``block`` rows at a time (memory stays bounded).
    """
    n, m = library.shape
    cap = window / m
    best = within.copy()
    index[:] = -1
    for q in range(queries.shape[0]):
        for s in range(first.shape[1]):
            k = first[q, s]
            forward = directed(queries[q], xq, library[k], xl, wq[q], best[q])
            d = min(forward, directed(library[k], xl, queries[q], xq, wl[k], min(forward, best[q])))
            if d < best[q] or (d == best[q] and k < index[q]):
                best[q], index[q] = d, k
    query_low, query_high = np.empty(queries.shape[1]), np.empty(queries.shape[1])
    low, high = np.empty((min(block, n), m)), np.empty((min(block, n), m))
    for start in range(0, n, block):
        stop = min(n, start + block)
        if window > 0:
            for k in range(start, stop):
                envelope(library[k], window, low[k - start], high[k - start])
        for q in range(queries.shape[0]):
            if window > 0:
                envelope(queries[q], window, query_low, query_high)
            for k in range(start, stop):
                if (
                    window > 0
                    and bound(queries[q], wq[q], low[k - start], high[k - start], cap, best[q]) > best[q]
                    and bound(library[k], wl[k], query_low, query_high, cap, best[q]) > best[q]
                ):
                    continue
                forward = directed(queries[q], xq, library[k], xl, wq[q], best[q])
                d = min(forward, directed(library[k], xl, queries[q], xq, wl[k], min(forward, best[q])))
                if d < best[q] or (d == best[q] and k < index[q]):
                    best[q], index[q] = d, k
    distance[:] = best
