"""What a scan's camera measured along its rays: how far another surface's points stand in front of it.

The space between a camera and the surface it measured is empty. A point of another scan, moved into this scan's
camera frame (camera at the origin), that lies on one of its rays nearer the camera than the surface there cannot be
there: the motion that put it there is wrong. Registration (:mod:`heatdata.jasnom.register`) uses the share of such
points to tell a wrong match from a right one, and JASNOM (:mod:`heatdata.jasnom.align`) their depth as a cost.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree


@dataclass(frozen=True)
class RayDepths:
    """A scan's points as its camera saw them: the direction of each ray and its range.

    Attributes
    ----------
    ranges : (n,) float64
        Each point's distance from the camera.
    tree : cKDTree
        The unit directions of the rays.
    spacing : float
        The median angle between a ray and its nearest neighbour (radians, as a chord of the unit sphere): a point
        is on the scan's rays when its direction lies within two of these of one.
    """

    ranges: np.ndarray
    tree: cKDTree
    spacing: float

    @classmethod
    def of(cls, points: np.ndarray) -> RayDepths:
        """The rays of ``points`` (n, 3), in their camera's frame (each at a positive distance from it)."""
        ranges = np.linalg.norm(points, axis=1)
        tree = cKDTree(points / ranges[:, None])
        return cls(ranges, tree, float(np.median(tree.query(tree.data, k=2)[0][:, 1])))

    def in_front(self, points: np.ndarray) -> np.ndarray:
        """How much nearer the camera than the measured surface each of ``points`` (m, 3) lies, along the nearest
        ray within two ray spacings (negative: behind it; NaN where no ray is that near).

        Returns
        -------
        (m,) float64
        """
        ranges = np.linalg.norm(points, axis=1)
        gap, nearest = self.tree.query(points / ranges[:, None], distance_upper_bound=2 * self.spacing)
        depth = np.full(len(points), np.nan)
        hit = np.isfinite(gap)
        depth[hit] = self.ranges[nearest[hit]] - ranges[hit]
        return depth
