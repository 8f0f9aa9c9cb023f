"""Registration of two overlapping scans, the field's answer where JASNOM's premise does not hold.

Two scans that share part of their surface (an object turned 90 degrees between them) are aligned by the overlap
itself: open3d's global registration (FPFH features of voxel-downsampled points, matched by RANSAC with a fixed seed;
Rusu et al. 2009), refined by point-to-plane ICP on the full-resolution points (``registration_icp``). How much of
the smaller scan lies on the other after the motion (ICP's fitness) is the measured overlap; :func:`overlap_share`
gives it, and ``heatdata stitch`` registers a pair above :data:`MIN_OVERLAP` and stitches the rest with JASNOM.

The voxel is a fraction of the scans' size (:data:`VOXELS_PER_SIZE`), the feature radius five voxels, the inlier
distance 1.5 voxels for RANSAC and :data:`ICP_VOXELS` for ICP, as in open3d's global registration tutorial.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np

from heatdata.errors import StitchError
from heatdata.jasnom.rays import RayDepths

log = logging.getLogger(__name__)

#: the voxel of the downsampled points, as a fraction of the larger scan's bounding-box diagonal
VOXELS_PER_SIZE = 50
#: ICP's inlier distance, in voxels
ICP_VOXELS = 1.0
#: the least share of the smaller scan that must lie on the other after registration for a pair to be registered
#: rather than stitched (the overlapping bunny pair: 61-62%). A wrong motion can reach it too (47-58% where the
#: opposite bunny scans' smooth back was matched onto the front): :data:`MAX_IN_FRONT` tells those apart
MIN_OVERLAP = 0.3
#: the most of either scan, of its points on the other's rays, that may lie in front of the other's surface, seen
#: from the other's camera, for a registration to stand: the space between a camera and the surface it measured is
#: empty, so a motion that puts one scan there is wrong. Measured from five random starts each
#: (``scripts/scan_pairs.py``): 22-30% where FPFH + RANSAC matched the smooth back of the bunny onto its front
#: (opposite scans), 5-7% at the right motion of the overlapping pair; on rendered views 40 degrees apart at most 9%,
#: and 15-28% on opposite views of objects without a symmetry
MAX_IN_FRONT = 0.15
#: how much nearer its camera than the surface there a point must lie to count as in front, in voxels
IN_FRONT_VOXELS = 0.5
#: RANSAC's iterations and confidence
RANSAC_ITERATIONS, RANSAC_CONFIDENCE = 100_000, 0.999
#: the fewest points a scan needs for features and a motion
MIN_POINTS = 30


@dataclass(frozen=True)
class Registration:
    """The rigid motion of the second scan onto the first found by their overlap, and how much they overlap there.

    Attributes
    ----------
    rotation : (3, 3) float64
    translation : (3,) float64
        ``x = rotation @ y + translation`` maps the second scan into the first's frame.
    overlap : float
        The share of the smaller scan's downsampled points within ICP's inlier distance of the other scan at the
        motion, in [0, 1].
    in_front : float
        The larger of the two shares of a scan's points on the other's rays that lie in front of the other's surface,
        seen from the other's camera (:func:`in_front`), in [0, 1].
    rmse : float
        The RMS distance of those inliers, in the scans' units.
    voxel : float
        The downsampling voxel, in the scans' units.
    seconds : float
    """

    rotation: np.ndarray
    translation: np.ndarray
    overlap: float
    in_front: float
    rmse: float
    voxel: float
    seconds: float

    @property
    def overlapping(self) -> bool:
        """Whether the registration stands: the scans share enough surface (:data:`MIN_OVERLAP`), and neither lies
        in front of the other (:data:`MAX_IN_FRONT`)."""
        return self.overlap >= MIN_OVERLAP and self.in_front <= MAX_IN_FRONT


def _cloud(points: np.ndarray, voxel: float):
    import open3d as o3d

    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(np.asarray(points, np.float64))).voxel_down_sample(voxel)
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=2 * voxel, max_nn=30))
    cloud.orient_normals_towards_camera_location(np.zeros(3))
    return cloud


def fpfh_ransac(first, second, voxel: float, *, seed: int = 0) -> np.ndarray:
    """open3d's global registration of two downsampled clouds with normals: FPFH features (radius 5 voxels) matched
    mutually by RANSAC (3 points, edge-length and 1.5-voxel distance checks, seeded).

    Parameters
    ----------
    first, second : open3d.geometry.PointCloud
        Downsampled at ``voxel``, with normals.
    voxel : float
    seed : int
        open3d's random seed.

    Returns
    -------
    (4, 4) float64
        The motion of ``second`` onto ``first``.
    """
    import open3d as o3d

    registration = o3d.pipelines.registration
    features = [
        registration.compute_fpfh_feature(cloud, o3d.geometry.KDTreeSearchParamHybrid(radius=5 * voxel, max_nn=100))
        for cloud in (first, second)
    ]
    o3d.utility.random.seed(seed)
    found = registration.registration_ransac_based_on_feature_matching(
        second,
        first,
        features[1],
        features[0],
        True,
        1.5 * voxel,
        registration.TransformationEstimationPointToPoint(False),
        3,
        [
            registration.CorrespondenceCheckerBasedOnEdgeLength(0.9),
            registration.CorrespondenceCheckerBasedOnDistance(1.5 * voxel),
        ],
        registration.RANSACConvergenceCriteria(RANSAC_ITERATIONS, RANSAC_CONFIDENCE),
    )
    return np.asarray(found.transformation)


def register(first: np.ndarray, second: np.ndarray, *, seed: int = 0, voxel: float | None = None) -> Registration:
    """FPFH + RANSAC, then point-to-plane ICP: the motion of ``second`` onto ``first`` (module docstring).

    Parameters
    ----------
    first, second : (n, 3) float
        The scans' points, each in its camera's frame (the camera at the origin, so that normals face it).
    seed : int
        open3d's random seed for RANSAC.
    voxel : float, optional
        The downsampling voxel (default: :data:`VOXELS_PER_SIZE` voxels across the larger scan's diagonal).

    Returns
    -------
    Registration

    Raises
    ------
    StitchError
        A scan of fewer than :data:`MIN_POINTS` points after downsampling.
    """
    import open3d as o3d

    begin = time.perf_counter()
    first, second = np.asarray(first, np.float64), np.asarray(second, np.float64)
    registration = o3d.pipelines.registration
    size = max(float(np.linalg.norm(np.ptp(np.asarray(p), axis=0))) for p in (first, second))
    voxel = size / VOXELS_PER_SIZE if voxel is None else float(voxel)
    clouds = [_cloud(points, voxel) for points in (first, second)]
    for name, cloud in zip(("first", "second"), clouds, strict=True):
        if len(cloud.points) < MIN_POINTS:
            raise StitchError(
                f"the {name} scan has {len(cloud.points)} points at a {voxel:.3g} voxel: at least {MIN_POINTS} are "
                "needed to register it"
            )
    coarse = fpfh_ransac(clouds[0], clouds[1], voxel, seed=seed)
    fine = registration.registration_icp(
        clouds[1],
        clouds[0],
        ICP_VOXELS * voxel,
        coarse,
        registration.TransformationEstimationPointToPlane(),
        registration.ICPConvergenceCriteria(max_iteration=100),
    )
    motion = np.asarray(fine.transformation)
    points = [np.asarray(cloud.points) for cloud in clouds]
    back = np.linalg.inv(motion)
    found = Registration(
        rotation=motion[:3, :3].copy(),
        translation=motion[:3, 3].copy(),
        overlap=overlap_share(points[0], points[1], motion, ICP_VOXELS * voxel),
        in_front=max(  # on every point: a voxel's points sample a slope at other depths than its own
            in_front(first, second @ motion[:3, :3].T + motion[:3, 3], IN_FRONT_VOXELS * voxel),
            in_front(second, first @ back[:3, :3].T + back[:3, 3], IN_FRONT_VOXELS * voxel),
        ),
        rmse=float(fine.inlier_rmse),
        voxel=voxel,
        seconds=time.perf_counter() - begin,
    )
    log.info(
        "registered: %.0f%% of the smaller scan overlaps the other, %.0f%% lies in front of it (RMS %.3g at a %.3g "
        "voxel), %.1f s",
        100 * found.overlap,
        100 * found.in_front,
        found.rmse,
        voxel,
        found.seconds,
    )
    return found


def overlap_share(first: np.ndarray, second: np.ndarray, motion: np.ndarray, distance: float) -> float:
    """The share of the smaller of two point sets that lies within ``distance`` of the other, ``second`` moved by
    ``motion`` (4 x 4) into ``first``'s frame.

    Parameters
    ----------
    first, second : (n, 3) float
    motion : (4, 4) float
    distance : float

    Returns
    -------
    float
        In [0, 1].
    """
    from scipy.spatial import cKDTree

    moved = np.asarray(second) @ motion[:3, :3].T + motion[:3, 3]
    near = (
        cKDTree(first).query(moved, distance_upper_bound=distance)[0]
        if len(moved) <= len(first)
        else cKDTree(moved).query(first, distance_upper_bound=distance)[0]
    )
    return float(np.mean(np.isfinite(near)))


def in_front(seen: np.ndarray, other: np.ndarray, tolerance: float) -> float:
    """The share of ``other``'s points on ``seen``'s rays that lie in front of the surface ``seen`` measured, both in
    ``seen``'s camera frame (camera at the origin): a point is compared with the point of ``seen`` nearest its ray
    from the camera (within twice ``seen``'s median angular spacing), and lies in front when it is nearer the camera
    by more than ``tolerance``. Points whose ray misses ``seen`` are not counted.

    Parameters
    ----------
    seen, other : (n, 3) float
    tolerance : float

    Returns
    -------
    float
        In [0, 1]; 0 when no point is on ``seen``'s rays.
    """
    depth = RayDepths.of(np.asarray(seen, np.float64)).in_front(np.asarray(other, np.float64))
    hit = np.isfinite(depth)
    return float(np.sum(depth[hit] > tolerance) / max(int(hit.sum()), 1))
