"""Scenes: the support plane of a depth frame and the objects standing on it, one view each (the step thesis 2.1
leaves outside its scope, as PCL's ``3d_rec_framework`` global pipeline does it).

:func:`segment_frame` reads a depth frame (and its colour) the way a tabletop pipeline does:

1. **planes**: up to :data:`MAX_PLANES` planes by RANSAC (open3d's ``segment_plane``, seeded, every sample drawn,
   then refit by least squares to its inliers, so that a frame is segmented the same every time), each holding at
   least ``plane_share`` of the readings; a **support plane** spans at least ``plane_size`` metres and has (almost)
   nothing hanging below its edges (an object's own face has: a box's top its sides, a chair's seat its legs). Of
   these, those facing up in the image (the normal within 60 deg of the image's up) come first (a table before the
   wall behind it; a camera looking straight down has no other), and of them the highest that anything stands on
   is the support (a table before the floor beneath it), else the largest (a bare table);
2. **the workspace**: the readings between ``min_height`` and ``max_height`` above the support plane whose foot on
   it lies inside the plane's outline (the convex hull of its inliers): not the wall behind the table, not the
   floor beyond it. Without a support plane (a frame of one isolated object, as the library's views are) every
   reading is in the workspace; and when nothing stands on the support plane of a frame whose readings cover less
   than half the image, the plane was an object's own face (a chair's seat) and the frame is segmented without it;
3. **clusters** of the workspace's points (open3d's ``cluster_dbscan``, ``cluster_distance`` apart at most, or three
   pixels' spacing in a far or coarse frame);
   clusters under ``min_pixels`` are dropped (speckle, flying pixels), and so is a cluster that is one flat surface
   wider than ``plane_size`` (a wall seen without a table), but in a frame of one isolated object (readings on less
   than half the image), where it is the object's face;
4. each cluster becomes a :class:`heatdata.View`, triangulated from its own pixels as a depth frame is
   (:func:`heatdata.views.depth.grid_view`), with every connected piece kept but specks below
   :data:`heatdata.views.view.MIN_VERTICES` vertices.

What a user should know about a segment is in its ``notes``: cut by the image border, in several pieces, and (the
library adds this) larger than any object it holds, which is what objects touching each other look like: they form
one segment. What the frame as a whole showed (no support plane, a plane seen edge-on, clusters dropped) is in the
:class:`Segmentation`'s ``notes``.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial import QhullError

from heatdata.core.mesh import component_labels, mesh_edges
from heatdata.errors import ViewError
from heatdata.views.depth import (
    MAX_DEPTH_JUMP,
    back_project,
    checked_depth,
    checked_rgb,
    cut_depth,
    grid_faces,
    grid_view,
)
from heatdata.views.view import MIN_VERTICES, View, check_intrinsics, has_colour

log = logging.getLogger(__name__)

MAX_PLANES = 3  # planes looked for before the support plane is chosen: a table, the floor, a wall
PLANE_POINTS = 20_000  # readings RANSAC samples from (a pixel stride), the inliers then counted over all
CLUSTER_POINTS = 8_000  # workspace points DBSCAN clusters (a pixel stride); the rest join their block's
FACING = np.cos(np.radians(30))  # a plane's region faces within 30 deg of its normal
HANGING_DEPTH = 0.05  # m: readings this far below a plane and under its edges hang from it (an object's sides)
HANGING_MARGIN = 0.02  # m: feet this near a plane's outline, either side, are along its edge (the outline stops short)
HANGING_SHARE = 0.1  # a support plane has at most this many readings hanging below it, per reading on it
EDGE_ON = 10.0  # degrees: a support plane seen at a median angle below this is seen edge-on
DBSCAN_POINTS = 10  # neighbours within cluster_distance that make a core point (fewer where the samples are sparser)
ISOLATED = 0.5  # a frame whose readings cover less of the image than this is of one object, when nothing stands on
# its support plane (the void around an object cut out of its frame, as a library's view is)
FOOTING = 0.5  # readings this share of the plane's distance above it may be an object's foot, where one touches
FLAT_SHARE = 0.95  # a cluster with this share of its points on one plane wider than plane_size is background
REFINE_STEPS = 5  # least-squares refinements of a RANSAC plane, at most
TRIM = 0.01  # the share of a segment's points, at each end of each principal axis, its size leaves out


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
        DBSCAN's distance: points nearer than this belong to one object.
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
    min_pixels: int = 300
    max_depth_jump: float = MAX_DEPTH_JUMP
    seed: int = 0

    def __post_init__(self) -> None:
        lengths = ("plane_distance", "plane_size", "max_height", "cluster_distance", "max_depth_jump")
        bad = [name for name in lengths if not _positive(getattr(self, name))]
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


def depth_scale(points: np.ndarray) -> np.ndarray:
    """(h, w): how much a depth sensor's error at each point exceeds its error at 1 m: ``max(1, z^2)`` (the noise
    of 2.6.1 and the disparity steps both grow as z^2), by which the plane's tolerances grow with depth."""
    with np.errstate(invalid="ignore"):
        return np.maximum(1.0, points[..., 2] ** 2)


def _positive(value) -> bool:
    return not isinstance(value, bool) and isinstance(value, (int, float)) and bool(np.isfinite(value)) and value > 0


@dataclass
class Segment:
    """One object's part of a frame.

    Attributes
    ----------
    view : View
        Its partial view (camera frame), every connected piece kept.
    mask : (h, w) bool or None
        Its pixels (None for a view given whole, :func:`segment_view`).
    pixels : int
        How many readings it holds.
    bbox : (4,) int
        ``u0, v0, u1, v1``: its pixels' bounding box, inclusive.
    centroid : (3,) float64
        The mean of its points in the camera frame, metres (x right, y down, z forward).
    extent : float
        Its largest size, metres: the diameter of its footprint on the support plane when there is one, else of its
        points (:data:`TRIM` of the outermost left out).
    notes : list of str
        What a user should know about it (cut by the image border, several pieces).
    """

    view: View
    mask: np.ndarray | None
    pixels: int
    bbox: tuple[int, int, int, int]
    centroid: np.ndarray
    extent: float
    notes: list[str] = field(default_factory=list)


@dataclass
class Segmentation:
    """What :func:`segment_frame` found in a frame.

    Attributes
    ----------
    plane : (4,) float64 or None
        The support plane ``a, b, c, d`` (``a x + b y + c z + d = 0`` in the camera frame, unit normal towards the
        camera: ``d > 0`` and a point's height above the plane is ``n . x + d``), or None.
    segments : list of Segment
        The objects, largest first.
    notes : list of str
        What the frame showed: the plane, or why there is none; clusters dropped.
    coloured : bool
        Whether the frame came with a colour image.
    depth : (h, w) float64 or None
        The frame's depth, metres, NaN where it has no reading (all of it, also outside a mask or depth range);
        None for a view given whole. A pose is checked against it (:mod:`heatdata.recognition.pose`).
    """

    plane: np.ndarray | None
    segments: list[Segment]
    notes: list[str] = field(default_factory=list)
    coloured: bool = False
    depth: np.ndarray | None = field(default=None, repr=False)


def segment_frame(
    depth: np.ndarray,
    intrinsics: dict,
    rgb: np.ndarray | None = None,
    settings: SegmentSettings | None = None,
    *,
    mask: np.ndarray | None = None,
    depth_range: tuple[float, float] | None = None,
    name: str = "frame",
) -> Segmentation:
    """The support plane of a depth frame and a view of each object on it (see the module docstring).

    Parameters
    ----------
    depth : (h, w) float
        z-depth in metres; NaN, infinite or <= 0 where there is no reading.
    intrinsics : dict
        ``fx, fy, cx, cy, width, height`` matching the image.
    rgb : (h, w, 3) uint8 or float in [0, 1], optional
        Colour registered to the depth image (default grey).
    settings : SegmentSettings, optional
        The plane, workspace and clustering settings.
    mask : (h, w) bool, optional
        The pixels to segment (an object cut out by the user: two objects in one mask are two segments).
    depth_range : (near, far) metres, optional
        Without a mask: the depths to segment.
    name : str
        The frame's name, for messages and the views' ids (``name/0``, ``name/1``...).

    Returns
    -------
    Segmentation
        The plane (or None), the segments, largest first (possibly none), and notes.

    Raises
    ------
    ViewError
        Intrinsics that do not match the image, an RGB image of another size, or no reading at all.
    """
    depth, k = checked_depth(depth, intrinsics, name)
    if mask is None and depth_range is None:
        return segment_points(back_project(depth, k), k, rgb, settings, name=name)
    cut, note = cut_depth(depth, mask, depth_range, name)
    found = segment_points(back_project(cut, k), k, rgb, settings, name=name)
    whole = np.where(np.isfinite(depth) & (depth > 0), depth, np.nan)
    return Segmentation(found.plane, found.segments, [note, *found.notes], found.coloured, whole)


def segment_points(
    points: np.ndarray,
    intrinsics: dict,
    colors: np.ndarray | None = None,
    settings: SegmentSettings | None = None,
    *,
    name: str = "frame",
) -> Segmentation:
    """:func:`segment_frame` of an organized grid of camera-frame points (an organized cloud's).

    Parameters
    ----------
    points : (h, w, 3) float
        Camera-frame points, metres (x right, y down, z forward); NaN where there is no reading.
    intrinsics : dict
        The camera's ``fx, fy, cx, cy, width, height`` (:func:`heatdata.views.clouds.fit_intrinsics` for a cloud).
    colors : (h, w, 3) uint8 or float in [0, 1], optional
        Their colours.
    settings : SegmentSettings, optional
        The plane, workspace and clustering settings.
    name : str
        The frame's name.

    Returns
    -------
    Segmentation
    """
    settings = settings or SegmentSettings()
    points = np.asarray(points, dtype=np.float64)
    if points.ndim != 3 or points.shape[2] != 3:
        raise ViewError(f"{name}: an organized grid of points is (h, w, 3), got shape {points.shape}")
    k = check_intrinsics(intrinsics, points.shape[:2], name)
    valid = np.isfinite(points).all(axis=2) & (points[..., 2] > 0)
    if not valid.any():
        raise ViewError(f"{name}: the frame has no valid reading (all zero, NaN or negative): an empty frame")
    points = np.where(valid[..., None], points, np.nan)
    colors = None if colors is None else checked_rgb(colors, valid.shape, name)
    notes: list[str] = []
    plane, inliers, outline = _support_plane(points, valid, settings, notes)
    footing = np.zeros(valid.shape, bool)
    if plane is None or outline is None:
        workspace = valid.copy()
    else:
        height = points @ plane[:3] + plane[3]
        with np.errstate(invalid="ignore"):
            scale = depth_scale(points)
            workspace = valid & ~inliers & (height > settings.min_height * scale) & (height <= settings.max_height)
            # the band an object's foot stands in, above the plane's noise: a segment grows into it where it touches
            footing = valid & (height > FOOTING * settings.plane_distance * scale) & ~workspace
        stride = max(1, int(np.sqrt(workspace.sum() / PLANE_POINTS)))
        # within the outline by a margin: not the wall rising at its edge (nor its base, in the foot's band, along
        # which an object standing by the wall would grow)
        workspace = outline.contains_grid(points, workspace, settings.plane_distance, stride)
        footing &= (height <= settings.min_height * scale) & outline.contains_grid(
            points, footing, settings.plane_distance, stride
        )
    isolated = valid.sum() < ISOLATED * valid.size
    segments = _clusters(points, colors, workspace, footing, plane, settings, notes, name, k, isolated)
    if not segments and plane is not None and isolated:
        notes.append(
            f"nothing stands on that plane, and the readings cover {valid.sum() / valid.size:.0%} of the image: a "
            "frame of one object seen over a face of its own (a chair's seat); segmented without a support"
        )
        plane = None
        segments = _clusters(points, colors, valid, np.zeros(valid.shape, bool), None, settings, notes, name, k, True)
    if not segments:
        notes.append(
            "no object on the support plane" if plane is not None else "no object in the frame (only flat background)"
        )
    for note in notes:
        log.debug("%s: %s", name, note)
    return Segmentation(
        plane, segments, notes, coloured=colors is not None, depth=np.where(valid, points[..., 2], np.nan)
    )


def segment_view(view: View, note: str) -> Segmentation:
    """A view already cut from its frame (a saved view, a frame segmented by a mask or a depth range) as the one
    segment of a frame with no support plane, so that it is answered as a scene's objects are.

    Parameters
    ----------
    view : View
        The object's view.
    note : str
        How it was segmented, for the answer's notes.

    Returns
    -------
    Segmentation
    """
    pixels = view.pixels
    low, high = np.floor(pixels.min(axis=0)).astype(int), np.ceil(pixels.max(axis=0)).astype(int)
    segment = Segment(
        view=view,
        mask=None,
        pixels=view.n_vertices,
        bbox=(int(low[0]), int(low[1]), int(high[0]), int(high[1])),
        centroid=view.vertices.mean(axis=0),
        extent=_diameter(view.vertices),
    )
    return Segmentation(None, [segment], [note], coloured=has_colour(view.colors))


def _basis(normal: np.ndarray) -> np.ndarray:
    """(2, 3): two unit vectors spanning the plane of ``normal``."""
    helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
    first = np.cross(normal, helper)
    first /= np.linalg.norm(first)
    return np.stack([first, np.cross(normal, first)])


class _Outline:
    """A plane's outline: the convex hull of its inliers' feet, in the plane's own 2D basis."""

    def __init__(self, plane: np.ndarray, inliers: np.ndarray):
        from scipy.spatial import ConvexHull

        self.basis = _basis(plane[:3])
        stride = max(1, len(inliers) // PLANE_POINTS)  # the hull of a sample is the hull, but for a sliver
        self.equations = ConvexHull(inliers[::stride] @ self.basis.T).equations

    def contains(self, points: np.ndarray, margin: float | np.ndarray = 0.0) -> np.ndarray:
        """(k,) bool: which of ``points`` (k, 3) have their foot at least ``margin`` (one, or (k,)) inside the
        outline."""
        feet = points @ self.basis.T
        limit = -np.reshape(np.asarray(margin, dtype=np.float64), (-1, 1))
        return np.all(feet @ self.equations[:, :2].T + self.equations[:, 2] <= limit, axis=1)

    def contains_grid(self, points: np.ndarray, candidates: np.ndarray, margin: float, stride: int) -> np.ndarray:
        """(h, w) bool: :meth:`contains` of the ``candidates`` pixels of an organized grid of ``points`` by ``margin``
        grown with depth (:func:`depth_scale`), tested on a pixel stride and exactly only where the stride's answer
        changes (the outline's edge)."""
        from scipy.ndimage import maximum_filter, minimum_filter

        coarse = np.zeros(points[::stride, ::stride].shape[:2], bool)
        sampled = candidates[::stride, ::stride]
        coarse_points = points[::stride, ::stride][sampled]
        coarse[sampled] = self.contains(coarse_points, margin * depth_scale(coarse_points))
        edge = maximum_filter(coarse, size=3, mode="nearest") != minimum_filter(coarse, size=3, mode="nearest")
        height, width = candidates.shape
        inside = np.repeat(np.repeat(coarse, stride, axis=0), stride, axis=1)[:height, :width] & candidates
        exact = np.repeat(np.repeat(edge, stride, axis=0), stride, axis=1)[:height, :width] & candidates
        inside[exact] = self.contains(points[exact], margin * depth_scale(points[exact]))
        return inside


def _support_plane(
    points: np.ndarray, valid: np.ndarray, settings: SegmentSettings, notes: list[str]
) -> tuple[np.ndarray | None, np.ndarray, _Outline | None]:
    """The support plane (unit normal towards the camera), its inliers (h, w) and outline; or None, none, None."""
    import open3d as o3d

    readings = int(valid.sum())
    stride = max(1, int(np.ceil(np.sqrt(readings / PLANE_POINTS))))
    sample = np.zeros(valid.shape, bool)
    sample[::stride, ::stride] = True
    sample &= valid
    grid = points[::stride, ::stride]  # the sample as an image, for each plane's connected region
    pieces = _pieces(grid, settings.max_depth_jump)[sample[::stride, ::stride]]  # its mesh's connected pieces
    sampled = points[sample]
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(sampled))
    o3d.utility.random.seed(settings.seed)
    candidates: list[tuple[np.ndarray, _Outline, float, int]] = []
    free = np.ones(len(sampled), bool)
    for _ in range(MAX_PLANES):
        if free.sum() < 3:
            break
        remaining = np.flatnonzero(free)
        model, _ = cloud.select_by_index(remaining).segment_plane(settings.plane_distance, 3, 500, probability=1.0)
        plane, chosen = _refined(sampled[remaining], model, settings.plane_distance)
        if len(chosen) < settings.plane_share * len(sampled):
            break
        free[remaining[chosen]] = False
        if plane[3] < 0:
            plane = -plane  # the camera (the origin) on the positive side
        height = sampled @ plane[:3] + plane[3]
        region = _largest_region(grid, plane, settings.plane_distance)
        on = region[sample[::stride, ::stride]]
        span = _diameter(sampled[on], plane)
        if span < settings.plane_size:
            notes.append(f"a plane {span:.2f} m across is smaller than a support plane ({settings.plane_size:g} m)")
            continue
        try:
            outline = _Outline(plane, sampled[on])
        except QhullError:  # its points on one line: a plane seen exactly edge-on
            notes.append(f"a plane {span:.2f} m across is seen as a line, edge-on: not a support")
            continue
        near = (np.abs(height) >= settings.min_height) & (np.abs(height) <= settings.max_height)
        standing = int(outline.contains(sampled[near & (height > 0)]).sum())
        # a box's sides hang from its top: below it, their feet along its edge, one piece of surface with it (the floor
        # seen under a table's front is deep inside its outline, and mostly another piece)
        piece = np.bincount(pieces[on]).argmax()
        deep = sampled[(height < -HANGING_DEPTH) & (height >= -settings.max_height) & (pieces == piece)]
        along = outline.contains(deep, -HANGING_MARGIN) & ~outline.contains(deep, HANGING_MARGIN)
        hanging = int(along.sum())
        if hanging > HANGING_SHARE * on.sum():
            notes.append(
                f"a plane {span:.2f} m across has {hanging * stride**2} readings hanging below its edges: the face of "
                "an object (a box's top, a seat), not a support"
            )
            continue
        candidates.append((plane, outline, span, standing))
    if not candidates:
        notes.append(
            f"no support plane (none holds {settings.plane_share:.0%} of the {readings} readings, spans "
            f"{settings.plane_size:g} m and has nothing hanging below its edges): every reading may be an object"
        )
        return None, np.zeros(valid.shape, bool), None
    # a table before the wall behind it (its normal within 60 deg of the image's up, -y); a camera looking down
    # on its table has no other plane
    facing_up = [c for c in candidates if -c[0][1] >= 0.5] or candidates
    # the highest plane something stands on (a table before the floor beneath it), else the largest
    bearing = [c for c in facing_up if c[3] > 0]
    plane, outline, span, _ = min(bearing, key=lambda c: c[0][3]) if bearing else max(facing_up, key=lambda c: c[2])
    with np.errstate(invalid="ignore"):
        inliers = valid & (np.abs(points @ plane[:3] + plane[3]) < settings.plane_distance * depth_scale(points))
    on = points[inliers][:: max(1, int(inliers.sum()) // PLANE_POINTS)]
    rays = on / np.linalg.norm(on, axis=1, keepdims=True)
    grazing = float(np.degrees(np.arcsin(np.clip(np.median(np.abs(rays @ plane[:3])), 0.0, 1.0))))
    notes.append(f"support plane: {int(inliers.sum())} readings, {span:.2f} m across, seen at {grazing:.0f} deg")
    if grazing < EDGE_ON:
        notes.append(
            f"the support plane is seen edge-on ({grazing:.0f} deg between the rays and the plane, below "
            f"{EDGE_ON:g}): objects' bottoms may be lost in it, and objects far back hide each other"
        )
    return plane, inliers, outline


def _pieces(grid: np.ndarray, max_depth_jump: float) -> np.ndarray:
    """(h, w) int: the connected piece of the depth grid's mesh each pixel belongs to (-1: no reading)."""
    valid = np.isfinite(grid).all(axis=2)
    index = np.full(valid.shape, -1, np.int64)
    index[valid] = np.arange(int(valid.sum()))
    count = int(valid.sum())
    faces = grid_faces(index, grid[valid][:, 2], max_depth_jump)
    pieces = np.full(valid.shape, -1, np.int64)
    pieces[valid] = component_labels(mesh_edges(faces, count), count)
    return pieces


def _largest_region(grid: np.ndarray, plane: np.ndarray, distance: float) -> np.ndarray:
    """(h, w) bool: the largest connected region of the image ``grid`` (h, w, 3) that lies within ``distance`` of
    ``plane`` and faces as it does (a table's top, not the strip of the wall that crosses its infinite plane)."""
    from scipy.ndimage import label

    with np.errstate(invalid="ignore"):
        near = (np.abs(grid @ plane[:3] + plane[3]) < distance) & (np.abs(_normals(grid) @ plane[:3]) > FACING)
    regions, count = label(near, structure=np.ones((3, 3)))
    if count == 0:
        return near
    return regions == 1 + int(np.argmax(np.bincount(regions[near])[1:]))


def _normals(grid: np.ndarray) -> np.ndarray:
    """(h, w, 3): unit normals of an organized grid of points by central differences (NaN at its edge and holes)."""
    normals = np.full(grid.shape, np.nan)
    across = grid[1:-1, 2:] - grid[1:-1, :-2]
    down = grid[2:, 1:-1] - grid[:-2, 1:-1]
    cross = np.cross(across, down)
    with np.errstate(invalid="ignore", divide="ignore"):
        normals[1:-1, 1:-1] = cross / np.linalg.norm(cross, axis=2, keepdims=True)
    return normals


def _refined(points: np.ndarray, model, distance: float) -> tuple[np.ndarray, np.ndarray]:
    """RANSAC's plane ``model`` refined by least squares on its inliers (within ``distance``) until they no longer
    change (at most :data:`REFINE_STEPS` times): the unit-normal plane and its inliers' indices.

    open3d's ``segment_plane`` runs in parallel threads and, seeded or not, does not return the same plane twice
    (its issue #7270); planes a little apart have nearly the same inliers, whose least-squares plane is the same, so
    the frame's segmentation no longer changes from one run to the next. Its early stop (``probability`` < 1) ends
    the threads' search after a number of samples that depends on their timing: on a busy machine a table's plane
    then came out another way in 3 of 6 runs and moved an object's segment, so the callers pass
    ``probability=1.0`` and every sample is drawn.
    """
    plane = np.asarray(model, np.float64) / np.linalg.norm(np.asarray(model, np.float64)[:3])
    inliers = np.flatnonzero(np.abs(points @ plane[:3] + plane[3]) < distance)
    for _ in range(REFINE_STEPS):
        if len(inliers) < 3:
            break
        centre = points[inliers].mean(axis=0)
        normal = np.linalg.svd(points[inliers] - centre, full_matrices=False)[2][2]
        normal = normal if normal @ plane[:3] >= 0 else -normal
        plane = np.append(normal, -normal @ centre)
        again = np.flatnonzero(np.abs(points @ plane[:3] + plane[3]) < distance)
        if np.array_equal(again, inliers):
            break
        inliers = again
    return plane, inliers


def _diameter(points: np.ndarray, plane: np.ndarray | None = None) -> float:
    """The largest distance between two of ``points`` (k, 3), their feet on ``plane`` when one is given: the diameter
    of their convex hull, the outermost :data:`TRIM` of them along each principal axis left out (a flying pixel at an
    edge, a speck of the table); unlike a bounding box's diagonal, it does not depend on how the object is turned."""
    from scipy.spatial import ConvexHull
    from scipy.spatial.distance import pdist

    if len(points) < 2:
        return 0.0
    feet = points @ _basis(plane[:3]).T if plane is not None else np.asarray(points, np.float64)
    centred = feet - feet.mean(axis=0)
    axes = np.linalg.svd(centred, full_matrices=False)[2]
    along = centred @ axes.T
    low, high = np.percentile(along, [100 * TRIM, 100 * (1 - TRIM)], axis=0)
    kept = feet[np.all((along >= low) & (along <= high), axis=1)]
    try:
        kept = kept[ConvexHull(kept).vertices]
    except QhullError:  # on a line or a plane of fewer dimensions: its own extent
        return float(np.linalg.norm(high - low))
    return float(pdist(kept).max())


def _clusters(
    points: np.ndarray,
    colors: np.ndarray | None,
    workspace: np.ndarray,
    footing: np.ndarray,
    plane: np.ndarray | None,
    settings: SegmentSettings,
    notes: list[str],
    name: str,
    intrinsics: dict,
    isolated: bool,
) -> list[Segment]:
    """The workspace's clusters, each a :class:`Segment` (DBSCAN on a pixel stride, the rest joining the nearest),
    grown into the ``footing`` pixels they touch (an object's foot, near the plane)."""
    import open3d as o3d
    from scipy.ndimage import binary_propagation

    count = int(workspace.sum())
    if count < settings.min_pixels:
        if count:
            notes.append(f"dropped {count} readings in the workspace: fewer than {settings.min_pixels}")
        return []
    stride = max(1, int(np.ceil(np.sqrt(count / CLUSTER_POINTS))))
    rows, cols = np.nonzero(workspace)
    sampled = (rows % stride == 0) & (cols % stride == 0)
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points[rows[sampled], cols[sampled]]))
    grid = np.full(workspace.shape, -1, np.int64)
    # DBSCAN's radius is the cluster distance, or three pixels' spacing where the pixels lie farther apart (a far or
    # coarse frame: a chair's leg holds its core points), widened with the stride
    spacing = float(np.median(points[rows[sampled], cols[sampled], 2])) / intrinsics["fx"]
    radius = stride * max(settings.cluster_distance, 3.0 * spacing)
    core = max(3, int(DBSCAN_POINTS * (settings.cluster_distance / radius) ** 2))  # as many neighbours per area
    grid[rows[sampled], cols[sampled]] = cloud.cluster_dbscan(radius, core)
    # the other pixels join the cluster of a sampled corner of their stride cell, the first near enough
    labels = grid[rows, cols]
    height, width = workspace.shape
    for anchor_rows, anchor_cols in (
        (rows - rows % stride, cols - cols % stride),
        (np.minimum(rows - rows % stride + stride, height - 1), cols - cols % stride),
        (rows - rows % stride, np.minimum(cols - cols % stride + stride, width - 1)),
        (np.minimum(rows - rows % stride + stride, height - 1), np.minimum(cols - cols % stride + stride, width - 1)),
    ):
        open_ = labels < 0
        candidate = grid[anchor_rows[open_], anchor_cols[open_]]
        gap = np.linalg.norm(points[rows[open_], cols[open_]] - points[anchor_rows[open_], anchor_cols[open_]], axis=1)
        labels[open_] = np.where((candidate >= 0) & (gap <= radius), candidate, -1)
    sizes = np.bincount(labels[labels >= 0]) if (labels >= 0).any() else np.zeros(0, np.int64)
    segments: list[Segment] = []
    small = flat = 0
    for label in np.argsort(-sizes, kind="stable"):
        if sizes[label] < settings.min_pixels:
            small += int(sizes[label])
            continue
        mask = np.zeros(workspace.shape, bool)
        mask[rows[labels == label], cols[labels == label]] = True
        if footing.any():
            mask = binary_propagation(mask, structure=np.ones((3, 3)), mask=mask | footing)
        segment = _segment(points, colors, mask, plane, settings, f"{name}/{len(segments)}", intrinsics, isolated)
        if segment is None:
            flat += 1
            continue
        segments.append(segment)
    noise = int((labels < 0).sum())
    if small or noise:
        notes.append(f"dropped {small + noise} readings in clusters under {settings.min_pixels} pixels or alone")
    if flat:
        notes.append(f"dropped {flat} flat cluster(s) wider than {settings.plane_size:g} m: background, not objects")
    return segments


def _segment(
    points: np.ndarray,
    colors: np.ndarray | None,
    mask: np.ndarray,
    plane: np.ndarray | None,
    settings: SegmentSettings,
    view_id: str,
    intrinsics: dict,
    isolated: bool,
) -> Segment | None:
    """The :class:`Segment` of the pixels ``mask``; None for a flat background surface (not in a frame of one
    isolated object, where a flat cluster is the object's face)."""
    import open3d as o3d

    cloud = points[mask]
    if _diameter(cloud, plane) > settings.plane_size and not isolated:
        o3d.utility.random.seed(settings.seed)
        tolerance = settings.plane_distance * float(np.median(depth_scale(cloud)))
        flat = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(cloud))
        model, _ = flat.segment_plane(tolerance, 3, 200, probability=1.0)
        if len(_refined(cloud, model, tolerance)[1]) >= FLAT_SHARE * len(cloud):
            return None
    notes = []
    height, width = mask.shape
    rows, cols = np.nonzero(mask)
    u0, v0, u1, v1 = int(cols.min()), int(rows.min()), int(cols.max()), int(rows.max())
    if u0 == 0 or v0 == 0 or u1 == width - 1 or v1 == height - 1:
        notes.append("cut by the image border: part of the object is outside the frame")
    window = (slice(v0, v1 + 1), slice(u0, u1 + 1))  # the view's vertices are camera coordinates: crop freely
    grid = np.where(mask[window][..., None], points[window], np.nan)
    try:
        view = grid_view(
            grid, None if colors is None else colors[window], max_depth_jump=settings.max_depth_jump,
            components="all", intrinsics=intrinsics, view_id=view_id,
        )  # fmt: skip
    except ViewError as exc:
        log.info("%s: no view (%s)", view_id, exc)
        return None
    sizes = np.bincount(view.component_labels)
    if (sizes < MIN_VERTICES).any():
        keep = sizes[view.component_labels] >= MIN_VERTICES
        if not keep.any():
            return None
        dropped = int((sizes < MIN_VERTICES).sum())
        view = view.submesh(keep, f"dropped {dropped} speck(s) under {MIN_VERTICES} vertices")
    if view.n_components > 1:
        notes.append(f"in {view.n_components} pieces (the surface breaks at depth steps); all are kept")
    return Segment(
        view=view,
        mask=mask,
        pixels=int(mask.sum()),
        bbox=(u0, v0, u1, v1),
        centroid=cloud.mean(axis=0),
        extent=_diameter(view.vertices, plane),
        notes=notes,
    )
