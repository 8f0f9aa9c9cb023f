"""The modified Hausdorff distance between descriptors (thesis 3.2, eq. 3.1, Alg. 3.1).

A descriptor z in R^M becomes the curve eta = {(i/M, z_i), i = 1..M}; two curves are
compared point to nearest point, so that a small shift of the boundary
parameterization costs little (Fig. 3.2):

    d(z, z') = min( sum_{x in eta} min_{y in eta'} ||x - y||,  sum_{y in eta'} min_{x in eta} ||x - y|| )

:func:`mhd_matrix` evaluates it between many queries and a whole library in chunks,
in float32 by default (the distances need no more; memory and time halve).
"""

from __future__ import annotations

import numpy as np

from .errors import HeatdataError


def _curve_x(m: int, dtype) -> np.ndarray:
    return (np.arange(1, m + 1) / m).astype(dtype)


def mhd(z1: np.ndarray, z2: np.ndarray) -> float:
    """Modified Hausdorff distance of eq. 3.1 between two descriptors.

    Parameters
    ----------
    z1 : (M,) float
    z2 : (M',) float
        Descriptors; the lengths may differ (each is parameterized on (0, 1]).
    """
    z1, z2 = np.asarray(z1, float), np.asarray(z2, float)
    if z1.ndim != 1 or z2.ndim != 1 or len(z1) == 0 or len(z2) == 0:
        raise HeatdataError("mhd takes two non-empty 1-D descriptors")
    dx = _curve_x(len(z1), float)[:, None] - _curve_x(len(z2), float)[None, :]
    d = np.sqrt(dx ** 2 + (z1[:, None] - z2[None, :]) ** 2)
    return float(min(d.min(axis=1).sum(), d.min(axis=0).sum()))


def mhd_matrix(queries: np.ndarray, library: np.ndarray, *, chunk_elements: int = 2 ** 16,
               dtype=np.float32) -> np.ndarray:
    """Eq. 3.1 between every query and every library descriptor.

    Parameters
    ----------
    queries : (Q, M) float
    library : (N, M') float
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
    m, m2 = queries.shape[1], library.shape[1]
    kernel = _mhd_offsets if m == m2 else _mhd_tensor
    out = np.empty((len(queries), len(library)))
    n_block = max(1, min(len(library), chunk_elements // (m * m2 if kernel is _mhd_tensor else m)))
    q_block = max(1, chunk_elements // ((m * m2 if kernel is _mhd_tensor else m) * n_block))
    for q0 in range(0, len(queries), q_block):
        for n0 in range(0, len(library), n_block):
            out[q0:q0 + q_block, n0:n0 + n_block] = kernel(queries[q0:q0 + q_block, None, :],
                                                           library[None, n0:n0 + n_block, :])
    return out


def _mhd_offsets(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(q, 1, M) and (1, n, M) descriptors of equal length -> (q, n) distances."""
    m = a.shape[-1]
    forward = a - b
    forward *= forward
    backward = forward.copy()
    for k in range(1, m):
        step = (k / m) ** 2
        if step >= max(forward.max(), backward.max()):
            break
        for ai, bi, fi, bk in ((slice(None, m - k), slice(k, None), slice(None, m - k), slice(k, None)),
                               (slice(k, None), slice(None, m - k), slice(k, None), slice(None, m - k))):
            term = a[..., ai] - b[..., bi]
            term *= term
            term += step
            np.minimum(forward[..., fi], term, out=forward[..., fi])
            np.minimum(backward[..., bk], term, out=backward[..., bk])
    return np.minimum(np.sqrt(forward).sum(axis=-1), np.sqrt(backward).sum(axis=-1))


def _mhd_tensor(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(q, 1, M) and (1, n, M') descriptors -> (q, n) distances via the full tensor."""
    dx2 = (_curve_x(a.shape[-1], a.dtype)[:, None] - _curve_x(b.shape[-1], a.dtype)[None, :]) ** 2
    d2 = (a[..., :, None] - b[..., None, :]) ** 2 + dx2  # (q, n, M, M')
    return np.minimum(np.sqrt(d2.min(axis=3)).sum(axis=2), np.sqrt(d2.min(axis=2)).sum(axis=2))
