"""Compiled kernels of the ESF (:mod:`heatdata.descriptors.esf`; numba, cached on disk).

The random triplets and their float geometry stay in numpy; these kernels do what loops
over voxels do: marking the occupancy grid and tracing each triplet's three lines
through it (PCL's ``lci``). Both give exactly what the vectorized numpy code gave:
the same voxels, in the same order, with the same integer counts.
"""

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def occupancy(voxels, grid):  # pragma: no cover - compiled
    """Mark each (n, 3) voxel and its 26 neighbours in the cubic bool ``grid`` (PCL's voxelize9)."""
    size = grid.shape[0]
    for i in range(voxels.shape[0]):
        for dx in range(-1, 2):
            x = voxels[i, 0] + dx
            if x < 0 or x >= size:
                continue
            for dy in range(-1, 2):
                y = voxels[i, 1] + dy
                if y < 0 or y >= size:
                    continue
                for dz in range(-1, 2):
                    z = voxels[i, 2] + dz
                    if 0 <= z < size:
                        grid[x, y, z] = True


@njit(cache=True, nogil=True)
def trace(grid, start, end, count, occupied):  # pragma: no cover - compiled
    """For each line from voxel ``start[i]`` to ``end[i]`` (both (lines, 3) int64): ``count[i]``, the voxels
    visited (one per step of the longest axis, the end excluded, at least 1), and ``occupied[i]``, how many
    of them are set in ``grid``.

    Step k visits ``rint(start + delta * (k / steps))``, clipped to the grid, as the numpy code did.
    """
    top = grid.shape[0] - 1
    for i in range(start.shape[0]):
        d0, d1, d2 = end[i, 0] - start[i, 0], end[i, 1] - start[i, 1], end[i, 2] - start[i, 2]
        steps = max(abs(d0), abs(d1), abs(d2), 1)
        hits = 0
        for k in range(steps):
            f = k / steps
            x = min(max(int(np.rint(start[i, 0] + d0 * f)), 0), top)
            y = min(max(int(np.rint(start[i, 1] + d1 * f)), 0), top)
            z = min(max(int(np.rint(start[i, 2] + d2 * f)), 0), top)
            if grid[x, y, z]:
                hits += 1
        count[i] = steps
        occupied[i] = hits
