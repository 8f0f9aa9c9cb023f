"""The settings of a frame's segmentation (:func:`heatdata.segmentation.segment.segment_frame`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from heatdata.errors import ViewError
from heatdata.views.depth import MAX_DEPTH_JUMP


@dataclass(frozen=True)
class SegmentSettings:
    """How :func:`segment_frame` finds the support plane and the objects on it (lengths in metres).

    Attributes
    ----------
    plane_distance : float
        RANSAC's inlier distance to a plane; a reading at depth z > 1 m is on the plane within ``z^2`` times this
        (:func:`depth_scale`).
    plane_share : float
        A plane holds at least this share of the frame's readings.
    plane_size : float
        A support plane spans at least this (its inliers' largest extent); a flat cluster wider than this is
        background.
    min_height, max_height : float
        The workspace: how far above the support plane an object's points lie (``min_height`` grows as
        ``plane_distance`` does beyond 1 m).
    cluster_distance : float
        A pixel between cuts joins the nearest object's surface when it lies nearer to it than this.
    concavity : float
        Degrees: surfaces meeting at a concave crease sharper than this are two objects (LCCP's concavity
        tolerance; Stein et al., CVPR 2014, use 10 on supervoxels).
    piece_area : float
        Square metres, as the camera sees it: a piece cut off smaller than this joins the neighbour it shares the
        longest border with (a mug's handle, a dish's lid; LCCP's minimum segment size).
    min_pixels : int
        Clusters with fewer readings are dropped.
    max_depth_jump : float
        The triangulation's relative depth step (:func:`heatdata.views.depth.grid_faces`).
    seed : int
        RANSAC's seed (open3d's global random generator).
    """

    plane_distance: float = 0.008
    plane_share: float = 0.05
    plane_size: float = 0.4
    min_height: float = 0.008
    max_height: float = 1.0
    cluster_distance: float = 0.015
    concavity: float = 20.0
    piece_area: float = 0.004
    min_pixels: int = 300
    max_depth_jump: float = MAX_DEPTH_JUMP
    seed: int = 0

    def __post_init__(self) -> None:
        lengths = ("plane_distance", "plane_size", "max_height", "cluster_distance", "max_depth_jump", "piece_area")
        bad = [name for name in lengths if not _positive(getattr(self, name))]
        if not (_positive(self.concavity) and self.concavity < 180):
            bad.append("concavity (degrees in (0, 180))")
        if not (_positive(self.plane_share) and self.plane_share < 1):
            bad.append("plane_share (a share in (0, 1))")
        if not (_positive(self.min_height) or self.min_height == 0) or not self.min_height < self.max_height:
            bad.append("min_height (>= 0 and below max_height)")
        if (
            isinstance(self.min_pixels, bool)
            or not isinstance(self.min_pixels, (int, np.integer))
            or self.min_pixels < 3
        ):
            bad.append("min_pixels (a whole number >= 3)")
        if bad:
            raise ViewError(f"bad segmentation settings: {', '.join(bad)}")


def _positive(value) -> bool:
    return not isinstance(value, bool) and isinstance(value, (int, float)) and bool(np.isfinite(value)) and value > 0
