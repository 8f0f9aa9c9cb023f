"""Organized point clouds (PCD, range PLY) to views, with the intrinsics fitted to their grid; and
:func:`read_frame`, which reads a sensor's frame of either kind: an organized cloud or a depth image."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from heatdata.errors import ViewError
from heatdata.io.files import require_file
from heatdata.io.models import checked_faces
from heatdata.typing import StrPath
from heatdata.views.depth import MAX_DEPTH_JUMP, grid_view, read_depth
from heatdata.views.view import MAX_IMAGE_PIXELS, View


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
    max_depth_jump: float = MAX_DEPTH_JUMP,
    view_id: str | None = None,
    object_id: str = "",
    label: str = "",
) -> View:
    """The view of an organized point cloud: a PCD with ``WIDTH`` x ``HEIGHT``, or a range-map PLY.

    Parameters
    ----------
    path : str or Path
        ``.pcd`` (ASCII or binary; fields ``x y z``, optionally ``rgb``; NaN = no reading)
        or ``.ply`` whose header holds a VCG ``camera`` element (MeshLab's range maps): its
        vertices are put back on their pixel grid by the camera.
    scale : float
        File units to metres (PCL writes metres; MeshLab range maps are often millimetres).

    Returns
    -------
    View
        Triangulated by :func:`grid_view`, intrinsics fitted to the grid.
    """
    path = Path(path)
    points, colors, intrinsics = read_cloud_grid(path, scale=scale)
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


def read_cloud_grid(path: StrPath, *, scale: float = 1.0) -> tuple[np.ndarray, np.ndarray | None, dict]:
    """An organized cloud's grid of points, its colours and the intrinsics fitted to the grid.

    Parameters
    ----------
    path : str or Path
        ``.pcd`` or a range-map ``.ply`` (:func:`read_organized_cloud`).
    scale : float
        File units to metres.

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
    if path.suffix.lower() == ".pcd":
        points, colors = _read_pcd(path)
    elif path.suffix.lower() == ".ply":
        points, colors = _read_range_ply(path)
    else:
        raise ViewError(f"{path}: unsupported organized cloud {path.suffix!r} (.pcd or a range-map .ply)")
    points = points * float(scale)
    return points, colors, fit_intrinsics(points)


MAX_CLOUD_BYTES = 256 * 2**20  # an ASCII cloud of a full MAX_IMAGE_PIXELS grid (about 60 bytes a point), with room

PCD_TYPES = {
    ("F", 4): "<f4",
    ("F", 8): "<f8",
    ("U", 1): "u1",
    ("U", 2): "<u2",
    ("U", 4): "<u4",
    ("I", 1): "i1",
    ("I", 2): "<i2",
    ("I", 4): "<i4",
}


def _read_pcd(path: Path) -> tuple[np.ndarray, np.ndarray | None]:
    raw = path.read_bytes()
    header, position = {}, 0
    while True:
        end = raw.find(b"\n", position)
        if end < 0:
            raise ViewError(f"{path}: the PCD header has no DATA line")
        line = raw[position:end].decode("ascii", "replace").strip()
        position = end + 1
        if not line or line.startswith("#"):
            continue
        key, *values = line.split()
        header[key.upper()] = values
        if key.upper() == "DATA":
            break
    try:
        fields, sizes, types = header["FIELDS"], [int(s) for s in header["SIZE"]], header["TYPE"]
        counts = [int(c) for c in header.get("COUNT", ["1"] * len(fields))]
        width, height, data = int(header["WIDTH"][0]), int(header["HEIGHT"][0]), header["DATA"][0].lower()
    except (KeyError, ValueError, IndexError) as error:
        raise ViewError(f"{path}: not a PCD header ({error})") from error
    if not len(fields) == len(sizes) == len(types) == len(counts):
        raise ViewError(
            f"{path}: the PCD header gives {len(fields)} FIELDS, {len(sizes)} SIZE, {len(types)} TYPE and "
            f"{len(counts)} COUNT entries; they must match"
        )
    if height <= 1:
        raise ViewError(f"{path}: the cloud is not organized (HEIGHT {height}): a view needs its pixel grid")
    if not (width >= 1 and width * height <= MAX_IMAGE_PIXELS) or min(counts) < 1:
        raise ViewError(
            f"{path}: a {width}x{height} grid with counts {counts} is not read "
            f"(at most {MAX_IMAGE_PIXELS / 1e6:.1f} Mpixel)"
        )
    if not {"x", "y", "z"} <= set(fields):
        raise ViewError(f"{path}: the cloud has no x y z fields ({' '.join(fields)})")
    if len(set(fields)) < len(fields):
        raise ViewError(f"{path}: a field is named twice in FIELDS {' '.join(fields)}")
    if any(c != 1 for f, c in zip(fields, counts) if f in ("x", "y", "z", "rgb", "rgba")):
        raise ViewError(f"{path}: x, y, z and rgb must be one number each (COUNT {' '.join(map(str, counts))})")
    unknown = [f"{f} {t}{s}" for f, s, t in zip(fields, sizes, types) if (t, s) not in PCD_TYPES]
    if unknown:
        raise ViewError(f"{path}: PCD field types not read: {', '.join(unknown)}")
    dtype = np.dtype(
        [(f, PCD_TYPES[(t, s)], (c,) if c > 1 else ()) for f, s, t, c in zip(fields, sizes, types, counts)]
    )
    if data == "ascii":
        try:
            table = np.loadtxt(raw[position:].decode("ascii").splitlines(), ndmin=2)
        except (ValueError, UnicodeDecodeError) as error:
            raise ViewError(f"{path}: the PCD's ASCII data are not rows of numbers ({error})") from None
        if table.shape[1] != sum(counts):
            raise ViewError(f"{path}: the PCD's rows have {table.shape[1]} numbers, its header {sum(counts)} fields")
        cloud = np.zeros(len(table), dtype)
        column = 0
        for f, c in zip(fields, counts):
            cloud[f] = table[:, column] if c == 1 else table[:, column : column + c]
            column += c
    elif data == "binary":
        if len(raw) - position < dtype.itemsize * width * height:
            raise ViewError(
                f"{path}: truncated: {len(raw) - position} bytes of data for {width}x{height} points of "
                f"{dtype.itemsize} bytes"
            )
        cloud = np.frombuffer(raw, dtype, count=width * height, offset=position)
    else:
        raise ViewError(f"{path}: PCD DATA {data} is not read (save it as ascii or binary)")
    if len(cloud) != width * height:
        raise ViewError(f"{path}: {len(cloud)} points for a {width}x{height} grid")
    points = np.stack([cloud[a].astype(np.float64) for a in "xyz"], axis=-1).reshape(height, width, 3)
    colors = None
    if "rgb" in fields or "rgba" in fields:
        packed = cloud["rgb" if "rgb" in fields else "rgba"]
        packed = packed.view(np.uint32) if packed.dtype.kind == "f" else packed.astype(np.uint32)
        colors = (
            np.stack([(packed >> 16) & 255, (packed >> 8) & 255, packed & 255], axis=-1).reshape(height, width, 3)
            / 255.0
        )
    return points, colors


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
        A depth image's intrinsics (needed), colour image and mask; a cloud carries its own grid and colours.
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
        if intrinsics_path or rgb_path or mask_path or depth_range:
            raise ViewError(
                f"{path}: an organized cloud carries its own grid and colours; --intrinsics, "
                "--rgb, --mask and --depth-range are for depth images"
            )
        return read_organized_cloud(path, scale=scale, max_depth_jump=max_depth_jump)
    return read_depth(
        path,
        intrinsics_path,
        rgb_path or None,
        mask_path or None,
        depth_range=depth_range,
        max_depth_jump=max_depth_jump,
    )
