"""Where an object is: a 6-DoF pose by ICP from the nearest library view, and the check that it explains the segment.

The thesis recognizes an object and the angle it is seen from (ch. 3: the nearest library view's azimuth). A robot
that grasps needs the model-to-camera transform. PCL's global pipeline (the ``3d_rec_framework``) gets it as heatdata
does here, in three steps:

1. **An initial pose** from the nearest library view: its camera (:func:`heatdata.views.render.camera_pose` at the
   view's azimuth, elevation and distance about the model's centre) gives the model's rotation in the segment's
   canonical frame (:attr:`heatdata.views.view.View.canonical_rotation`, eq. 2.8: the camera turned to face the
   segment, as the library views face their object). A support plane, when the frame has one, sets the model's
   +y axis along the plane's normal; the translation puts the centroid of the model's surface seen from the
   library camera on the segment's centroid.
2. **ICP**: open3d's point-to-plane ``registration_icp`` of the segment's points onto the model's surface samples
   (:class:`Surface`: points with normals, in the library file), at a coarse then a fine correspondence distance.
3. **Verification** (hypothesis verification after Aldoma et al. 2012): the pose is accepted when the posed surface
   explains the segment (a share of its points within a tolerance of the surface) and the part of the posed model
   the camera would see does not stand in front of the measured depth.

Poses are scored as the BOP benchmark scores them (:func:`pose_errors`): ADD-S, the mean distance from each posed
surface point to the nearest point of the true posed surface, within 10% of the object's diameter; the error of
the object's centre; the rotation error up to the turns about the model's up axis that leave its surface in place
(:func:`symmetry_turns`).
"""

from __future__ import annotations

import base64
import json
import logging
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from scipy.spatial import cKDTree
from scipy.spatial.distance import pdist

from heatdata.core.geometry import rotation_between, turn_about_up
from heatdata.errors import LibraryError
from heatdata.io.files import atomic, require_file
from heatdata.typing import StrPath
from heatdata.views.depth import nearest_readings, pixels_of

if TYPE_CHECKING:
    import open3d as o3d

log = logging.getLogger(__name__)

#: surface samples per object in a library file (9 bytes each, 12 as base64)
SURFACE_SAMPLES = 2000
#: points of a segment that ICP registers (a seeded subset of a larger segment)
ICP_POINTS = 800
#: library views of an object whose poses start ICP (its nearest ones to the query)
STARTS = 3
#: points of a segment whose distance to a posed surface verification measures (a seeded subset of a larger
#: segment): the share explained of 1,000 points has a standard error of 1 percentage point about 0.9
VERIFY_POINTS = 1000
#: ICP's correspondence distances, coarse then fine: this share of the object's diameter, then the tolerance
COARSE = 0.15
#: ICP's iterations at each distance
ICP_ITERATIONS = 30
#: the coarse stage: points of the segment and iterations of the quick ICP that ranks every start of every candidate,
#: and the surface samples it checks against the measured depth
COARSE_POINTS, COARSE_ITERATIONS, COARSE_SAMPLES = 200, 10, 300
#: the starts of an object refined and verified after the coarse stage, best first
FINE_STARTS = 2
#: the candidates posed in full after the coarse stage (those whose best start fits most)
FINE_CANDIDATES = 3
#: the smallest tolerance of a point on the surface (metres), to which the sensor's noise and half the samples' spacing
#: add
TOLERANCE = 0.005
#: the depth noise's standard deviation per squared metre of depth (the Kinect's, thesis 2.6.1)
NOISE_PER_M2 = 1.42e-3
#: share of the segment's points the posed surface must explain (within the tolerance) to accept a pose; this and the
#: two limits below were chosen on 40 of the scenes experiment's frames and 10 test views per object of the main job,
#: each object left out in turn (the pose page)
MIN_EXPLAINED = 0.9
#: largest share of the posed model's visible points that may stand in front of the measured depth
MAX_IN_FRONT = 0.15
#: largest share of the posed model's visible points where the frame measures nothing
MAX_UNSEEN = 0.15
#: largest share of the posed model below the support plane (an object sunk into the table to fit a bump of it)
MAX_BELOW = 0.05
#: the side of the pixel window whose nearest reading a posed point is compared with (verification)
NEIGHBOURHOOD = 5
#: turns about the up axis of the nearest library view's start that start ICP as well (degrees): a handle or a
#: lid's ridge seen from the other side looks alike, and an elongated loaf 40 deg off the nearest view's azimuth
#: falls into a wrong minimum from starts 90 deg apart (the scenes experiment)
TURNS = (45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0)
#: a start whose pose explains this share of the segment's points, with at most this share of the visible model in
#: front of the depth, ends the search for a better one
CLEAR_EXPLAINED, CLEAR_IN_FRONT = 0.95, 0.03
#: below this share of points within the tolerance ICP has not converged, and the pose stays the view's estimate
MIN_FITNESS = 0.3
#: the turns about the up axis tried when finding an object's symmetries (degrees)
TURN_STEP = 5.0
#: a turn is a symmetry when 95% of the turned samples lie within this many sample spacings of the surface...
SYMMETRY_SPACINGS = 1.0
#: ... and every one within this many (a cup's handle turned away is a few spacings off)
SYMMETRY_MAX_SPACINGS = 2.5


#: how a library file stores surface samples: points as float16 offsets from the centre (0.25 mm steps half a metre
#: out), unit normals as int8 (steps of 1/127); Parquet keeps its metadata twice (its own and Arrow's schema), so an
#: object costs about 4.7 times the raw 18 kB
POINTS_TYPE, NORMALS_TYPE, NORMAL_SCALE = "<f2", "i1", 127.0


def _encode(array: np.ndarray, dtype: str) -> str:
    return base64.b64encode(np.ascontiguousarray(array, dtype=dtype).tobytes()).decode("ascii")


def _decode(text: str, dtype: str, name: str) -> np.ndarray:
    values = np.frombuffer(base64.b64decode(text.encode("ascii"), validate=True), dtype=dtype)
    if len(values) % 3:
        raise LibraryError(f"{name}: surface samples are not (n, 3)")
    return values.reshape(-1, 3).astype(np.float64)


@dataclass(frozen=True)
class Surface:
    """An object's surface as a library file keeps it: samples with normals, in the model's frame.

    Attributes
    ----------
    points : (n, 3) float64
        Surface samples, metres, model frame (+y up), evenly spread (Poisson disk).
    normals : (n, 3) float64
        Their unit normals (the sign is the face's winding's, which a model does not always keep).
    center : (3,) float64
        The model's bounding-box centre: what the library's cameras looked at.
    diameter : float
        The largest distance between two samples, metres.
    spacing : float
        The samples' mean spacing, ``sqrt(area / n)``, metres.
    coloured : bool
        Whether the model had colour (:attr:`heatdata.io.models.Model.coloured`): a library compares a frame's colour
        only with the views of coloured models.
    """

    points: np.ndarray
    normals: np.ndarray
    center: np.ndarray
    diameter: float
    spacing: float
    coloured: bool = True
    _seen: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def seen_centroid(self, camera: np.ndarray) -> np.ndarray:
        """The centroid of the samples a camera sees (:func:`visible`; kept for the next query from the same library
        view).

        Parameters
        ----------
        camera : (3,) float
            The camera's position, model frame.

        Returns
        -------
        (3,) float64
        """
        key = tuple(np.round(camera, 9))
        if key not in self._seen:
            self._seen[key] = self.points[visible(self.points, np.asarray(camera))].mean(axis=0)
        return self._seen[key]

    def to_dict(self) -> dict:
        """As a library file's metadata keeps it.

        Returns
        -------
        dict
            ``points`` and ``normals`` (:data:`POINTS_TYPE` offsets from the centre and :data:`NORMALS_TYPE`, in
            base64), ``center``, ``diameter``, ``spacing``, ``coloured``.
        """
        return {
            "points": _encode(self.points - self.center, POINTS_TYPE),
            "normals": _encode(np.round(self.normals * NORMAL_SCALE), NORMALS_TYPE),
            "center": [float(c) for c in self.center],
            "diameter": float(self.diameter),
            "spacing": float(self.spacing),
            "coloured": bool(self.coloured),
        }

    @classmethod
    def from_dict(cls, data: dict, name: str = "surface") -> Surface:
        """Read :meth:`to_dict`'s form back.

        Parameters
        ----------
        data : dict
            :meth:`to_dict`'s.
        name : str
            Where it came from, for messages.

        Returns
        -------
        Surface

        Raises
        ------
        LibraryError
            Damaged samples.
        """
        try:
            center = np.asarray(data["center"], dtype=np.float64)
            points = _decode(data["points"], POINTS_TYPE, name) + center
            normals = _decode(data["normals"], NORMALS_TYPE, name) / NORMAL_SCALE
            normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
            diameter, spacing = float(data["diameter"]), float(data["spacing"])
            coloured = data.get("coloured", True)  # a file written before models without colour were told apart
            if not isinstance(coloured, bool):
                raise TypeError(f"coloured must be true or false, got {coloured!r}")
        except (KeyError, TypeError, ValueError) as exc:
            raise LibraryError(f"{name}: damaged surface samples ({type(exc).__name__}: {exc})") from None
        finite = np.all(np.isfinite(points)) and np.all(np.isfinite(normals)) and np.all(np.isfinite(center))
        if len(points) < 3 or normals.shape != points.shape or center.shape != (3,) or not finite:
            raise LibraryError(f"{name}: damaged surface samples ({len(points)} points, {len(normals)} normals)")
        if not (diameter > 0 and spacing > 0):
            raise LibraryError(f"{name}: damaged surface samples (diameter {diameter}, spacing {spacing})")
        return cls(points, normals, center, diameter, spacing, coloured)


def sample_surface(
    vertices: np.ndarray, faces: np.ndarray, count: int = SURFACE_SAMPLES, seed: int = 0, *, coloured: bool = True
) -> Surface:
    """Evenly spread samples of a mesh's surface with their normals (open3d's Poisson-disk sampling, seeded).

    Parameters
    ----------
    vertices : (v, 3) float
        The model's vertices, metres, its own frame (:func:`heatdata.load_model`).
    faces : (f, 3) int
        Its triangles.
    count : int
        Samples.
    seed : int
        open3d's random seed (the same seed gives the same samples).
    coloured : bool
        Whether the model has colour (:attr:`heatdata.io.models.Model.coloured`).

    Returns
    -------
    Surface
    """
    import open3d as o3d

    mesh = o3d.geometry.TriangleMesh(
        o3d.utility.Vector3dVector(np.array(vertices, dtype=np.float64)),  # a copy: open3d refuses read-only arrays
        o3d.utility.Vector3iVector(np.asarray(faces, dtype=np.int32)),
    )
    mesh.compute_triangle_normals()
    o3d.utility.random.seed(seed)
    cloud = mesh.sample_points_poisson_disk(count, init_factor=5, use_triangle_normal=True)
    points, normals = np.asarray(cloud.points), np.asarray(cloud.normals)
    lo, hi = np.asarray(vertices).min(axis=0), np.asarray(vertices).max(axis=0)
    surface = Surface(
        points,
        normals,
        (lo + hi) / 2.0,
        float(pdist(points).max()),
        float(np.sqrt(mesh.get_surface_area() / len(points))),
        coloured,
    )
    log.info(
        "%d surface samples, %.1f mm apart, diameter %.1f cm",
        len(points),
        surface.spacing * 1e3,
        surface.diameter * 1e2,
    )
    return surface


def write_surface(surface: Surface, path: StrPath) -> None:
    """Write an object's surface samples (JSON of :meth:`Surface.to_dict`; written whole, then renamed).

    Parameters
    ----------
    surface : Surface
    path : str or Path
    """
    with atomic(path) as temporary:
        temporary.write_text(json.dumps(surface.to_dict()))


def read_surface(path: StrPath) -> Surface:
    """Read :func:`write_surface`'s file.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    Surface

    Raises
    ------
    LibraryError
        Not surface samples, or damaged ones.
    """
    try:
        data = json.loads(require_file(path, "surface samples", LibraryError).read_text())
    except json.JSONDecodeError as exc:
        raise LibraryError(f"{path}: not surface samples ({exc})") from None
    if not isinstance(data, dict):
        raise LibraryError(f"{path}: not surface samples")
    return Surface.from_dict(data, str(path))


@dataclass(frozen=True)
class Pose:
    """A hypothesis's pose and how well it explains the segment.

    Attributes
    ----------
    object : str
        The library object posed.
    matrix : (4, 4) float64
        Model-to-camera transform: the model's frame (metres, +y up) to the camera's (x right, y down, z forward).
    fitness : float
        ICP's fitness: the share of the segment's points with a surface point within the tolerance.
    rmse : float
        ICP's inlier RMSE, metres.
    explained : float
        The share of the segment's points within the tolerance of the posed surface (verification).
    in_front : float
        The share of the posed model's visible points that stand in front of the measured depth (verification).
    unseen : float
        The share of the posed model's visible points where the frame measures nothing (verification).
    converged : bool
        Whether ICP converged; when not, ``matrix`` is the library view's estimate.
    accepted : bool
        Whether verification accepts it.
    tolerance : float
        The distance a point counts as on the surface within, metres.
    notes : list of str
        What a user should know of it (ICP did not converge).
    below : float
        The share of the posed model below the support plane (verification; 0 without a plane).
    """

    object: str
    matrix: np.ndarray
    fitness: float
    rmse: float
    explained: float
    in_front: float
    unseen: float
    converged: bool
    accepted: bool
    tolerance: float
    notes: list[str] = field(default_factory=list)
    below: float = 0.0

    def to_dict(self) -> dict:
        """The pose as plain types.

        Returns
        -------
        dict
            ``heatdata recognize --json``'s ``pose``: ``object, matrix`` (4 x 4 rows), ``fitness, rmse, explained,
            in_front, unseen, below, converged, accepted, tolerance, notes``.
        """
        return {
            "object": self.object,
            "matrix": [[float(x) for x in row] for row in self.matrix],
            "fitness": float(self.fitness),
            "rmse": float(self.rmse),
            "explained": float(self.explained),
            "in_front": float(self.in_front),
            "unseen": float(self.unseen),
            "below": float(self.below),
            "converged": bool(self.converged),
            "accepted": bool(self.accepted),
            "tolerance": float(self.tolerance),
            "notes": list(self.notes),
        }


def tolerance(surface: Surface, depth: float) -> float:
    """The distance within which a point at ``depth`` metres counts as on ``surface``: :data:`TOLERANCE`, three
    standard deviations of the sensor's noise there and half the samples' spacing (about the farthest a point of the
    surface lies from its nearest sample).

    Parameters
    ----------
    surface : Surface
    depth : float
        Metres.

    Returns
    -------
    float
        Metres.
    """
    return TOLERANCE + 3.0 * NOISE_PER_M2 * depth**2 + 0.5 * surface.spacing


def library_camera(surface: Surface, azimuth: float, elevation: float, distance: float) -> np.ndarray:
    """The model-to-camera transform of a library view, as :func:`heatdata.views.render.render_view` placed it.

    Parameters
    ----------
    surface : Surface
        The object's (its centre is what the camera looked at).
    azimuth, elevation : float
        Degrees.
    distance : float
        Metres.

    Returns
    -------
    (4, 4) float64
    """
    from heatdata.views.render import camera_pose

    return np.linalg.inv(camera_pose(surface.center, azimuth, elevation, distance))


def visible(points: np.ndarray, camera: np.ndarray) -> np.ndarray:
    """Indices of ``points`` a camera at ``camera`` (a position in their frame) sees: open3d's hidden point removal.

    Parameters
    ----------
    points : (n, 3) float
    camera : (3,) float

    Returns
    -------
    (k,) int
    """
    cloud = _cloud(points)
    radius = 100.0 * float(np.linalg.norm(points - camera, axis=1).max())
    _, indices = cloud.hidden_point_removal(np.asarray(camera, dtype=np.float64), radius)
    return np.asarray(indices, dtype=np.int64)


def initial_pose(
    points: np.ndarray,
    canonical: np.ndarray,
    surface: Surface,
    view: tuple[float, float, float],
    up: np.ndarray | None = None,
) -> np.ndarray:
    """A segment's model-to-camera pose as the library view ``view`` sees its object (step 1 of the module).

    Parameters
    ----------
    points : (n, 3) float
        The segment's points, camera frame.
    canonical : (3, 3) float
        The segment's canonical rotation (camera frame to the frame facing it).
    surface : Surface
        The object's.
    view : (azimuth, elevation, distance)
        The library view's angle (degrees) and camera distance (metres).
    up : (3,) float, optional
        The support plane's normal towards the camera (the model's +y), camera frame.

    Returns
    -------
    (4, 4) float64
    """
    lib = library_camera(surface, *view)
    rotation = lib[:3, :3]
    if up is not None:
        facing = canonical @ np.asarray(up, dtype=np.float64)
        rotation = rotation_between(rotation[:, 1], facing) @ rotation
    rotation = canonical.T @ rotation
    camera = -lib[:3, :3].T @ lib[:3, 3]  # the library camera's position, model frame
    pose = np.eye(4)
    pose[:3, :3] = rotation
    pose[:3, 3] = points.mean(axis=0) - rotation @ surface.seen_centroid(camera)
    return pose


def _cloud(points: np.ndarray, normals: np.ndarray | None = None) -> o3d.geometry.PointCloud:
    """An open3d cloud of copies of ``points`` (and ``normals``): open3d refuses a read-only array (one read from
    Parquet)."""
    import open3d as o3d

    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(np.array(points, dtype=np.float64)))
    if normals is not None:
        cloud.normals = o3d.utility.Vector3dVector(np.array(normals, dtype=np.float64))
    return cloud


def refine(points: np.ndarray, surface: Surface, initial: np.ndarray, tol: float) -> tuple[np.ndarray, float, float]:
    """ICP of the segment's points onto the surface from ``initial`` (open3d's ``registration_icp``): point-to-point
    at :data:`COARSE` of the diameter, then point-to-plane at ``tol``.

    Point-to-plane alone runs away along a flat segment (a desk calendar seen face-on: nothing holds it in the
    plane), to kilometres in the scenes experiment; the point-to-point stage first brings it home, and the
    point-to-plane stage is kept only when it stays within ``tol`` of it (the pose page measures both).

    Parameters
    ----------
    points : (n, 3) float
        The segment's points, camera frame (at most :data:`ICP_POINTS`).
    surface : Surface
    initial : (4, 4) float
        Model-to-camera start.
    tol : float
        The fine correspondence distance, metres.

    Returns
    -------
    matrix : (4, 4) float64
        Model-to-camera.
    fitness, rmse : float
        ICP's at ``tol``.
    """
    import open3d as o3d

    registration = o3d.pipelines.registration
    source, target = _cloud(points), _cloud(surface.points, surface.normals)
    criteria = registration.ICPConvergenceCriteria(max_iteration=ICP_ITERATIONS)
    start = _point_to_point(source, target, surface, initial, tol, ICP_ITERATIONS)
    fine = registration.registration_icp(
        source, target, tol, start, registration.TransformationEstimationPointToPlane(), criteria
    )
    change = np.asarray(fine.transformation) - start  # how far the point-to-plane stage moved each point
    moved = np.linalg.norm(points @ change[:3, :3].T + change[:3, 3], axis=1)
    if np.all(np.isfinite(moved)) and moved.max() <= tol and fine.fitness > 0:
        return np.linalg.inv(np.asarray(fine.transformation)), float(fine.fitness), float(fine.inlier_rmse)
    kept = registration.evaluate_registration(source, target, tol, start)
    return np.linalg.inv(start), float(kept.fitness), float(kept.inlier_rmse)


def depth_image(points: np.ndarray, intrinsics: dict) -> np.ndarray:
    """The z-buffer of camera-frame points on the camera's pixels (NaN where none lands): a view's depth image.

    Parameters
    ----------
    points : (n, 3) float
    intrinsics : dict
        ``fx, fy, cx, cy, width, height``.

    Returns
    -------
    (height, width) float64
    """
    k = intrinsics
    depth = np.full((int(k["height"]), int(k["width"])), np.inf)
    pixel, inside = pixels_of(points, k)
    np.minimum.at(depth, (pixel[inside, 1], pixel[inside, 0]), points[inside, 2])
    depth[~np.isfinite(depth)] = np.nan
    return depth


def verify(
    matrix: np.ndarray,
    points: np.ndarray,
    surface: Surface,
    depth: np.ndarray,
    intrinsics: dict,
    tol: float,
    plane: np.ndarray | None = None,
) -> tuple[float, float, float, float]:
    """How well a pose explains a segment (step 3 of the module).

    Parameters
    ----------
    matrix : (4, 4) float
        Model-to-camera.
    points : (n, 3) float
        The segment's points, camera frame.
    surface : Surface
    depth : (h, w) float
        The frame's measured depth (NaN where none).
    intrinsics : dict
    tol : float
        Metres.
    plane : (4,) float, optional
        The support plane ``n . p + d = 0``, ``n`` the unit normal towards the camera (up).

    Returns
    -------
    explained : float
        The share of ``points`` within ``tol`` of the posed surface (of a seeded :data:`VERIFY_POINTS` of them).
    in_front : float
        The share of the posed surface's visible points, where the frame has a depth, that lie more than ``tol``
        in front of it.
    unseen : float
        The share of the posed surface's visible points inside the image where the frame has no depth (the model
        larger than what was measured: a larger twin of the object seen).
    below : float
        The share of the posed surface more than ``tol`` below the support plane (an object sunk into the table to
        fit a bump of it); 0 without a plane.
    """
    posed = surface.points @ matrix[:3, :3].T + matrix[:3, 3]
    gaps, _ = cKDTree(posed).query(_subset(points, VERIFY_POINTS), distance_upper_bound=tol)
    explained = float(np.mean(np.isfinite(gaps)))
    below = 0.0 if plane is None else float(np.mean(posed @ np.asarray(plane[:3], float) + float(plane[3]) < -tol))
    seen = posed[visible(posed, np.zeros(3))]
    pixel, inside = pixels_of(seen, intrinsics)
    if not inside.any():
        return explained, 0.0, 1.0, below
    pixel = pixel[inside]
    half = NEIGHBOURHOOD // 2  # filter only the crop round the pixels
    u0, v0 = np.maximum(pixel.min(axis=0) - half, 0)
    u1, v1 = pixel.max(axis=0) + half + 1
    measured = nearest_readings(depth[v0:v1, u0:u1], NEIGHBOURHOOD)[pixel[:, 1] - v0, pixel[:, 0] - u0]
    read = np.isfinite(measured)
    in_front = float(np.mean(seen[inside][read, 2] < measured[read] - tol)) if read.any() else 0.0
    return explained, in_front, float(1.0 - read.mean()), below


def start_poses(
    points: np.ndarray,
    canonical: np.ndarray,
    surface: Surface,
    views: list[tuple[float, float, float]],
    up: np.ndarray | None = None,
) -> list[np.ndarray]:
    """ICP's starts for one object: its nearest library views (at most :data:`STARTS`) and the nearest one turned
    by each of :data:`TURNS` about the up axis (:func:`initial_pose`).

    Parameters
    ----------
    points : (n, 3) float
        The segment's points, camera frame.
    canonical : (3, 3) float
    surface : Surface
    views : list of (azimuth, elevation, distance)
        Its library views nearest the segment, nearest first.
    up : (3,) float, optional

    Returns
    -------
    list of (4, 4) float64
        Model-to-camera starts, the nearest view's first.
    """
    starts = [initial_pose(points, canonical, surface, view, up) for view in views[:STARTS]]
    nearest = starts[0]
    for angle in TURNS:
        turned = nearest.copy()
        turned[:3, :3] = nearest[:3, :3] @ turn_about_up(angle)
        turned[:3, 3] += nearest[:3, :3] @ (surface.center - turn_about_up(angle) @ surface.center)
        starts.append(turned)
    return starts


def coarse_fits(
    points: np.ndarray, surface: Surface, starts: list[np.ndarray], tol: float, measured: np.ndarray, intrinsics: dict
) -> list[tuple[float, np.ndarray]]:
    """The coarse stage: a quick point-to-point ICP of :data:`COARSE_POINTS` of the segment from each start (at
    :data:`COARSE` of the diameter, :data:`COARSE_ITERATIONS` iterations), scored as verification scores a pose but
    cheaply: the share of those points within ``2 tol`` of the surface, less the share of :data:`COARSE_SAMPLES`
    surface samples that stand in front of the measured depth (every sample, seen or not: one the camera cannot see
    lies behind one it sees, so it is in front only where that one is too).

    Parameters
    ----------
    points : (n, 3) float
        The segment's points, camera frame.
    surface : Surface
    starts : list of (4, 4) float
    tol : float
        The fine tolerance, metres.
    measured : (h, w) float
        The frame's nearest reading about each pixel (:func:`heatdata.views.depth.nearest_readings` of its depth,
        :data:`NEIGHBOURHOOD`), NaN where none.
    intrinsics : dict

    Returns
    -------
    list of (score, (4, 4) float64)
        Each start's score and pose after the quick ICP, best first (equals in the starts' order).
    """
    subset = _subset(points, COARSE_POINTS)
    source, target = _cloud(subset), _cloud(surface.points)
    tree = cKDTree(surface.points)  # one tree for every start's fitness (open3d's evaluation builds one a call)
    samples = _subset(surface.points, COARSE_SAMPLES)
    fits = []
    for start in starts:
        matrix = _point_to_point(source, target, surface, start, tol, COARSE_ITERATIONS)
        gaps, _ = tree.query(subset @ matrix[:3, :3].T + matrix[:3, 3], distance_upper_bound=2 * tol)
        pose = np.linalg.inv(matrix)
        in_front = _in_front(samples @ pose[:3, :3].T + pose[:3, 3], measured, intrinsics, tol)
        fits.append((float(np.mean(np.isfinite(gaps))) - in_front, pose))
    order = sorted(range(len(fits)), key=lambda i: -fits[i][0])
    return [fits[i] for i in order]


def _point_to_point(
    source: o3d.geometry.PointCloud,
    target: o3d.geometry.PointCloud,
    surface: Surface,
    start: np.ndarray,
    tol: float,
    iterations: int,
) -> np.ndarray:
    """(4, 4): open3d's point-to-point ICP of the segment's points (``source``) onto the surface from the model-to-
    camera ``start``, at :data:`COARSE` of the diameter (at least ``2 tol``): the camera-to-model transform."""
    import open3d as o3d

    registration = o3d.pipelines.registration
    found = registration.registration_icp(
        source,
        target,
        max(COARSE * surface.diameter, 2 * tol),
        np.linalg.inv(start),
        registration.TransformationEstimationPointToPoint(),
        registration.ICPConvergenceCriteria(max_iteration=iterations),
    )
    return np.asarray(found.transformation)


def _in_front(posed: np.ndarray, measured: np.ndarray, intrinsics: dict, tol: float) -> float:
    """The share of ``posed`` points, of those on a pixel with a reading, more than ``tol`` in front of it."""
    pixel, inside = pixels_of(posed, intrinsics)
    reading = measured[pixel[inside, 1], pixel[inside, 0]]
    read = np.isfinite(reading)
    return float(np.mean(posed[inside][read, 2] < reading[read] - tol)) if read.any() else 0.0


def _subset(points: np.ndarray, count: int) -> np.ndarray:
    """At most ``count`` of ``points``, a seeded choice (the same segment, the same subset)."""
    if len(points) <= count:
        return points
    return points[np.random.default_rng(0).choice(len(points), count, replace=False)]


def estimate_pose(
    obj: str,
    points: np.ndarray,
    canonical: np.ndarray,
    surface: Surface,
    views: list[tuple[float, float, float]],
    depth: np.ndarray,
    intrinsics: dict,
    plane: np.ndarray | None = None,
    *,
    fits: list[tuple[float, np.ndarray]] | None = None,
) -> Pose:
    """The best pose of ``obj`` for a segment from its nearest library views, and whether it is accepted.

    Coarse to fine: every start (:func:`start_poses`) gets a quick ICP (:func:`coarse_fits`); the
    :data:`FINE_STARTS` that fit best are refined (:func:`refine`) and verified (:func:`verify`), and the one that
    explains most, less what it contradicts, is the pose.

    Parameters
    ----------
    obj : str
        The object.
    points : (n, 3) float
        The segment's points, camera frame.
    canonical : (3, 3) float
        The segment's canonical rotation.
    surface : Surface
        The object's.
    views : list of (azimuth, elevation, distance)
        Its library views nearest the segment, nearest first: each starts ICP (at most :data:`STARTS`).
    depth : (h, w) float
        The frame's measured depth, for verification.
    intrinsics : dict
    plane : (4,) float, optional
        The support plane ``n . p + d = 0``, ``n`` the unit normal towards the camera: the model's +y, and the
        surface it may not sink below.
    fits : list of (fitness, (4, 4) float), optional
        The coarse stage's, when the caller ran it already (:func:`pose_candidates`).

    Returns
    -------
    Pose
        The refined start that explains most; when none converges, the nearest view's start (noted).
    """
    tol = tolerance(surface, float(np.median(points[:, 2])))
    subset = _subset(points, ICP_POINTS)
    up = None if plane is None else np.asarray(plane[:3], float)
    if fits is None:
        measured = nearest_readings(depth, NEIGHBOURHOOD)
        fits = coarse_fits(
            points, surface, start_poses(subset, canonical, surface, views, up), tol, measured, intrinsics
        )
    tried: list[tuple] = []
    for _, start in fits[:FINE_STARTS]:
        matrix, fitness, rmse = refine(subset, surface, start, tol)
        if fitness >= MIN_FITNESS and np.all(np.isfinite(matrix)):
            explained, in_front, unseen, below = verify(matrix, points, surface, depth, intrinsics, tol, plane)
            score = explained - in_front - unseen - below
            tried.append((score, fitness, rmse, explained, in_front, unseen, below, matrix))
            if explained >= CLEAR_EXPLAINED and in_front + unseen + below <= CLEAR_IN_FRONT:
                break  # no other start can do much better
    notes = []
    if tried:
        _, fitness, rmse, explained, in_front, unseen, below, matrix = max(tried, key=lambda t: t[0])
    else:
        matrix, fitness, rmse = initial_pose(subset, canonical, surface, views[0], up), 0.0, float("nan")
        explained, in_front, unseen, below = verify(matrix, points, surface, depth, intrinsics, tol, plane)
        notes.append(
            f"ICP did not converge (under {MIN_FITNESS:.0%} of the points within {tol * 100:.1f} cm of the {obj} "
            "from every start): the pose is the nearest library view's estimate"
        )
    accepted = explained >= MIN_EXPLAINED and in_front <= MAX_IN_FRONT and unseen <= MAX_UNSEEN and below <= MAX_BELOW
    return Pose(obj, matrix, fitness, rmse, explained, in_front, unseen, bool(tried), accepted, tol, notes, below)


def pose_candidates(
    candidates: list[tuple[str, Surface, list[tuple[float, float, float]]]],
    points: np.ndarray,
    canonical: np.ndarray,
    depth: np.ndarray,
    intrinsics: dict,
    plane: np.ndarray | None = None,
) -> Pose | None:
    """Hypothesis verification over several objects: which of ``candidates`` a segment is, by its pose.

    The descriptor's nearest candidate is posed in full first (:func:`estimate_pose`); a clear fit (:func:`_clear`)
    is the answer. Otherwise every other candidate's starts get the coarse stage (:func:`coarse_fits`), the
    :data:`FINE_CANDIDATES` - 1 whose best start fits most are posed in full too, and of the accepted poses the one
    that explains most, less what it contradicts, is the answer. A descriptor's nearest object is not always the one
    seen (a real can lies nearer a library's box views than its own), so the check looks past it, as PCL's global
    pipeline verifies each of its nearest hypotheses.

    Parameters
    ----------
    candidates : list of (object, Surface, views)
        The objects to try, the descriptor's nearest first, each with its library views nearest the segment.
    points : (n, 3) float
        The segment's points, camera frame.
    canonical : (3, 3) float
    depth : (h, w) float
    intrinsics : dict
    plane : (4,) float, optional
        The support plane (:func:`estimate_pose`).

    Returns
    -------
    Pose or None
        The best accepted pose; else the descriptor's nearest candidate's (rejected); None without candidates.
    """
    subset = _subset(points, ICP_POINTS)
    depth_median = float(np.median(points[:, 2]))
    measured = nearest_readings(depth, NEIGHBOURHOOD)
    up = None if plane is None else np.asarray(plane[:3], float)
    ranked = []
    for order, (obj, surface, views) in enumerate(candidates):
        tol = tolerance(surface, depth_median)
        fits = coarse_fits(
            points, surface, start_poses(subset, canonical, surface, views, up), tol, measured, intrinsics
        )
        if order == 0:  # the descriptor's nearest, posed in full first: a clear fit needs no other candidate
            nearest = estimate_pose(obj, points, canonical, surface, views, depth, intrinsics, plane, fits=fits)
            if nearest.accepted and _clear(nearest):
                return nearest
        ranked.append((-fits[0][0], order, obj, surface, views, fits))
    if not ranked:
        return None
    posed = [(0, nearest)]
    ranked.sort(key=lambda r: r[:2])
    for _, order, obj, surface, views, fits in [r for r in ranked if r[1] != 0][: FINE_CANDIDATES - 1]:
        posed.append(
            (order, estimate_pose(obj, points, canonical, surface, views, depth, intrinsics, plane, fits=fits))
        )
    accepted = [(_score(p), -order, p) for order, p in posed if p.accepted]
    return max(accepted, key=lambda a: a[:2])[2] if accepted else nearest


def _score(pose: Pose) -> float:
    """What a pose explains, less what it contradicts."""
    return pose.explained - pose.in_front - pose.unseen - pose.below


def _clear(pose: Pose) -> bool:
    """A pose no other start or object can do much better than (:data:`CLEAR_EXPLAINED`, :data:`CLEAR_IN_FRONT`)."""
    return pose.explained >= CLEAR_EXPLAINED and pose.in_front + pose.unseen + pose.below <= CLEAR_IN_FRONT


def symmetry_turns(surface: Surface) -> np.ndarray:
    """The turns about the model's up axis through its centre that leave its surface in place.

    A turn (tried every :data:`TURN_STEP` degrees) keeps the surface in place when 95% of the turned samples lie
    within :data:`SYMMETRY_SPACINGS` sample spacings of the nearest sample and all within
    :data:`SYMMETRY_MAX_SPACINGS`. A small turn always does, at the samples' spacing: unless every turn does (a
    round object), each run of neighbouring turns counts once, as its turn nearest to fitting. On the embedded
    objects, the round ones turn into themselves at every step, the carton and the desk calendar at a half turn,
    and a cup's handle (4 spacings off when turned) keeps its cup from any symmetry.

    Returns
    -------
    (k,) float
        Degrees in [0, 360), 0 always among them.
    """
    tree = cKDTree(surface.points)
    centred = surface.points - surface.center
    angles = np.arange(0.0, 360.0, TURN_STEP)
    fits, gaps_mean = [], []
    for angle in angles:
        gaps = tree.query(centred @ turn_about_up(angle).T + surface.center)[0] / surface.spacing
        fits.append(bool(np.quantile(gaps, 0.95) <= SYMMETRY_SPACINGS and gaps.max() <= SYMMETRY_MAX_SPACINGS))
        gaps_mean.append(float(gaps.mean()))
    fits[0] = True
    if all(fits):
        return angles
    turns = []
    first = fits.index(False)  # runs of neighbouring turns, walked round from a turn that does not fit
    run: list[int] = []
    for step in range(1, len(angles) + 1):
        index = (first + step) % len(angles)
        if fits[index]:
            run.append(index)
        elif run:
            turns.append(angles[0] if 0 in run else angles[min(run, key=lambda i: gaps_mean[i])])
            run = []
    return np.sort(np.asarray(turns, dtype=np.float64))


def pose_errors(estimate: np.ndarray, truth: np.ndarray, surface: Surface, turns: np.ndarray) -> dict:
    """How far an estimated pose is from the true one, as BOP scores it.

    Parameters
    ----------
    estimate, truth : (4, 4) float
        Model-to-camera transforms.
    surface : Surface
        The object's.
    turns : (k,) float
        Its symmetries (:func:`symmetry_turns`).

    Returns
    -------
    dict
        ``add_s`` (metres: mean distance from each estimated surface point to the nearest true one),
        ``add_s_ok`` (within 10% of the diameter), ``translation`` (metres, of the object's centre) and
        ``rotation`` (degrees, the smallest over the symmetries).
    """
    placed = surface.points @ estimate[:3, :3].T + estimate[:3, 3]
    true = surface.points @ truth[:3, :3].T + truth[:3, 3]
    add_s = float(cKDTree(true).query(placed)[0].mean())
    centre = surface.center
    translation = float(
        np.linalg.norm(estimate[:3, :3] @ centre + estimate[:3, 3] - truth[:3, :3] @ centre - truth[:3, 3])
    )
    angles = []
    for turn in turns:
        relative = estimate[:3, :3].T @ truth[:3, :3] @ turn_about_up(float(turn))
        angles.append(np.degrees(np.arccos(np.clip((np.trace(relative) - 1.0) / 2.0, -1.0, 1.0))))
    return {
        "add_s": add_s,
        "add_s_ok": bool(add_s <= 0.1 * surface.diameter),
        "translation": translation,
        "rotation": float(min(angles)),
    }
