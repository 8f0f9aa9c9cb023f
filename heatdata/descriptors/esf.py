"""Ensemble of Shape Functions (ESF; Wohlkinger & Vincze 2011, thesis 3.6.1).

A re-implementation of PCL 1.13's ``pcl::ESFEstimation`` (``features/impl/esf.hpp``),
because no maintained Python binding of it exists and Debian's ``pcl-tools`` has no ESF
tool: the triplets and their geometry in numpy, the voxel grid and the line tracing in
numba (:mod:`heatdata.descriptors._esf_kernel`). As in PCL:

1. the view's points are centred on their centroid and scaled so that the farthest
   lies at 32 voxels; a 64^3 voxel grid marks each point's voxel and its 26 neighbours;
2. 20,000 random point triplets (distinct, with Heron's ``s(s-a)(s-b)(s-c) > 0.001``
   in voxel units) give three distances (D2), the triangle's square-root area (D3)
   and its three angles (A3);
3. each of the three lines of a triplet is traced voxel by voxel (3D Bresenham:
   the voxels from the start, one per step of the longest axis, the end excluded) and
   classed *in* (all but at most one voxel occupied), *out* (at most 7 occupied) or
   *mixed*, whose in-ratio goes into a tenth histogram; a triangle is *out* when its
   lines cross at most 21 occupied voxels, *in* when fewer than 4 of their voxels are
   empty, else *mixed*; an angle counts with the voxel length of the opposite line / 32;
4. 10 histograms x 64 bins (A3, D3, D2 each in/out/mixed, then the mixed ratio),
   weighted 0.5 (the first eight) and 1 (the last two), normalized to sum 1.

Unlike PCL (``srand(time(NULL))``) the triplets come from a seeded generator, so a view
always gets the same ESF. Compared by the chi-square distance.
"""

from __future__ import annotations

import numpy as np

from heatdata.descriptors.base import DescriptorSpec, Option, integer, register
from heatdata.descriptors.histograms import HistogramKind
from heatdata.errors import ViewError

GRID = 64
HALF = GRID // 2
BINS = 64
WEIGHTS = np.array([0.5] * 8 + [1.0, 1.0])
MAX_DRAWS = 20  # batches of random triplets before a view is called too degenerate


def _voxels(points: np.ndarray) -> np.ndarray:
    """PCL's voxel of scaled points: floor + 32 below zero, ceil + 31 from zero up."""
    return np.where(points < 0, np.floor(points) + HALF, np.ceil(points) + HALF - 1).astype(np.int64)


def _occupancy(points: np.ndarray) -> np.ndarray:
    """(64, 64, 64) bool: each point's voxel and its 26 neighbours (PCL's voxelize9)."""
    from heatdata.descriptors._esf_kernel import occupancy

    grid = np.zeros((GRID, GRID, GRID), dtype=bool)
    occupancy(np.ascontiguousarray(_voxels(points)), grid)
    return grid


def _trace(grid: np.ndarray, start: np.ndarray, end: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(lines,) voxels visited and occupied voxels among them, for lines between voxel ``start`` and ``end``
    (:func:`heatdata.descriptors._esf_kernel.trace`)."""
    from heatdata.descriptors._esf_kernel import trace

    count, occupied = np.empty(len(start), np.int64), np.empty(len(start), np.int64)
    trace(grid, np.ascontiguousarray(start), np.ascontiguousarray(end), count, occupied)
    return count, occupied


def _bin(values: np.ndarray, top: float) -> np.ndarray:
    return np.zeros(len(values), np.int64) if top == 0 else np.rint(values / top * (BINS - 1)).astype(np.int64)


def esf_histogram(points: np.ndarray, *, triplets: int = 20000, seed: int = 0, name: str = "view") -> np.ndarray:
    """The 640-bin ESF of a point set (see the module docstring).

    Parameters
    ----------
    points : (n, 3) float
    triplets : int
        Random point triplets (PCL: 20,000).
    seed : int

    Returns
    -------
    (640,) float64
        Sums to 1.
    """
    x = np.asarray(points, np.float64)
    centred = x - x.mean(axis=0)
    radius = float(np.linalg.norm(centred, axis=1).max())
    if not radius > 0:
        raise ViewError(f"{name}: all points coincide; no ESF")
    p = centred * (HALF / radius)
    grid = _occupancy(p)
    rng = np.random.default_rng(seed)
    chosen = []
    found = 0
    for _ in range(MAX_DRAWS):
        idx = rng.integers(0, len(p), size=(2 * triplets, 3))
        idx = idx[(idx[:, 0] != idx[:, 1]) & (idx[:, 0] != idx[:, 2]) & (idx[:, 1] != idx[:, 2])]
        a = np.linalg.norm(p[idx[:, 1]] - p[idx[:, 0]], axis=1)
        b = np.linalg.norm(p[idx[:, 2]] - p[idx[:, 0]], axis=1)
        c = np.linalg.norm(p[idx[:, 1]] - p[idx[:, 2]], axis=1)
        s = (a + b + c) / 2
        idx = idx[s * (s - a) * (s - b) * (s - c) > 0.001]
        chosen.append(idx)
        found += len(idx)
        if found >= triplets:
            break
    idx = np.concatenate(chosen)[:triplets]
    if len(idx) < triplets:
        raise ViewError(
            f"{name}: only {len(idx)} of {triplets} random point triplets span a triangle; "
            "the view is too small or flat for an ESF"
        )
    p1, p2, p3 = p[idx[:, 0]], p[idx[:, 1]], p[idx[:, 2]]

    def unit(v):
        return v / np.linalg.norm(v, axis=1, keepdims=True)

    v21, v31, v23 = unit(p2 - p1), unit(p3 - p1), unit(p2 - p3)
    angle = [
        np.rint(np.arccos(np.clip(np.abs(np.einsum("ij,ij->i", u, v)), 0, 1)) / (np.pi / 2) * (BINS - 1)).astype(
            np.int64
        )
        for u, v in ((v21, v31), (v23, v31), (v23, v21))
    ]  # at p1, p3, p2
    a = np.linalg.norm(p2 - p1, axis=1)
    b = np.linalg.norm(p3 - p1, axis=1)
    c = np.linalg.norm(p2 - p3, axis=1)
    s = (a + b + c) / 2
    d3 = np.sqrt(np.sqrt(s * (s - a) * (s - b) * (s - c)))
    d2 = np.concatenate([a, b, c])  # lines 1-2, 1-3, 2-3
    v1, v2, v3 = _voxels(p1), _voxels(p2), _voxels(p3)
    count, occupied = _trace(grid, np.concatenate([v1, v1, v2]), np.concatenate([v2, v3, v3]))
    line_in = occupied >= count - 1
    line_out = ~line_in & (occupied <= 7)
    line_mix = ~line_in & ~line_out
    hist = np.zeros((10, BINS))
    d2_bins = _bin(d2, float(d2.max()))
    for row, mask in ((6, line_in), (7, line_out), (8, line_mix)):
        hist[row] += np.bincount(d2_bins[mask], minlength=BINS)
    hist[9] += np.bincount(np.rint(occupied[line_mix] / count[line_mix] * (BINS - 1)).astype(np.int64), minlength=BINS)
    n = len(idx)
    count3, occupied3 = count.reshape(3, n), occupied.reshape(3, n)
    in_sum, visited_sum = occupied3.sum(axis=0), count3.sum(axis=0)
    tri_out = in_sum <= 21
    tri_in = ~tri_out & (visited_sum - in_sum < 4)
    tri_mix = ~tri_out & ~tri_in
    d3_bins = _bin(d3, float(d3.max()))
    opposite = (count3[2], count3[0], count3[1])  # angle at p1 weighs line 2-3, at p3 line 1-2, at p2 line 1-3
    for a3_row, d3_row, mask in ((0, 3, tri_in), (1, 4, tri_out), (2, 5, tri_mix)):
        for bins, weight in zip(angle, opposite, strict=True):
            hist[a3_row] += np.bincount(bins[mask], weight[mask] / 32.0, minlength=BINS)
        hist[d3_row] += np.bincount(d3_bins[mask], minlength=BINS)
    hist *= WEIGHTS[:, None]
    return (hist / hist.sum()).ravel()


class ESF(HistogramKind):
    name = "esf"
    summary = "Ensemble of Shape Functions (PCL's algorithm, re-implemented; thesis 3.6.1)"
    bins = 10 * BINS
    options = (
        Option("triplets", 20000, "random point triplets (PCL: 20,000)", integer(100, 10**7)),
        Option("seed", 0, "seed of the random triplets", integer(0)),
    )

    def compute(self, work, spec: DescriptorSpec, **context):
        view = work.view
        self.check_points(view)
        values = esf_histogram(view.canonical_vertices, triplets=spec.triplets, seed=spec.seed, name=view.name)
        return [self.histogram(spec, values, view)]


register(ESF())
