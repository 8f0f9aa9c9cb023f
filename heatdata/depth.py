"""Views from depth images and organized point clouds, real or rendered, and back (thesis 2.1, 2.3).

A partial view is the triangle mesh of an organized depth grid: neighbouring valid pixels
are joined unless their depths differ by more than ``max_depth_jump`` times their mean
depth (a depth discontinuity), and only the largest connected piece is kept. The virtual
Kinect (:func:`heatdata.render_view`) and every sensor reader here go through the same
:func:`grid_view`, so a capture and a rendering of the same surface give the same mesh.

Inputs:

- a depth image: a 16-bit PNG in millimetres (0 = no reading, as the Kinect and
  RealSense SDKs write them) or a float ``.npy`` in metres (NaN or 0 = no reading), with
  pinhole intrinsics ``fx, fy, cx, cy, width, height`` in a JSON or YAML file, an optional
  aligned RGB image and an optional object mask;
- an organized point cloud: a PCD with ``WIDTH`` x ``HEIGHT`` (NaN = no reading), or a
  range-map PLY whose header holds its camera (VCG/MeshLab's ``camera`` element, e.g.
  pymeshlab's ``tests/sample_meshes/rangemaps/face000.ply``).

Segmentation, in this order: the mask when given; else the depth range when given; else
every valid pixel. Then the largest connected piece of the mesh (a support plane joined
to the object stays: give a mask or a depth range to cut it off).
"""

from __future__ import annotations

import json
import logging
from pathlib import Path

import numpy as np
import yaml
from PIL import Image

from .errors import ViewError
from .view import View

log = logging.getLogger(__name__)

INTRINSIC_KEYS = ("fx", "fy", "cx", "cy", "width", "height")
MAX_DEPTH_JUMP = 0.02  # relative depth step above which neighbouring pixels are not joined


def grid_faces(index: np.ndarray, depth: np.ndarray, max_jump: float) -> np.ndarray:
    """Triangles joining neighbouring valid pixels of an organized grid.

    Parameters
    ----------
    index : (h, w) int64
        Vertex index of each pixel, -1 where there is no reading.
    depth : (n,) float
        Depth of each vertex.
    max_jump : float
        A triangle is dropped when two of its pixels differ in depth by more than
        ``max_jump`` times their mean depth.

    Returns
    -------
    (m, 3) int64
        Each 2x2 pixel block gives two triangles when its four pixels are valid, or one
        when three are, wound clockwise in the image (u right, v down): their normals
        point away from the camera (+z).
    """
    a, b = index[:-1, :-1], index[:-1, 1:]
    c, d = index[1:, :-1], index[1:, 1:]
    candidates = [
        (a, b, c, (a >= 0) & (b >= 0) & (c >= 0)),
        (b, d, c, (b >= 0) & (c >= 0) & (d >= 0)),
        (a, b, d, (a >= 0) & (b >= 0) & (d >= 0) & (c < 0)),
        (a, d, c, (a >= 0) & (c >= 0) & (d >= 0) & (b < 0)),
    ]
    faces = np.concatenate([np.column_stack([p[m], q[m], r[m]]) for p, q, r, m in candidates])
    z = depth[faces]
    mean = z.mean(axis=1)
    spread = z.max(axis=1) - z.min(axis=1)
    return faces[spread <= max_jump * mean]


def grid_view(points: np.ndarray, colors: np.ndarray | None = None, *, max_depth_jump: float = MAX_DEPTH_JUMP,
              components: str = "largest", **view_fields) -> View:
    """The view of an organized grid of camera-frame points: its triangle mesh, largest piece only by default.

    Parameters
    ----------
    points : (h, w, 3) float
        Camera-frame points (x right, y down, z forward, metres), NaN where there is no
        reading.
    colors : (h, w, 3) float in [0, 1], optional
    max_depth_jump : float
        See :func:`grid_faces`.
    components : {"largest", "all"}
        Keep the largest connected piece (a repair, recorded in ``repairs``), or every piece (to measure what
        the largest leaves out, issue 28).
    **view_fields
        ``intrinsics``, ``view_id``, ``object_id``, ``label``, angles, ``pose``, ``repairs``.

    Raises
    ------
    ViewError
        No valid pixel, or no triangle between them.
    """
    name = view_fields.get("view_id") or "view"
    if components not in ("largest", "all"):
        raise ViewError(f"{name}: components must be 'largest' or 'all', got {components!r}")
    valid = np.isfinite(points).all(axis=2) & (points[..., 2] > 0)
    if not valid.any():
        raise ViewError(f"{name}: no valid pixel")
    index = np.full(valid.shape, -1, np.int64)
    index[valid] = np.arange(int(valid.sum()))
    vertices = points[valid].astype(np.float64)
    faces = grid_faces(index, vertices[:, 2], max_depth_jump)
    if len(faces) == 0:
        raise ViewError(f"{name}: the {int(valid.sum())} valid pixels form no triangle (isolated pixels, or depth "
                        f"steps above {max_depth_jump:g} of the depth everywhere)")
    rgb = None if colors is None else np.asarray(colors, np.float64)[valid]
    view = View.from_arrays(vertices, faces, rgb, **view_fields)
    return view.largest_component() if components == "largest" else view


def check_intrinsics(intrinsics: dict, shape: tuple[int, int] | None = None, name: str = "intrinsics") -> dict:
    """``fx, fy, cx, cy, width, height`` as numbers, checked (and against an image's ``(h, w)``)."""
    missing = [key for key in INTRINSIC_KEYS if key not in intrinsics]
    if missing:
        raise ViewError(f"{name}: missing {', '.join(missing)} (need {', '.join(INTRINSIC_KEYS)})")
    try:
        k = {key: float(intrinsics[key]) for key in INTRINSIC_KEYS}
    except (TypeError, ValueError) as error:
        raise ViewError(f"{name}: intrinsics must be numbers ({error})") from error
    if not (k["fx"] > 0 and k["fy"] > 0 and k["width"] >= 1 and k["height"] >= 1):
        raise ViewError(f"{name}: fx, fy, width and height must be positive, got {k}")
    k["width"], k["height"] = int(k["width"]), int(k["height"])
    if shape is not None and (k["height"], k["width"]) != tuple(shape):
        raise ViewError(f"{name}: the intrinsics are for {k['width']}x{k['height']} but the depth image is "
                        f"{shape[1]}x{shape[0]}")
    return k


def back_project(depth: np.ndarray, intrinsics: dict) -> np.ndarray:
    """(h, w, 3) camera-frame points of a z-depth image (metres; NaN stays NaN)."""
    rows, cols = np.indices(depth.shape)
    k = intrinsics
    return np.stack([(cols - k["cx"]) / k["fx"] * depth, (rows - k["cy"]) / k["fy"] * depth, depth], axis=-1)


def view_from_depth(depth_m: np.ndarray, intrinsics: dict, rgb: np.ndarray | None = None,
                    mask: np.ndarray | None = None, *, depth_range: tuple[float, float] | None = None,
                    max_depth_jump: float = MAX_DEPTH_JUMP, view_id: str = "depth", object_id: str = "",
                    label: str = "") -> View:
    """The view seen in a depth image (thesis 2.1): segmented, triangulated as rendered views are.

    Parameters
    ----------
    depth_m : (h, w) float
        z-depth in metres; NaN, infinite or <= 0 where there is no reading.
    intrinsics : dict
        ``fx, fy, cx, cy`` in pixels, ``width, height`` matching the image.
    rgb : (h, w, 3) uint8 or float in [0, 1], optional
        Colour registered to the depth image (default grey).
    mask : (h, w) bool, optional
        The object's pixels.
    depth_range : (near, far) metres, optional
        Used when there is no mask: the pixels within it.
    max_depth_jump : float
        See :func:`grid_faces`.

    Returns
    -------
    View
        Camera-frame vertices; the segmentation is recorded in ``view.repairs``.

    Raises
    ------
    ViewError
        Intrinsics that do not match the image, an RGB image or mask of another size, no
        valid pixel (after segmentation), no triangle.
    """
    depth = np.array(depth_m, dtype=np.float64)
    if depth.ndim != 2:
        raise ViewError(f"{view_id}: a depth image is (h, w), got shape {depth.shape}")
    k = check_intrinsics(intrinsics, depth.shape, view_id)
    depth[~np.isfinite(depth) | (depth <= 0)] = np.nan
    readings = int(np.isfinite(depth).sum())
    if readings == 0:
        raise ViewError(f"{view_id}: the depth image has no valid pixel (all zero, NaN or negative)")
    colors = None if rgb is None else _rgb(rgb, depth.shape, view_id)
    if mask is not None:
        mask = np.asarray(mask)
        if mask.shape != depth.shape:
            raise ViewError(f"{view_id}: the mask is {mask.shape[1::-1]} but the depth image is {depth.shape[::-1]}")
        depth[~mask.astype(bool)] = np.nan
        note = f"segmented by the mask: {int(np.isfinite(depth).sum())} of {readings} readings"
    elif depth_range is not None:
        near, far = map(float, depth_range)
        if not 0 <= near < far:
            raise ViewError(f"{view_id}: depth_range must be (near, far) with 0 <= near < far, got {depth_range}")
        depth[(depth < near) | (depth > far)] = np.nan
        note = f"segmented by depth {near:g}-{far:g} m: {int(np.isfinite(depth).sum())} of {readings} readings"
    else:
        note = f"not segmented: all {readings} readings"
    if not np.isfinite(depth).any():
        raise ViewError(f"{view_id}: no valid pixel is left after segmentation ({note.split(':')[0]})")
    log.info("%s: %s", view_id, note)
    return grid_view(back_project(depth, k), colors, max_depth_jump=max_depth_jump, intrinsics=k, view_id=view_id,
                     object_id=object_id, label=label, repairs=[note])


def _rgb(rgb: np.ndarray, shape: tuple[int, int], name: str) -> np.ndarray:
    rgb = np.asarray(rgb)
    if rgb.ndim == 3 and rgb.shape[2] == 4:
        rgb = rgb[..., :3]
    if rgb.shape != (*shape, 3):
        raise ViewError(f"{name}: the RGB image is {rgb.shape[1::-1] if rgb.ndim >= 2 else rgb.shape} but the "
                        f"depth image is {shape[::-1]} (register the colour to the depth first)")
    if rgb.dtype.kind in "ui":
        return rgb.astype(np.float64) / 255.0
    rgb = rgb.astype(np.float64)
    if not (np.isfinite(rgb).all() and rgb.min() >= 0 and rgb.max() <= 1):
        raise ViewError(f"{name}: a float RGB image must lie in [0, 1]")
    return rgb


def read_intrinsics(path) -> dict:
    """Intrinsics from a JSON or YAML file with ``fx, fy, cx, cy, width, height``."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text())  # JSON is YAML
    except (OSError, yaml.YAMLError) as error:
        raise ViewError(f"{path}: cannot read the intrinsics ({error})") from error
    if not isinstance(data, dict):
        raise ViewError(f"{path}: the intrinsics must be a mapping of {', '.join(INTRINSIC_KEYS)}")
    return check_intrinsics(data, name=str(path))


def read_depth(path, intrinsics_path, rgb_path=None, mask_path=None, **kwargs) -> View:
    """:func:`view_from_depth` of files: a 16-bit PNG in millimetres or a float ``.npy`` in metres.

    ``rgb_path``: a colour image of the same size; ``mask_path``: an image whose non-zero
    pixels are the object's. Other keywords go to :func:`view_from_depth`.
    """
    path = Path(path)
    if not path.is_file():
        raise ViewError(f"{path}: no such depth file")
    suffix = path.suffix.lower()
    if suffix == ".npy":
        depth = np.load(path)
        if depth.dtype.kind != "f":
            raise ViewError(f"{path}: a .npy depth image holds float metres, got {depth.dtype}")
    elif suffix == ".png":
        with Image.open(path) as image:
            if image.mode not in ("I;16", "I;16B", "I;16L", "I"):
                raise ViewError(f"{path}: a depth PNG must be 16-bit (millimetres), got mode {image.mode}")
            depth = np.asarray(image, dtype=np.float64) / 1000.0
    else:
        raise ViewError(f"{path}: unsupported depth file {suffix!r} (a 16-bit PNG in millimetres or a float .npy "
                        "in metres; convert EXR to .npy)")
    rgb = None if rgb_path is None else _image(rgb_path, "RGB")
    mask = None if mask_path is None else _image(mask_path, "L") > 0
    kwargs.setdefault("view_id", path.stem)
    return view_from_depth(depth, read_intrinsics(intrinsics_path), rgb, mask, **kwargs)


CAPTURE_SUFFIXES = (".png", ".npy")
CAMERA_NAMES = ("camera.json", "camera.yaml", "camera.yml")


def find_captures(root) -> list[dict]:
    """The captures of a folder laid out as ``<root>/<object>/<name>.png`` (or ``.npy``), one folder per object.

    Beside a depth image ``<name>.png`` may lie ``<name>.rgb.png`` (colour) and
    ``<name>.mask.png`` (the object's pixels). The intrinsics are ``<name>.json`` (or
    ``.yaml``) when present, else ``camera.json`` / ``camera.yaml`` in the object's folder,
    else in ``root``.

    Returns
    -------
    list of dict
        ``object, name, depth, intrinsics, rgb, mask`` (paths as strings, ``""`` when
        absent), sorted by object and name.

    Raises
    ------
    ViewError
        ``root`` is not a folder, holds no capture, or a capture has no intrinsics.
    """
    root = Path(root)
    if not root.is_dir():
        raise ViewError(f"{root}: no such folder of captures")
    captures = []
    for folder in sorted(p for p in root.iterdir() if p.is_dir()):
        for depth in sorted(folder.iterdir()):
            if depth.suffix.lower() not in CAPTURE_SUFFIXES or depth.name.lower().endswith((".rgb.png", ".mask.png")):
                continue
            stem = depth.name[: -len(depth.suffix)]
            own = [folder / f"{stem}{suffix}" for suffix in (".json", ".yaml", ".yml")]
            shared = [folder / name for name in CAMERA_NAMES] + [root / name for name in CAMERA_NAMES]
            intrinsics = next((p for p in own + shared if p.is_file()), None)
            if intrinsics is None:
                raise ViewError(f"{depth}: no intrinsics ({stem}.json beside it, or camera.json in {folder} or "
                                f"{root})")
            extra = {kind: folder / f"{stem}.{kind}.png" for kind in ("rgb", "mask")}
            captures.append({"object": folder.name, "name": stem, "depth": str(depth), "intrinsics": str(intrinsics),
                             **{kind: str(path) if path.is_file() else "" for kind, path in extra.items()}})
    if not captures:
        raise ViewError(f"{root}: no capture (expected <object>/<name>.png or .npy)")
    return captures


def _image(path, mode: str) -> np.ndarray:
    try:
        with Image.open(path) as image:
            return np.asarray(image.convert(mode))
    except OSError as error:
        raise ViewError(f"{path}: cannot read the image ({error})") from error


def write_depth(view: View, path, intrinsics_path=None) -> None:
    """The depth image a view corresponds to: a 16-bit PNG in millimetres, and its intrinsics as JSON.

    Each vertex is written at its pixel (``view.pixels``, rounded); pixels without a vertex
    are 0. ``intrinsics_path`` defaults to the PNG's name with ``.json``.
    """
    k = check_intrinsics(view.intrinsics, name=view.name)
    pixels = np.round(view.pixels).astype(np.int64)
    inside = (pixels[:, 0] >= 0) & (pixels[:, 0] < k["width"]) & (pixels[:, 1] >= 0) & (pixels[:, 1] < k["height"])
    millimetres = np.round(view.vertices[:, 2] * 1000.0)
    if not inside.all() or millimetres.max() > np.iinfo(np.uint16).max:
        raise ViewError(f"{view.name}: vertices outside the image or beyond 65.5 m cannot be written as a depth PNG")
    image = np.zeros((k["height"], k["width"]), np.uint16)
    image[pixels[:, 1], pixels[:, 0]] = millimetres.astype(np.uint16)
    path = Path(path)
    Image.fromarray(image).save(path)
    Path(intrinsics_path or path.with_suffix(".json")).write_text(json.dumps(k, indent=1) + "\n")


def fit_intrinsics(points: np.ndarray) -> dict:
    """Pinhole intrinsics of an organized cloud: least squares of its pixel grid against x/z and y/z."""
    valid = np.isfinite(points).all(axis=2) & (points[..., 2] > 0)
    rows, cols = np.nonzero(valid)
    if len(rows) < 3:
        raise ViewError("an organized cloud needs at least 3 valid points to fit its intrinsics")
    p = points[valid]
    (fx, cx), *_ = np.linalg.lstsq(np.column_stack([p[:, 0] / p[:, 2], np.ones(len(p))]), cols, rcond=None)
    (fy, cy), *_ = np.linalg.lstsq(np.column_stack([p[:, 1] / p[:, 2], np.ones(len(p))]), rows, rcond=None)
    return {"fx": float(fx), "fy": float(fy), "cx": float(cx), "cy": float(cy), "width": points.shape[1],
            "height": points.shape[0]}


def read_organized_cloud(path, *, scale: float = 1.0, max_depth_jump: float = MAX_DEPTH_JUMP,
                         view_id: str | None = None, object_id: str = "", label: str = "") -> View:
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
    if not path.is_file():
        raise ViewError(f"{path}: no such point cloud file")
    if path.suffix.lower() == ".pcd":
        points, colors = _read_pcd(path)
    elif path.suffix.lower() == ".ply":
        points, colors = _read_range_ply(path)
    else:
        raise ViewError(f"{path}: unsupported organized cloud {path.suffix!r} (.pcd or a range-map .ply)")
    points = points * float(scale)
    return grid_view(points, colors, max_depth_jump=max_depth_jump, intrinsics=fit_intrinsics(points),
                     view_id=view_id or path.stem, object_id=object_id, label=label,
                     repairs=[f"organized {points.shape[1]}x{points.shape[0]} cloud, not segmented"])


PCD_TYPES = {("F", 4): "<f4", ("F", 8): "<f8", ("U", 1): "u1", ("U", 2): "<u2", ("U", 4): "<u4", ("I", 1): "i1",
             ("I", 2): "<i2", ("I", 4): "<i4"}


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
    if height <= 1:
        raise ViewError(f"{path}: the cloud is not organized (HEIGHT {height}): a view needs its pixel grid")
    if not {"x", "y", "z"} <= set(fields):
        raise ViewError(f"{path}: the cloud has no x y z fields ({' '.join(fields)})")
    unknown = [f"{f} {t}{s}" for f, s, t in zip(fields, sizes, types) if (t, s) not in PCD_TYPES]
    if unknown:
        raise ViewError(f"{path}: PCD field types not read: {', '.join(unknown)}")
    dtype = np.dtype([(f, PCD_TYPES[(t, s)], (c,) if c > 1 else ())
                      for f, s, t, c in zip(fields, sizes, types, counts)])
    if data == "ascii":
        table = np.loadtxt(raw[position:].decode("ascii").splitlines(), ndmin=2)
        cloud = np.zeros(len(table), dtype)
        column = 0
        for f, c in zip(fields, counts):
            cloud[f] = table[:, column] if c == 1 else table[:, column:column + c]
            column += c
    elif data == "binary":
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
        colors = np.stack([(packed >> 16) & 255, (packed >> 8) & 255, packed & 255], axis=-1).reshape(
            height, width, 3) / 255.0
    return points, colors


def _read_range_ply(path: Path) -> tuple[np.ndarray, np.ndarray | None]:
    import trimesh

    try:
        mesh = trimesh.load(path, process=False)
    except Exception as error:  # trimesh raises many kinds on a bad file
        raise ViewError(f"{path}: cannot read the PLY ({error})") from error
    camera = getattr(mesh, "metadata", {}).get("_ply_raw", {}).get("camera")
    if camera is None or not len(camera["data"]):
        raise ViewError(f"{path}: the PLY has no camera element, so its pixel grid is unknown (not organized)")
    c = camera["data"][0]
    axes = np.array([[c[f"{a}_axis{b}"] for b in "xyz"] for a in "xyz"], np.float64)
    local = (np.asarray(mesh.vertices, np.float64) - [c["view_px"], c["view_py"], c["view_pz"]]) @ axes.T
    local[:, 1] *= -1.0  # VCG's camera y is up; a view's is down (z stays forward)
    if not (local[:, 2] > 0).all():
        raise ViewError(f"{path}: vertices behind the PLY's camera")
    angles = local[:, :2] / local[:, 2:]
    # The grid's pitch, from the range map's own edges (MeshLab's focal and pixel size round it off by ~2%)
    faces = np.asarray(mesh.faces)
    if not len(faces):
        raise ViewError(f"{path}: the range map has no faces to find its grid pitch from")
    steps = np.abs(np.diff(angles[faces[:, [0, 1, 2, 0]]], axis=1)).reshape(-1, 2)
    pitch = np.array([np.median(s[s > 0.5 * np.median(s[s > 0])]) for s in steps.T])
    grid = np.round((angles - angles.min(axis=0)) / pitch).astype(np.int64)
    shape = grid.max(axis=0)[::-1] + 1
    cells = grid[:, 1] * shape[1] + grid[:, 0]
    if len(np.unique(cells)) < len(cells):
        raise ViewError(f"{path}: two vertices fall on one pixel: not an organized range map")
    points = np.full((*shape, 3), np.nan)
    points.reshape(-1, 3)[cells] = local
    colors = None
    visual = getattr(mesh, "visual", None)
    if getattr(visual, "kind", None) == "vertex":
        colors = np.full((*shape, 3), 0.5)
        colors.reshape(-1, 3)[cells] = np.asarray(visual.vertex_colors, np.float64)[:, :3] / 255.0
    return points, colors
