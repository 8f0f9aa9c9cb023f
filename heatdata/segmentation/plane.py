"""The support plane of a frame: RANSAC planes, the one objects stand on, its outline (thesis 2.1's tabletop, as
PCL's ``3d_rec_framework`` finds it)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.spatial import QhullError

from heatdata.core.mesh import component_labels, mesh_edges
from heatdata.segmentation.settings import SegmentSettings
from heatdata.views.depth import grid_faces

MAX_PLANES = 3  # planes looked for before the support plane is chosen: a table, the floor, a wall
PLANE_POINTS = 20_000  # readings RANSAC samples from (a pixel stride), the inliers then counted over all
FACING = np.cos(np.radians(30))  # a plane's region faces within 30 deg of its normal
HANGING_DEPTH = 0.05  # m: readings this far below a plane and under its edges hang from it (an object's sides)
HANGING_MARGIN = 0.02  # m: feet this near a plane's outline, either side, are along its edge (the outline stops short)
HANGING_SHARE = 0.1  # a support plane has at most this many readings hanging below it, per reading on it
TABLE_DISTANCE = (0.2, 4.0)  # m: from the camera to a support plane, nearest and farthest plausible
EDGE_ON = 10.0  # degrees: a support plane seen at a median angle below this is seen edge-on
RANSAC_SAMPLES = 250  # every one drawn; 500 scored the same on 56 real and 100 rendered frames, in twice the time
REFINE_STEPS = 5  # least-squares refinements of a RANSAC plane, at most
REGION_PIXELS = 20  # pixels of the RANSAC sample: smaller pieces of a plane are not its outline's
STANDS_ON = 0.3  # m: a plane this little above a wider one is an object's top standing on it (a book, a tray)
TRIM = 0.01  # the share of a segment's points, at each end of each principal axis, its size leaves out


def depth_scale(points: np.ndarray) -> np.ndarray:
    """(h, w): how much a depth sensor's error at each point exceeds its error at 1 m: ``max(1, z^2)`` (the noise
    of 2.6.1 and the disparity steps both grow as z^2), by which the plane's tolerances grow with depth."""
    with np.errstate(invalid="ignore"):
        return np.maximum(1.0, points[..., 2] ** 2)


def _basis(normal: np.ndarray) -> np.ndarray:
    """(2, 3): two unit vectors spanning the plane of ``normal``."""
    helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
    first = np.cross(normal, helper)
    first /= np.linalg.norm(first)
    return np.stack([first, np.cross(normal, first)])


class Outline:
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


class _Candidate(NamedTuple):
    """A plane that may be the support: unit normal towards the camera and offset, outline, span (metres), sampled
    readings standing on it, and the centre of its facing region."""

    plane: np.ndarray
    outline: Outline
    span: float
    standing: int
    centre: np.ndarray


def support_plane(
    points: np.ndarray, valid: np.ndarray, settings: SegmentSettings, notes: list[str]
) -> tuple[np.ndarray | None, np.ndarray, Outline | None]:
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
    candidates: list[_Candidate] = []
    free = np.ones(len(sampled), bool)
    for _ in range(MAX_PLANES):
        if free.sum() < 3:
            break
        remaining = np.flatnonzero(free)
        model, _ = cloud.select_by_index(remaining).segment_plane(
            settings.plane_distance, 3, RANSAC_SAMPLES, probability=1.0
        )
        plane, chosen = refined_plane(sampled[remaining], model, settings.plane_distance)
        if len(chosen) < settings.plane_share * len(sampled):
            break
        free[remaining[chosen]] = False
        if plane[3] < 0:
            plane = -plane  # the camera (the origin) on the positive side
        height = sampled @ plane[:3] + plane[3]
        region = facing_region(grid, plane, settings.plane_distance)
        on = region[sample[::stride, ::stride]]
        span = diameter(sampled[on], plane)
        if span < settings.plane_size:
            notes.append(f"a plane {span:.2f} m across is smaller than a support plane ({settings.plane_size:g} m)")
            continue
        try:
            outline = Outline(plane, sampled[on])
        except (QhullError, ValueError):  # its points on one line (a plane seen edge-on), or too few for an outline
            held = f"{int(on.sum())} sampled readings"
            notes.append(f"a plane {span:.2f} m across of {held} has no outline (a line, edge-on): not a support")
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
        candidates.append(_Candidate(plane, outline, span, standing, sampled[on].mean(axis=0)))
    if not candidates:
        notes.append(
            f"no support plane (none holds {settings.plane_share:.0%} of the {readings} readings, spans "
            f"{settings.plane_size:g} m and has nothing hanging below its edges): every reading may be an object"
        )
        return None, np.zeros(valid.shape, bool), None
    # a table before the wall behind it (its normal within 60 deg of the image's up, -y); a camera looking down
    # on its table has no other plane
    facing_up = [c for c in candidates if -c.plane[1] >= 0.5] or candidates
    # not the top of a wide flat object (a book, a tray) standing on a wider plane: the table under it
    facing_up = [c for c in facing_up if not any(_stands_on(c, other) for other in facing_up)]
    # the highest plane something stands on (a table before the floor beneath it), else the largest
    bearing = [c for c in facing_up if c.standing > 0]
    support = min(bearing, key=lambda c: c.plane[3]) if bearing else max(facing_up, key=lambda c: c.span)
    plane, outline, span = support.plane, support.outline, support.span
    with np.errstate(invalid="ignore"):
        inliers = valid & (np.abs(points @ plane[:3] + plane[3]) < settings.plane_distance * depth_scale(points))
    on = points[inliers][:: max(1, int(inliers.sum()) // PLANE_POINTS)]
    rays = on / np.linalg.norm(on, axis=1, keepdims=True)
    grazing = float(np.degrees(np.arcsin(np.clip(np.median(np.abs(rays @ plane[:3])), 0.0, 1.0))))
    notes.append(f"support plane: {int(inliers.sum())} readings, {span:.2f} m across, seen at {grazing:.0f} deg")
    near, far = TABLE_DISTANCE
    if not near <= plane[3] <= far:
        notes.append(
            f"the support plane is {plane[3]:.3g} m from the camera, outside the {near:g}-{far:g} m a depth sensor "
            "sees a table at: is the depth's unit right (a PNG holds millimetres, a .npy metres)?"
        )
    if grazing < EDGE_ON:
        notes.append(
            f"the support plane is seen edge-on ({grazing:.0f} deg between the rays and the plane, below "
            f"{EDGE_ON:g}): objects' bottoms may be lost in it, and objects far back hide each other"
        )
    return plane, inliers, outline


def _stands_on(top: _Candidate, under: _Candidate) -> bool:
    """Whether the candidate plane ``top`` is an object's top standing on the wider, parallel plane ``under``: its
    centre less than :data:`STANDS_ON` above it."""
    if under.span <= top.span or abs(top.plane[:3] @ under.plane[:3]) < FACING:
        return False
    return 0.0 < float(top.centre @ under.plane[:3] + under.plane[3]) < STANDS_ON


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


def facing_region(grid: np.ndarray, plane: np.ndarray, distance: float) -> np.ndarray:
    """(h, w) bool: the pixels of the image ``grid`` (h, w, 3) that lie within ``distance`` of ``plane`` and face as
    it does (a table's top, not the strip of the wall that crosses its infinite plane), in connected regions of at
    least :data:`REGION_PIXELS` (a real table is seen in many pieces between the objects on it)."""
    from scipy.ndimage import label

    with np.errstate(invalid="ignore"):
        near = (np.abs(grid @ plane[:3] + plane[3]) < distance) & (np.abs(_normals(grid) @ plane[:3]) > FACING)
    regions, count = label(near, structure=np.ones((3, 3)))
    if count == 0:
        return near
    sizes = np.bincount(regions.ravel())
    sizes[0] = 0
    keep = sizes >= min(REGION_PIXELS, sizes.max())
    return keep[regions]


def _normals(grid: np.ndarray) -> np.ndarray:
    """(h, w, 3): unit normals of an organized grid of points by central differences (NaN at its edge and holes)."""
    normals = np.full(grid.shape, np.nan)
    across = grid[1:-1, 2:] - grid[1:-1, :-2]
    down = grid[2:, 1:-1] - grid[:-2, 1:-1]
    cross = np.cross(across, down)
    with np.errstate(invalid="ignore", divide="ignore"):
        normals[1:-1, 1:-1] = cross / np.linalg.norm(cross, axis=2, keepdims=True)
    return normals


def refined_plane(points: np.ndarray, model, distance: float) -> tuple[np.ndarray, np.ndarray]:
    """RANSAC's plane ``model`` refined by least squares on its inliers (within ``distance``) until they no longer
    change (at most :data:`REFINE_STEPS` times): the unit-normal plane and its inliers' indices.

    open3d's ``segment_plane`` runs in parallel threads and, seeded or not, does not return the same plane twice
    (its issue #7270); planes a little apart have nearly the same inliers, whose least-squares plane is the same, so
    the frame's segmentation no longer changes from one run to the next. Its early stop (``probability`` < 1) ends
    the threads' search after a number of samples that depends on their timing: on a busy machine a table's plane
    then came out another way in 3 of 6 runs and moved an object's segment, so the callers pass
    ``probability=1.0`` and every sample is drawn.
    """
    model = np.asarray(model, np.float64)
    length = float(np.linalg.norm(model[:3]))
    if not (np.isfinite(model).all() and length > 0):  # RANSAC drew three points of one spot: no plane
        return np.array([0.0, 0.0, 1.0, 0.0]), np.zeros(0, np.int64)
    plane = model / length
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


def diameter(points: np.ndarray, plane: np.ndarray | None = None) -> float:
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
    if len(kept) < feet.shape[1] + 1:  # too few left for a hull (a speck of a few readings)
        return float(np.linalg.norm(high - low))
    try:
        kept = kept[ConvexHull(kept).vertices]
    except QhullError:  # on a line or a plane of fewer dimensions: its own extent
        return float(np.linalg.norm(high - low))
    return float(pdist(kept).max())
