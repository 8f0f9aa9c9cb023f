"""Organized point clouds (PCD, range PLY) to views, with the intrinsics fitted to their grid; and
:func:`read_frame`, which reads a sensor's frame of either kind: an organized cloud or a depth image."""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from heatdata.errors import ViewError
from heatdata.frames.pcd import read_pcd
from heatdata.frames.range_grid import is_range_grid, read_range_grid
from heatdata.io.files import require_file
from heatdata.io.models import checked_faces
from heatdata.typing import StrPath
from heatdata.views.depth import MAX_DEPTH_JUMP, grid_view, pixels_of, read_depth, read_intrinsics
from heatdata.views.view import MAX_IMAGE_PIXELS, View, check_intrinsics

log = logging.getLogger(__name__)


def fit_intrinsics(points: np.ndarray) -> dict:
    """Pinhole intrinsics of an organized cloud: least squares of its pixel grid against x/z and y/z."""
    valid = np.isfinite(points).all(axis=2) & (points[..., 2] > 0)
    rows, cols = np.nonzero(valid)
    if len(rows) < 3:
        raise ViewError("an organized cloud needs at least 3 valid points to fit its intrinsics")
    p = points[valid]
    (fx, cx), *_ = np.linalg.lstsq(np.column_stack([p[:, 0] / p[:, 2], np.ones(len(p))]), cols, rcond=None)
    (fy, cy), *_ = np.linalg.lstsq(np.column_stack([p[:, 1] / p[:, 2], np.ones(len(p))]), rows, rcond=None)
    return {
        "fx": float(fx),
        "fy": float(fy),
        "cx": float(cx),
        "cy": float(cy),
        "width": points.shape[1],
        "height": points.shape[0],
    }


def read_organized_cloud(
    path: StrPath,
    *,
    scale: float = 1.0,
    intrinsics: dict | None = None,
    max_depth_jump: float = MAX_DEPTH_JUMP,
    view_id: str | None = None,
    object_id: str = "",
    label: str = "",
) -> View:
    """The view of an organized point cloud: a PCD with ``WIDTH`` x ``HEIGHT``, or a range-map PLY.

    Parameters
    ----------
    path : str or Path
        ``.pcd`` (DATA ascii, binary or binary_compressed; fields ``x y z``, optionally ``rgb``/``rgba`` and any
        others; NaN = no reading), ``.ply`` whose header holds a VCG ``camera`` element (MeshLab's range maps): its
        vertices are put back on their pixel grid by the camera, or a Cyberware ``range_grid`` ``.ply``.
    scale : float
        File units to metres (PCL writes metres; MeshLab range maps are often millimetres).
    intrinsics : dict, optional
        The camera's, for an unorganized PCD (:func:`read_cloud_grid`).

    Returns
    -------
    View
        Triangulated by :func:`grid_view`, intrinsics fitted to the grid.
    """
    path = Path(path)
    points, colors, intrinsics = read_cloud_grid(path, scale=scale, intrinsics=intrinsics)
    return grid_view(
        points,
        colors,
        max_depth_jump=max_depth_jump,
        intrinsics=intrinsics,
        view_id=view_id or path.stem,
        object_id=object_id,
        label=label,
        repairs=[f"organized {points.shape[1]}x{points.shape[0]} cloud, not segmented"],
    )


def read_cloud_grid(
    path: StrPath, *, scale: float = 1.0, intrinsics: dict | None = None
) -> tuple[np.ndarray, np.ndarray | None, dict]:
    """An organized cloud's grid of points, its colours and the intrinsics fitted to the grid.

    Parameters
    ----------
    path : str or Path
        ``.pcd`` (any DATA kind), a range-map ``.ply`` (:func:`read_organized_cloud`) or a Cyberware
        ``range_grid`` ``.ply`` (:func:`heatdata.frames.range_grid.read_range_grid`).
    scale : float
        File units to metres.
    intrinsics : dict, optional
        The camera's: an unorganized PCD (HEIGHT 1) is put back on its pixels (:func:`on_pixels`), and an organized
        one is checked against them.

    Returns
    -------
    points : (h, w, 3) float64
        Camera-frame points in metres, NaN where there is no reading.
    colors : (h, w, 3) float64 in [0, 1] or None
    intrinsics : dict
        :func:`fit_intrinsics` of the grid.
    """
    path = require_file(path, "point cloud file", ViewError)
    if path.stat().st_size > MAX_CLOUD_BYTES:
        raise ViewError(f"{path}: {path.stat().st_size / 2**20:.0f} MB, above the cap of {MAX_CLOUD_BYTES >> 20} MB")
    if intrinsics is not None and path.suffix.lower() != ".pcd":
        raise ViewError(
            f"{path}: a range map carries its own grid; --intrinsics is for depth images and unorganized PCDs"
        )
    if path.suffix.lower() == ".pcd":
        points, colors = _read_pcd(path, intrinsics)
    elif path.suffix.lower() == ".ply" and is_range_grid(path):
        points, colors = read_range_grid(path)
    elif path.suffix.lower() == ".ply":
        points, colors = _read_range_ply(path)
    else:
        raise ViewError(f"{path}: unsupported organized cloud {path.suffix!r} (.pcd or a range-map .ply)")
    points = points * float(scale)
    if intrinsics is not None and path.suffix.lower() == ".pcd":
        return points, colors, check_intrinsics(intrinsics, points.shape[:2], str(path))
    return points, colors, fit_intrinsics(points)


MAX_CLOUD_BYTES = 256 * 2**20  # an ASCII cloud of a full MAX_IMAGE_PIXELS grid (about 60 bytes a point), with room


def _read_pcd(path: Path, intrinsics: dict | None) -> tuple[np.ndarray, np.ndarray | None]:
    """A PCD's grid of points and colours: an organized cloud's own grid, or an unorganized cloud put back on the
    pixels of ``intrinsics`` (:func:`on_pixels`)."""
    cloud = read_pcd(path)
    if cloud.organized:
        if intrinsics is not None and (intrinsics["width"], intrinsics["height"]) != cloud.points.shape[1::-1]:
            raise ViewError(
                f"{path}: an organized {cloud.points.shape[1]}x{cloud.points.shape[0]} cloud, but the intrinsics are "
                f"for {intrinsics['width']}x{intrinsics['height']} pixels"
            )
        return cloud.points, cloud.colors
    if intrinsics is None:
        raise ViewError(
            f"{path}: an unorganized cloud (HEIGHT 1) has no pixel grid: give the camera's intrinsics "
            "(--intrinsics) to put its points back on their pixels"
        )
    colors = None if cloud.colors is None else cloud.colors[0]
    return on_pixels(cloud.points[0], colors, intrinsics, str(path))


def on_pixels(
    points: np.ndarray, colors: np.ndarray | None, intrinsics: dict, name: str
) -> tuple[np.ndarray, np.ndarray | None]:
    """An unorganized cloud in the camera's frame put back on the camera's pixels: each point on the pixel it
    projects to, the nearest where two share one.

    Parameters
    ----------
    points : (n, 3) float
        Camera-frame points (z forward), NaN for no reading.
    colors : (n, 3) float in [0, 1], optional
    intrinsics : dict
        ``fx, fy, cx, cy, width, height``.
    name : str
        For messages.

    Returns
    -------
    points : (height, width, 3) float64
        NaN where no point falls.
    colors : (height, width, 3) float64 or None
    """
    k = check_intrinsics(intrinsics, name=name)
    points = np.asarray(points, np.float64)
    finite = np.isfinite(points).all(axis=1) & (points[:, 2] > 0)
    pixel, inside = pixels_of(points, k)
    if not inside.any():
        raise ViewError(f"{name}: no point of the cloud falls inside the image of these intrinsics")
    if inside.sum() < 0.9 * finite.sum():
        log.warning(
            "%s: %d of %d points fall outside the image of these intrinsics",
            name,
            int(finite.sum() - inside.sum()),
            int(finite.sum()),
        )
    index = np.flatnonzero(inside)
    index = index[np.argsort(-points[index, 2], kind="stable")]  # far first: the nearest is written last
    cells = pixel[index, 1] * k["width"] + pixel[index, 0]
    grid = np.full((k["height"] * k["width"], 3), np.nan)
    grid[cells] = points[index]
    colour_grid = None
    if colors is not None:
        colour_grid = np.full((k["height"] * k["width"], 3), 0.5)
        colour_grid[cells] = np.asarray(colors, np.float64)[index]
        colour_grid = colour_grid.reshape(k["height"], k["width"], 3)
    return grid.reshape(k["height"], k["width"], 3), colour_grid


CAMERA_FIELDS = [f"view_p{a}" for a in "xyz"] + [f"{a}_axis{b}" for a in "xyz" for b in "xyz"]


def _camera(mesh, path: Path) -> dict[str, float]:
    """The first row of a range-map PLY's VCG ``camera`` element: a structured array (binary PLY) or a mapping
    of columns (ASCII PLY), as trimesh reads them."""
    element = getattr(mesh, "metadata", {}).get("_ply_raw", {}).get("camera")
    data = None if element is None else element.get("data")
    if data is None or not len(data):
        raise ViewError(f"{path}: the PLY has no camera element, so its pixel grid is unknown (not organized)")
    names = data.keys() if isinstance(data, dict) else data.dtype.names or ()
    missing = [f for f in CAMERA_FIELDS if f not in names]
    if missing:
        raise ViewError(f"{path}: the PLY's camera element lacks {', '.join(missing)}")
    try:
        if isinstance(data, dict):
            return {f: float(np.ravel(data[f])[0]) for f in CAMERA_FIELDS}
        return {f: float(data[0][f]) for f in CAMERA_FIELDS}
    except (IndexError, TypeError, ValueError) as error:
        raise ViewError(f"{path}: the PLY's camera element is not numbers ({error})") from None


def _read_range_ply(path: Path) -> tuple[np.ndarray, np.ndarray | None]:
    import trimesh

    try:
        mesh = trimesh.load(path, process=False)
    except Exception as error:  # trimesh raises many kinds on a bad file
        raise ViewError(f"{path}: cannot read the PLY ({error})") from error
    if not isinstance(mesh, trimesh.Trimesh):
        raise ViewError(f"{path}: the PLY is not one triangle mesh (a range map is)")
    camera = _camera(mesh, path)
    axes = np.array([[camera[f"{a}_axis{b}"] for b in "xyz"] for a in "xyz"], np.float64)
    position = [camera["view_px"], camera["view_py"], camera["view_pz"]]
    if not (np.isfinite(axes).all() and np.isfinite(position).all()):
        raise ViewError(f"{path}: the PLY's camera has NaN or infinite values")
    faces = checked_faces(getattr(mesh, "faces", np.zeros((0, 3), np.int64)), len(mesh.vertices), str(path))
    local = (np.asarray(mesh.vertices, np.float64) - position) @ axes.T
    local[:, 1] *= -1.0  # VCG's camera y is up; a view's is down (z stays forward)
    if not (local[:, 2] > 0).all():
        raise ViewError(f"{path}: vertices behind the PLY's camera")
    angles = local[:, :2] / local[:, 2:]
    # The grid's pitch, from the range map's own edges (MeshLab's focal and pixel size round it off by ~2%)
    if not len(faces):
        raise ViewError(f"{path}: the range map has no faces to find its grid pitch from")
    steps = np.abs(np.diff(angles[faces[:, [0, 1, 2, 0]]], axis=1)).reshape(-1, 2)
    pitch = np.array([np.median(s[s > 0.5 * np.median(s[s > 0])]) for s in steps.T])
    if not (np.isfinite(pitch).all() and (pitch > 0).all()):
        raise ViewError(f"{path}: the range map's edges give no grid pitch (its faces join no neighbouring pixels)")
    grid = np.round((angles - angles.min(axis=0)) / pitch).astype(np.int64)
    shape = grid.max(axis=0)[::-1] + 1
    if shape[0] * shape[1] > MAX_IMAGE_PIXELS:
        raise ViewError(f"{path}: the range map's grid would be {shape[1]}x{shape[0]} pixels, above the cap")
    cells = grid[:, 1] * shape[1] + grid[:, 0]
    if len(np.unique(cells)) < len(cells):
        raise ViewError(f"{path}: two vertices fall on one pixel: not an organized range map")
    points = np.full((*shape, 3), np.nan)
    points.reshape(-1, 3)[cells] = local
    colors = None
    visual = getattr(mesh, "visual", None)
    if visual is not None and getattr(visual, "kind", None) == "vertex":
        colors = np.full((*shape, 3), 0.5)
        colors.reshape(-1, 3)[cells] = np.asarray(visual.vertex_colors, np.float64)[:, :3] / 255.0
    return points, colors


CLOUD_SUFFIXES = (".pcd", ".ply")


def read_frame(
    path: StrPath,
    intrinsics_path: StrPath | None = None,
    rgb_path: StrPath | None = None,
    mask_path: StrPath | None = None,
    *,
    depth_range: tuple[float, float] | None = None,
    scale: float = 1.0,
    max_depth_jump: float = MAX_DEPTH_JUMP,
) -> View:
    """The view of a sensor's frame: a depth image (:func:`heatdata.views.depth.read_depth`) or an organized cloud
    (:func:`read_organized_cloud`), told apart by the file's suffix.

    Parameters
    ----------
    path : str or Path
        A 16-bit PNG (millimetres) or float ``.npy`` (metres), or a ``.pcd`` or range-map ``.ply``.
    intrinsics_path, rgb_path, mask_path : str or Path, optional
        A depth image's intrinsics (needed), colour image and mask; a cloud carries its own colours, and its own
        grid unless it is unorganized (then the intrinsics put it on its pixels).
    depth_range : (near, far) metres, optional
        A depth image's segmentation when there is no mask.
    scale : float
        A cloud's units to metres.
    max_depth_jump : float
        See :func:`heatdata.views.depth.grid_faces`.

    Returns
    -------
    View
        The view in the camera's frame.
    """
    if Path(path).suffix.lower() in CLOUD_SUFFIXES:
        if rgb_path or mask_path or depth_range:
            raise ViewError(
                f"{path}: a cloud carries its own colours and is segmented as a whole; --rgb, --mask and "
                "--depth-range are for depth images"
            )
        intrinsics = read_intrinsics(intrinsics_path) if intrinsics_path else None
        return read_organized_cloud(path, scale=scale, intrinsics=intrinsics, max_depth_jump=max_depth_jump)
    return read_depth(
        path,
        intrinsics_path,
        rgb_path or None,
        mask_path or None,
        depth_range=depth_range,
        max_depth_jump=max_depth_jump,
    )


def read_frame_grid(
    path: StrPath,
    intrinsics_path: StrPath | None = None,
    rgb_path: StrPath | None = None,
    *,
    scale: float = 1.0,
) -> tuple[np.ndarray, np.ndarray | None, dict]:
    """A sensor's frame as an organized grid of camera-frame points, before segmentation: a depth image with its
    intrinsics and colour, or a cloud (:func:`read_cloud_grid`; an unorganized PCD needs the intrinsics).

    Parameters
    ----------
    path : str or Path
        A 16-bit PNG (millimetres) or float ``.npy`` (metres), or a ``.pcd`` or ``.ply`` cloud.
    intrinsics_path : str or Path, optional
        JSON or YAML ``fx, fy, cx, cy, width, height``: needed by a depth image and an unorganized PCD.
    rgb_path : str or Path, optional
        A depth image's colour (a cloud carries its own).
    scale : float
        A cloud's units to metres.

    Returns
    -------
    points : (h, w, 3) float64
        Metres, NaN where there is no reading.
    colors : (h, w, 3) float64 in [0, 1] or uint8, or None
    intrinsics : dict
    """
    from heatdata.views.depth import back_project, checked_depth, read_depth_frame

    if Path(path).suffix.lower() in CLOUD_SUFFIXES:
        if rgb_path:
            raise ViewError(f"{path}: a cloud carries its own colours; --rgb is for depth images")
        intrinsics = read_intrinsics(intrinsics_path) if intrinsics_path else None
        return read_cloud_grid(path, scale=scale, intrinsics=intrinsics)
    depth, rgb, intrinsics = read_depth_frame(path, intrinsics_path, rgb_path)
    depth, k = checked_depth(depth, intrinsics, str(path))
    return back_project(depth, k), rgb, k
