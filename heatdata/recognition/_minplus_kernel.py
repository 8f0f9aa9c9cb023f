"""Compiled min-plus product for the bounds of :mod:`heatdata.recognition.compact` (numba; cached on disk)."""

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def minplus(a, b):  # pragma: no cover - compiled
    """``out[i, j] = min_p a[i, p] + b[p, j]`` for C-contiguous float64 ``a`` (m, k) and ``b`` (k, n).

    Rows of ``a`` that are infinite contribute nothing; the inner loop runs along a row of ``b`` (vectorized).
    """
    m, k = a.shape
    n = b.shape[1]
    out = np.full((m, n), np.inf)
    for i in range(m):
        row = out[i]
        for p in range(k):
            v = a[i, p]
            if v == np.inf:
                continue
            bp = b[p]
            for j in range(n):
                t = v + bp[j]
                row[j] = min(row[j], t)
    return out
