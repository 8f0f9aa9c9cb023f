"""A virtual Kinect: partial views of a model by ray casting (thesis 2.1, 2.6.1, 3.1).

The camera sits on a sphere around the model's bounding-box centre at a view angle
(azimuth about the model's +y axis, elevation above its xz-plane) and looks at the
centre with the model's +y up in the image. Rays of a 640x480 pinhole camera
(f = 580 px) are cast with open3d's CPU ``RaycastingScene``; only pixels inside the
projected bounding box are cast. Depth noise follows 2.6.1: z = z0 + z0^2 eps,
eps ~ N(0, tau^2), tau = 1.42e-3 1/m. The organized depth grid becomes a triangle mesh
of the visible surface by :func:`heatdata.views.depth.grid_view`, as a captured depth image is:
neighbouring pixels are joined unless their depths differ by more than
``max_depth_jump`` times the depth.
"""

from __future__ import annotations

import logging

import numpy as np
import open3d as o3d

from heatdata.errors import RenderError
from heatdata.io.models import LARGE_MODEL, Model
from heatdata.views.depth import MAX_DEPTH_JUMP, grid_view
from heatdata.views.view import KINECT_INTRINSICS, View, check_intrinsics

log = logging.getLogger(__name__)

KINECT_TAU = 1.42e-3  # 1/m, depth noise of 2.6.1


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


def render_view(
    model: Model,
    azimuth: float = 0.0,
    elevation: float = 30.0,
    distance: float = 1.0,
    *,
    noise: bool = True,
    seed: int | None = 0,
    tau: float = KINECT_TAU,
    intrinsics: dict | None = None,
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
        Add Kinect depth noise (2.6.1), drawn from ``numpy.random.default_rng(seed)``.
    seed : int
        Seed of the noise (the same seed gives the same view).
    tau : float
        Noise level, 1/m.
    intrinsics : dict, optional
        ``fx, fy, cx, cy, width, height``; default the Kinect's (f = 580 px, 640x480).
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
    pose = camera_pose(model.center, azimuth, elevation, distance)
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
    cols, rows = np.meshgrid(np.arange(u0, u1 + 1), np.arange(v0, v1 + 1))
    directions = np.stack([(cols - k["cx"]) / k["fx"], (rows - k["cy"]) / k["fy"], np.ones(cols.shape)], axis=-1)
    world_dirs = directions.reshape(-1, 3) @ rotation.T  # unit z component in the camera frame
    rays = np.hstack([np.broadcast_to(position, world_dirs.shape), world_dirs]).astype(np.float32)
    hits = _scene_of(model).cast_rays(o3d.core.Tensor(rays))
    depth = hits["t_hit"].numpy().astype(np.float64).reshape(cols.shape)
    valid = np.isfinite(depth)
    if not valid.any():
        raise RenderError(
            f"{name}: no ray from the camera hits the model's {len(model.faces)} faces "
            f"(extents {np.round(model.extents, 4).tolist()} m){_scale_hint(model)}"
        )
    if noise:
        rng = np.random.default_rng(seed)
        depth[valid] += depth[valid] ** 2 * rng.normal(0.0, tau, int(valid.sum()))

    depth[~valid] = np.nan
    face_ids = hits["primitive_ids"].numpy().reshape(cols.shape)[valid].astype(np.int64)
    bary = hits["primitive_uvs"].numpy().reshape(*cols.shape, 2)[valid]
    colors = np.zeros((*cols.shape, 3))
    colors[valid] = _hit_colors(model, face_ids, bary)
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
