"""A virtual Kinect: partial views of a model, and frames of whole scenes, by ray casting (thesis 2.1, 2.6.1, 3.1).

:func:`render_view`: the camera sits on a sphere around the model's bounding-box centre at a view angle
(azimuth about the model's +y axis, elevation above its xz-plane) and looks at the centre with the model's +y up
in the image. Rays of a 640x480 pinhole camera (f = 580 px) are cast with open3d's CPU ``RaycastingScene``; only
pixels inside the projected bounding box are cast. The organized depth grid becomes a triangle mesh of the visible
surface by :func:`heatdata.views.depth.grid_view`, as a captured depth image is: neighbouring pixels are joined
unless their depths differ by more than ``max_depth_jump`` times the depth.

:func:`render_scene`: several placed models (objects, a table, a wall) seen by a camera anywhere, as a whole
depth and colour frame with the ground truth of which model each pixel sees.

Both go through a :class:`heatdata.views.sensor.SensorProfile`: by default the depth noise of 2.6.1,
z = z0 + z0^2 eps, eps ~ N(0, tau^2), tau = 1.42e-3 1/m; the ``kinect`` profile adds the projector's shadows,
disparity quantization, flying pixels and no depth on dark surfaces.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import open3d as o3d

from heatdata.core.geometry import rotation_between
from heatdata.errors import RenderError
from heatdata.io.models import LARGE_MODEL, Model
from heatdata.views.depth import MAX_DEPTH_JUMP, grid_view
from heatdata.views.sensor import KINECT_TAU, SensorProfile
from heatdata.views.view import KINECT_INTRINSICS, View, check_intrinsics

log = logging.getLogger(__name__)


def camera_pose(center: np.ndarray, azimuth: float, elevation: float, distance: float) -> np.ndarray:
    """Camera-to-model transform for a camera looking at ``center``.

    Returns
    -------
    (4, 4) float64
        Columns 0-2 are the camera's x (right), y (down), z (forward) axes in the model
        frame; column 3 is the camera position.

    Parameters
    ----------
    center : (3,) float
        The point the camera looks at, model frame.
    azimuth, elevation : float
        Degrees: azimuth about the model's up (y) axis, elevation above its x-z plane.
    distance : float
        Camera to ``center``, metres.
    """
    if not np.isfinite(azimuth):
        raise RenderError(f"azimuth must be a finite number of degrees, got {azimuth}")
    if not -89.0 <= elevation <= 89.0:
        raise RenderError(f"elevation {elevation} deg is outside [-89, 89] (the up direction is undefined)")
    if not (np.isfinite(distance) and distance > 0):
        raise RenderError(f"camera distance must be a positive number of metres, got {distance}")
    az, el = np.radians(azimuth), np.radians(elevation)
    position = center + distance * np.array([np.cos(el) * np.sin(az), np.sin(el), np.cos(el) * np.cos(az)])
    forward = center - position
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2], pose[:3, 3] = right, down, forward, position
    return pose


#: the share of the image's shorter side that a model's bounding sphere spans at the camera distance ``"fit"``
FIT_SHARE = 0.6


def camera_distance(model: Model, distance: float | str, intrinsics: dict | None = None) -> float:
    """The camera's distance from ``model``'s bounding-box centre: ``distance`` metres, or, for ``"fit"``, the
    distance at which the model's bounding sphere spans :data:`FIT_SHARE` of the image's shorter side.

    ``"fit"`` views a catalogue of 2 cm to 20 m models alike (Sweet Home 3D's): at a fixed distance a small one
    leaves too few pixels to describe and the camera stands inside a large one. A sphere of radius r seen from d
    spans the angle 2 asin(r / d) (``intrinsics``: the camera's, default the Kinect's 640x480).

    Parameters
    ----------
    model : Model
    distance : float or "fit"
    intrinsics : dict, optional

    Returns
    -------
    float
        Metres, larger than the bounding sphere's radius.

    Raises
    ------
    RenderError
        ``distance`` is neither a positive number nor ``"fit"``.
    """
    if distance == "fit":
        k = check_intrinsics(intrinsics) if intrinsics is not None else KINECT_INTRINSICS
        half_angle = np.arctan(FIT_SHARE * min(k["width"] / k["fx"], k["height"] / k["fy"]) / 2.0)
        return float(0.5 * np.linalg.norm(model.extents) / np.sin(half_angle))
    if isinstance(distance, str) or not float(distance) > 0:
        raise RenderError(f"camera distance must be a positive number of metres or 'fit', got {distance!r}")
    return float(distance)


def _scene_of(model: Model) -> o3d.t.geometry.RaycastingScene:
    """The model's ray-casting scene, built once and kept on the model."""
    scene = model.__dict__.get("_raycasting_scene")
    if scene is None:
        scene = o3d.t.geometry.RaycastingScene()
        scene.add_triangles(
            o3d.core.Tensor(model.vertices.astype(np.float32)), o3d.core.Tensor(model.faces.astype(np.uint32))
        )
        model.__dict__["_raycasting_scene"] = scene
    return scene


def _scale_hint(model: Model) -> str:
    """A hint when the model's size suggests its file is not in metres."""
    size = float(model.extents.max())
    if size > LARGE_MODEL:
        return f" (it is {size:.0f} m across: if its file is in millimetres, give --scale 0.001 or its real --size)"
    if size < 0.01:
        return f" (it is {size * 1000:.2g} mm across: give its real --size, or a --scale to metres)"
    return ""


def _hit_colors(model: Model, face: np.ndarray, bary: np.ndarray) -> np.ndarray:
    """(k, 3) RGB at hits on ``face`` with barycentric weights (w1, w2) of corners 1, 2."""
    w = np.column_stack([1.0 - bary[:, 0] - bary[:, 1], bary[:, 0], bary[:, 1]]).astype(np.float32)
    colors = np.einsum("kc,kcd->kd", w, model.corner_colors[face])
    tex = model.face_texture[face]
    for t in np.unique(tex[tex >= 0]):
        sel = tex == t
        image = model.textures[t]
        uv = np.einsum("kc,kcd->kd", w[sel], model.corner_uv[face[sel]]) % 1.0
        h, wd = image.shape[:2]
        cols = np.minimum((uv[:, 0] * wd).astype(int), wd - 1)
        rows = np.minimum(((1.0 - uv[:, 1]) * h).astype(int), h - 1)
        colors[sel] = image[rows, cols]
    return np.clip(colors, 0.0, 1.0).astype(np.float64)


def _turn(image_offset: tuple[float, float], k: dict) -> np.ndarray:
    """(3, 3): the rotation of camera coordinates that moves the optical axis's point to ``image_offset`` pixels."""
    du, dv = (float(x) for x in image_offset)
    if not (np.isfinite(du) and np.isfinite(dv)):
        raise RenderError(f"image_offset must be finite pixels, got {image_offset}")
    return rotation_between(np.array([0.0, 0.0, 1.0]), np.array([du / k["fx"], dv / k["fy"], 1.0]))


def _projector_shadow(
    scene: o3d.t.geometry.RaycastingScene, pose: np.ndarray, points: np.ndarray, baseline: float
) -> np.ndarray:
    """(k,) bool: which of the world ``points`` (k, 3) the projector, ``baseline`` metres along the camera's +x,
    does not light (something lies between them)."""
    projector = pose[:3, 3] + baseline * pose[:3, 0]
    rays = np.hstack([np.broadcast_to(projector, points.shape), points - projector]).astype(np.float32)
    hit = scene.cast_rays(o3d.core.Tensor(rays))["t_hit"].numpy()
    return hit < 1.0 - 2e-3  # the ray meets a surface before the point (2 mm at 1 m)


def _cast(
    scene: o3d.t.geometry.RaycastingScene, pose: np.ndarray, k: dict, window: tuple[int, int, int, int]
) -> tuple[np.ndarray, np.ndarray, dict]:
    """Rays of the pixels ``window = (u0, u1, v0, v1)`` (inclusive) from a camera at ``pose`` (camera to scene).

    Returns the (h, w, 3) camera-frame ray directions with unit z, the (h, w) z-depth (NaN: no hit) and
    open3d's answer (``geometry_ids``, ``primitive_ids``, ``primitive_uvs``).
    """
    u0, u1, v0, v1 = window
    cols, rows = np.meshgrid(np.arange(u0, u1 + 1), np.arange(v0, v1 + 1))
    directions = np.stack([(cols - k["cx"]) / k["fx"], (rows - k["cy"]) / k["fy"], np.ones(cols.shape)], axis=-1)
    world_dirs = directions.reshape(-1, 3) @ pose[:3, :3].T  # unit z component in the camera frame
    rays = np.hstack([np.broadcast_to(pose[:3, 3], world_dirs.shape), world_dirs]).astype(np.float32)
    hits = {name: value.numpy() for name, value in scene.cast_rays(o3d.core.Tensor(rays)).items()}
    depth = hits["t_hit"].astype(np.float64).reshape(cols.shape)
    depth[~np.isfinite(depth)] = np.nan
    return directions, depth, hits


def _sensed(
    scene: o3d.t.geometry.RaycastingScene,
    pose: np.ndarray,
    directions: np.ndarray,
    depth: np.ndarray,
    colors: np.ndarray,
    sensor: SensorProfile,
    fx: float,
    seed: int | None,
) -> np.ndarray:
    """The true ``depth`` as ``sensor`` measures it: its shadows cast in ``scene``, then
    :meth:`SensorProfile.measure`."""
    depth = depth.copy()
    if sensor.shadows:
        valid = np.isfinite(depth)
        points = (directions[valid] * depth[valid, None]) @ pose[:3, :3].T + pose[:3, 3]
        shadowed = np.zeros(depth.shape, bool)
        shadowed[valid] = _projector_shadow(scene, pose, points, sensor.baseline)
        depth[shadowed] = np.nan
    return sensor.measure(depth, colors, fx, np.random.default_rng(seed))


def render_view(
    model: Model,
    azimuth: float = 0.0,
    elevation: float = 30.0,
    distance: float = 1.0,
    *,
    noise: bool = True,
    seed: int | None = 0,
    tau: float = KINECT_TAU,
    sensor: str | SensorProfile | None = None,
    intrinsics: dict | None = None,
    image_offset: tuple[float, float] = (0.0, 0.0),
    max_depth_jump: float = MAX_DEPTH_JUMP,
    components: str = "largest",
    view_id: str | None = None,
) -> View:
    """Render the partial view of ``model`` seen from a view angle.

    Parameters
    ----------
    model : Model
    azimuth, elevation : float
        View angle in degrees (azimuth about +y, from +z towards +x; elevation above xz).
    distance : float
        Camera distance from the model's bounding-box centre, metres.
    noise : bool
        Add Kinect depth noise (2.6.1), drawn from ``numpy.random.default_rng(seed)`` (without ``sensor``).
    seed : int
        Seed of the noise (the same seed gives the same view).
    tau : float
        Noise level, 1/m (without ``sensor``).
    sensor : str or SensorProfile, optional
        A sensor profile (:class:`heatdata.views.sensor.SensorProfile`: ``"ideal"``, ``"noise"``, ``"kinect"``) in
        place of ``noise`` and ``tau``; ``"kinect"`` adds the projector's shadows, disparity quantization, flying
        pixels and no depth on dark surfaces.
    intrinsics : dict, optional
        ``fx, fy, cx, cy, width, height``; default the Kinect's (f = 580 px, 640x480).
    image_offset : (du, dv) float
        Pixels right and down of the principal point where the model's centre appears: the camera is turned about
        its optical centre (not moved), so the object stands off the optical axis, seen from the same place.
    max_depth_jump : float
        Relative depth difference above which neighbouring pixels are not joined.
    components : {"largest", "all"}
        Keep the largest connected component (the default) or every one (:func:`heatdata.views.depth.grid_view`).

    Returns
    -------
    View
        Vertices in camera coordinates; by default the largest connected component only (any other
        component is dropped, logged and recorded in ``view.repairs``).

    Raises
    ------
    RenderError
        The model is not in the field of view or not seen.
    ViewError
        The visible surface has no triangle, or too few vertices (:func:`heatdata.views.depth.grid_view`).
    """
    k = check_intrinsics(KINECT_INTRINSICS if intrinsics is None else intrinsics, name="render intrinsics")
    if not (np.isfinite(tau) and tau >= 0):
        raise RenderError(f"the noise level tau must be a finite number >= 0 (1/m), got {tau}")
    if sensor is None:
        profile = SensorProfile.named("noise" if noise else "ideal")
        profile = profile if not noise else SensorProfile(**{**profile.to_dict(), "tau": tau})
    else:
        profile = SensorProfile.named(sensor)
    pose = camera_pose(model.center, azimuth, elevation, distance)
    if tuple(image_offset) != (0.0, 0.0):
        pose[:3, :3] = pose[:3, :3] @ _turn(image_offset, k).T
    rotation, position = pose[:3, :3], pose[:3, 3]
    name = view_id or f"{model.name}/az{azimuth:g}_el{elevation:g}"

    # pixels inside the projected bounding box
    lo, hi = model.vertices.min(axis=0), model.vertices.max(axis=0)
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    cam = (corners - position) @ rotation
    if np.any(cam[:, 2] <= 1e-6):
        raise RenderError(
            f"{name}: the camera at {distance} m is inside or behind the model's bounding box{_scale_hint(model)}"
        )
    u = k["fx"] * cam[:, 0] / cam[:, 2] + k["cx"]
    v = k["fy"] * cam[:, 1] / cam[:, 2] + k["cy"]
    u0, u1 = int(max(np.floor(u.min()) - 1, 0)), int(min(np.ceil(u.max()) + 1, k["width"] - 1))
    v0, v1 = int(max(np.floor(v.min()) - 1, 0)), int(min(np.ceil(v.max()) + 1, k["height"] - 1))
    if u0 > u1 or v0 > v1:
        raise RenderError(f"{name}: the model is outside the field of view{_scale_hint(model)}")
    scene = _scene_of(model)
    directions, true_depth, hits = _cast(scene, pose, k, (u0, u1, v0, v1))
    valid = np.isfinite(true_depth)
    if not valid.any():
        raise RenderError(
            f"{name}: no ray from the camera hits the model's {len(model.faces)} faces "
            f"(extents {np.round(model.extents, 4).tolist()} m){_scale_hint(model)}"
        )
    face_ids = hits["primitive_ids"].reshape(valid.shape)[valid].astype(np.int64)
    bary = hits["primitive_uvs"].reshape(*valid.shape, 2)[valid]
    colors = np.zeros((*valid.shape, 3))
    colors[valid] = _hit_colors(model, face_ids, bary)
    depth = _sensed(scene, pose, directions, true_depth, colors, profile, k["fx"], seed)
    if not np.isfinite(depth).any():
        raise RenderError(f"{name}: the sensor reads no depth on the model (every pixel is dark or in shadow)")
    # the same triangulation as a captured depth image's
    return grid_view(
        directions * depth[..., None],
        colors,
        max_depth_jump=max_depth_jump,
        components=components,
        intrinsics=k,
        view_id=name,
        object_id=model.name,
        label=model.label,
        azimuth=float(azimuth),
        elevation=float(elevation),
        distance=float(distance),
        pose=pose,
        repairs=list(model.repairs),
    )


@dataclass(frozen=True)
class Placement:
    """A model placed in a scene: ``pose`` (4, 4) takes the model's frame (metres, +y up) to the scene's."""

    model: Model
    pose: np.ndarray


@dataclass
class SceneFrame:
    """A rendered frame of a scene, and which placed model each pixel sees.

    Attributes
    ----------
    depth : (h, w) float64
        z-depth in metres as the sensor measures it; NaN where it gives no reading.
    rgb : (h, w, 3) float64
        The colour image, in [0, 1] (black where no model is hit).
    labels : (h, w) int32
        The index in ``names`` of the model each pixel's ray hits first, -1 for none (whether or not the sensor
        reads a depth there).
    names : list of str
        The placed models' names, in placement order.
    intrinsics : dict
        The camera's ``fx, fy, cx, cy, width, height``.
    camera : (4, 4) float64
        Camera-to-scene transform (columns: x right, y down, z forward, position).
    """

    depth: np.ndarray
    rgb: np.ndarray
    labels: np.ndarray
    names: list[str]
    intrinsics: dict
    camera: np.ndarray


def render_scene(
    placements: list[Placement],
    camera: np.ndarray,
    *,
    intrinsics: dict | None = None,
    sensor: str | SensorProfile | None = "kinect",
    seed: int | None = 0,
) -> SceneFrame:
    """The whole frame a camera sees of several placed models (objects on a table, a wall): depth, colour, truth.

    Parameters
    ----------
    placements : list of Placement
        The models and their poses in the scene's frame.
    camera : (4, 4) float
        Camera-to-scene transform (:func:`camera_pose` gives one looking at a point).
    intrinsics : dict, optional
        ``fx, fy, cx, cy, width, height``; default the Kinect's.
    sensor : str or SensorProfile, optional
        The sensor profile (default ``"kinect"``: noise, shadows, quantization, flying pixels, dark surfaces).
    seed : int
        Seed of the sensor's noise and flying pixels.

    Returns
    -------
    SceneFrame

    Raises
    ------
    RenderError
        No placement, a pose that is not a finite rigid transform, or a camera that is not one.
    """
    if not placements:
        raise RenderError("a scene needs at least one placed model")
    k = check_intrinsics(KINECT_INTRINSICS if intrinsics is None else intrinsics, name="render intrinsics")
    camera = _rigid(camera, "the camera pose")
    scene = o3d.t.geometry.RaycastingScene()
    for placement in placements:
        pose = _rigid(placement.pose, f"the pose of {placement.model.name}")
        vertices = placement.model.vertices @ pose[:3, :3].T + pose[:3, 3]
        scene.add_triangles(
            o3d.core.Tensor(vertices.astype(np.float32)), o3d.core.Tensor(placement.model.faces.astype(np.uint32))
        )
    directions, depth, hits = _cast(scene, camera, k, (0, k["width"] - 1, 0, k["height"] - 1))
    valid = np.isfinite(depth)
    labels = np.where(valid, hits["geometry_ids"].reshape(valid.shape).astype(np.int64), -1).astype(np.int32)
    faces = hits["primitive_ids"].reshape(valid.shape).astype(np.int64)
    bary = hits["primitive_uvs"].reshape(*valid.shape, 2)
    rgb = np.zeros((*valid.shape, 3))
    for index, placement in enumerate(placements):
        mine = labels == index
        if mine.any():
            rgb[mine] = _hit_colors(placement.model, faces[mine], bary[mine])
    measured = _sensed(scene, camera, directions, depth, rgb, SensorProfile.named(sensor), k["fx"], seed)
    return SceneFrame(measured, rgb, labels, [p.model.name for p in placements], k, camera)


def _rigid(pose: np.ndarray, what: str) -> np.ndarray:
    """``pose`` as a (4, 4) float64 rigid transform, or a RenderError."""
    pose = np.asarray(pose, dtype=np.float64)
    if (
        pose.shape != (4, 4)
        or not np.all(np.isfinite(pose))
        or not np.allclose(pose[3], [0, 0, 0, 1])
        or not np.allclose(pose[:3, :3] @ pose[:3, :3].T, np.eye(3), atol=1e-6)
        or np.linalg.det(pose[:3, :3]) < 0
    ):
        raise RenderError(f"{what} must be a finite 4x4 rigid transform (a rotation and a translation)")
    return pose
