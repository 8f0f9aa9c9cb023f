"""Views from depth images, real or rendered, and back (thesis 2.1, 2.3); clouds: :mod:`heatdata.frames.clouds`.

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
from typing import Any

import numpy as np
from PIL import Image

from heatdata.errors import OutputError, ViewError
from heatdata.io.bounded_yaml import load_yaml
from heatdata.io.files import atomic, require_file
from heatdata.typing import StrPath
from heatdata.views.view import INTRINSIC_KEYS, MAX_IMAGE_PIXELS, View, check_intrinsics

log = logging.getLogger(__name__)


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


def grid_view(
    points: np.ndarray,
    colors: np.ndarray | None = None,
    *,
    max_depth_jump: float = MAX_DEPTH_JUMP,
    components: str = "largest",
    **view_fields,
) -> View:
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
        the largest leaves out).
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
        raise ViewError(
            f"{name}: the {int(valid.sum())} valid pixels form no triangle (isolated pixels, or depth "
            f"steps above {max_depth_jump:g} of the depth everywhere)"
        )
    rgb = None if colors is None else np.asarray(colors, np.float64)[valid]
    view = View.from_arrays(vertices, faces, rgb, **view_fields)
    return view.largest_component() if components == "largest" else view


def back_project(depth: np.ndarray, intrinsics: dict) -> np.ndarray:
    """(h, w, 3) camera-frame points of a z-depth image (metres; NaN stays NaN)."""
    rows, cols = np.indices(depth.shape)
    k = intrinsics
    return np.stack([(cols - k["cx"]) / k["fx"] * depth, (rows - k["cy"]) / k["fy"] * depth, depth], axis=-1)


def view_from_depth(
    depth_m: np.ndarray,
    intrinsics: dict,
    rgb: np.ndarray | None = None,
    mask: np.ndarray | None = None,
    *,
    depth_range: tuple[float, float] | None = None,
    max_depth_jump: float = MAX_DEPTH_JUMP,
    view_id: str = "depth",
    object_id: str = "",
    label: str = "",
) -> View:
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
        The pixels within it (with a mask too: the pixels both keep).
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
    depth, k = checked_depth(depth_m, intrinsics, view_id)
    colors = None if rgb is None else checked_rgb(rgb, depth.shape, view_id)
    depth, note = cut_depth(depth, mask, depth_range, view_id)
    log.info("%s: %s", view_id, note)
    return grid_view(
        back_project(depth, k),
        colors,
        max_depth_jump=max_depth_jump,
        intrinsics=k,
        view_id=view_id,
        object_id=object_id,
        label=label,
        repairs=[note],
    )


def checked_depth(depth: np.ndarray, intrinsics: dict, name: str) -> tuple[np.ndarray, dict]:
    """A depth image as (h, w) float64 metres with NaN where there is no reading, and its checked intrinsics.

    Parameters
    ----------
    depth : (h, w) float
        z-depth in metres; NaN, infinite or <= 0 where there is no reading.
    intrinsics : dict
        ``fx, fy, cx, cy, width, height`` matching the image.
    name : str
        The frame, for messages.

    Returns
    -------
    depth : (h, w) float64
        A copy, NaN where there is no reading.
    intrinsics : dict
        :func:`heatdata.views.view.check_intrinsics` of them.
    """
    depth = np.array(depth, dtype=np.float64)
    if depth.ndim != 2:
        raise ViewError(f"{name}: a depth image is (h, w), got shape {depth.shape}")
    k = check_intrinsics(intrinsics, depth.shape, name)
    depth[~np.isfinite(depth) | (depth <= 0)] = np.nan
    return depth, k


def cut_depth(
    depth: np.ndarray, mask: np.ndarray | None, depth_range: tuple[float, float] | None, name: str
) -> tuple[np.ndarray, str]:
    """A checked depth image (:func:`checked_depth`) kept where ``mask`` is true and within ``depth_range``.

    Parameters
    ----------
    depth : (h, w) float64
        Metres, NaN where there is no reading.
    mask : (h, w) bool, optional
        The pixels to keep.
    depth_range : (near, far) metres, optional
        The depths to keep (with a mask too: the pixels both keep).
    name : str
        The frame, for messages.

    Returns
    -------
    depth : (h, w) float64
        A copy, NaN outside the cut.
    note : str
        What was kept, for the view's or the answer's repairs.

    Raises
    ------
    ViewError
        A mask of another size, a range that is not ``0 <= near < far``, no reading at all or none left.
    """
    depth = depth.copy()
    readings = int(np.isfinite(depth).sum())
    if readings == 0:
        raise ViewError(f"{name}: the depth image has no valid pixel (all zero, NaN or negative)")
    kept = []
    if mask is not None:
        mask = np.asarray(mask)
        if mask.shape != depth.shape:
            raise ViewError(f"{name}: the mask is {mask.shape[1::-1]} but the depth image is {depth.shape[::-1]}")
        depth[~mask.astype(bool)] = np.nan
        kept.append("the mask")
    if depth_range is not None:
        near, far = map(float, depth_range)
        if not 0 <= near < far:
            raise ViewError(f"{name}: depth_range must be (near, far) with 0 <= near < far, got {depth_range}")
        depth[(depth < near) | (depth > far)] = np.nan
        kept.append(f"depth {near:g}-{far:g} m")
    left = int(np.isfinite(depth).sum())
    note = (
        f"segmented by {' and '.join(kept)}: {left} of {readings} readings"
        if kept
        else f"not segmented: all {readings} readings"
    )
    if not np.isfinite(depth).any():
        raise ViewError(f"{name}: no valid pixel is left after segmentation ({note.split(':', maxsplit=1)[0]})")
    return depth, note


def checked_rgb(rgb: np.ndarray, shape: tuple[int, int], name: str) -> np.ndarray:
    """A colour image registered to a depth image of ``shape``, as (h, w, 3) float64 in [0, 1] (8-bit divided
    by 255, an alpha channel dropped); a ViewError for another size or floats outside [0, 1]."""
    rgb = np.asarray(rgb)
    if rgb.ndim == 3 and rgb.shape[2] == 4:
        rgb = rgb[..., :3]
    if rgb.shape != (*shape, 3):
        raise ViewError(
            f"{name}: the RGB image is {rgb.shape[1::-1] if rgb.ndim >= 2 else rgb.shape} but the "
            f"depth image is {shape[::-1]} (register the colour to the depth first)"
        )
    if rgb.dtype.kind in "ui":
        return rgb.astype(np.float64) / 255.0
    rgb = rgb.astype(np.float64)
    if not (np.isfinite(rgb).all() and rgb.min() >= 0 and rgb.max() <= 1):
        raise ViewError(f"{name}: a float RGB image must lie in [0, 1]")
    return rgb


#: the keys a 3 x 3 camera matrix is read from: BOP's ``cam_K``, a YAML ``INTRINSICS:`` list (PoseCNN, YCB-Video's
#: ``meta``) or a plain ``K``; nine numbers, row-major
CAMERA_MATRIX_KEYS = ("cam_K", "INTRINSICS", "K")


def read_intrinsics(path: StrPath, shape: tuple[int, int] | None = None) -> dict:
    """A pinhole camera from a JSON (``.json``) or YAML file.

    The file holds ``fx, fy, cx, cy, width, height``, or a 3 x 3 camera matrix as nine row-major numbers under
    ``cam_K`` (BOP), ``INTRINSICS`` (YCB-Video's ``meta.yml``) or ``K``, flat or nested. A matrix carries no image
    size: the file's ``width`` and ``height`` or, failing those, the image's ``shape`` give it.

    Parameters
    ----------
    path : str or Path
        The intrinsics file.
    shape : (h, w), optional
        The image the camera took, for a camera matrix without ``width`` and ``height``.

    Returns
    -------
    dict
        ``fx, fy, cx, cy`` as floats, ``width, height`` as ints (:func:`heatdata.views.view.check_intrinsics`).

    Raises
    ------
    ViewError
        The file is missing, unreadable or larger than 1 MB; a matrix that is not nine numbers, has skew or a last
        row other than ``0 0 1``; no image size.
    """
    path = require_file(path, "intrinsics file", ViewError)
    if path.stat().st_size > 1 << 20:
        raise ViewError(f"{path}: {path.stat().st_size >> 20} MB is not an intrinsics file (six numbers)")
    try:
        text = path.read_text()
        if path.suffix.lower() == ".json":
            data = json.loads(text)
        else:  # YAML reads 5.8e2 as text; aliases are refused (a few hundred bytes of them expand to gigabytes)
            data = load_yaml(text, str(path), ViewError)
    except (OSError, ValueError, RecursionError) as error:
        raise ViewError(f"{path}: cannot read the intrinsics ({' '.join(str(error).split())[:300]})") from None
    if not isinstance(data, dict):
        raise ViewError(
            f"{path}: the intrinsics must be a mapping of {', '.join(INTRINSIC_KEYS)} or a camera matrix "
            f"({' or '.join(CAMERA_MATRIX_KEYS)})"
        )
    matrix_key = next((key for key in CAMERA_MATRIX_KEYS if key in data), None)
    if matrix_key is not None and not all(key in data for key in ("fx", "fy", "cx", "cy")):
        data = {**_from_camera_matrix(data[matrix_key], f"{path}: {matrix_key}"), **_image_size(data, shape, str(path))}
    return check_intrinsics(data, name=str(path))


def _from_camera_matrix(values, name: str) -> dict:
    """``fx, fy, cx, cy`` of a row-major 3 x 3 camera matrix (nine numbers, flat or as three rows)."""
    try:
        k = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise ViewError(f"{name}: a camera matrix is nine numbers, row-major") from None
    if k.size != 9:
        raise ViewError(f"{name}: a camera matrix is nine numbers, row-major; got {k.size}")
    k = k.reshape(3, 3)
    if not np.isfinite(k).all():
        raise ViewError(f"{name}: the camera matrix holds a number that is not finite")
    if k[0, 1] != 0 or not np.allclose(k[2], [0, 0, 1]) or k[1, 0] != 0:
        raise ViewError(f"{name}: a pinhole camera matrix is [[fx 0 cx] [0 fy cy] [0 0 1]]; got {k.tolist()}")
    return {"fx": k[0, 0], "fy": k[1, 1], "cx": k[0, 2], "cy": k[1, 2]}


def _image_size(data: dict, shape: tuple[int, int] | None, name: str) -> dict:
    """The image's ``width`` and ``height``: the file's own, else the image's ``shape`` (h, w)."""
    if "width" in data and "height" in data:
        return {"width": data["width"], "height": data["height"]}
    if shape is None:
        raise ViewError(
            f"{name}: a camera matrix carries no image size: give width and height beside it (an unorganized cloud "
            "has no image to take them from)"
        )
    return {"width": int(shape[1]), "height": int(shape[0])}


def read_depth(
    path: StrPath,
    intrinsics_path: StrPath | None,
    rgb_path: StrPath | None = None,
    mask_path: StrPath | None = None,
    **kwargs: Any,
) -> View:
    """:func:`view_from_depth` of files: a 16-bit PNG in millimetres or a float ``.npy`` in metres.

    ``rgb_path``: a colour image of the same size; ``mask_path``: an image whose non-zero
    pixels are the object's. Other keywords go to :func:`view_from_depth`.

    Parameters
    ----------
    path : str or Path
        A 16-bit PNG (millimetres) or a float ``.npy`` (metres).
    intrinsics_path : str or Path
        JSON or YAML with ``fx, fy, cx, cy, width, height``.
    rgb_path : str or Path, optional
        A colour image of the same size.
    mask_path : str or Path, optional
        An image whose non-zero pixels are the object's.
    **kwargs
        As for :func:`view_from_depth`.

    Returns
    -------
    View
        The view in the camera's frame.
    """
    path = Path(path)
    depth, rgb, intrinsics = read_depth_frame(path, intrinsics_path, rgb_path)
    mask = None if mask_path is None else read_image(mask_path, "mask", "L") > 0
    kwargs.setdefault("view_id", path.stem)
    return view_from_depth(depth, intrinsics, rgb, mask, **kwargs)


def read_depth_frame(
    path: StrPath, intrinsics_path: StrPath | None, rgb_path: StrPath | None = None
) -> tuple[np.ndarray, np.ndarray | None, dict]:
    """A depth frame's files as arrays: the depth in metres, its colour and its intrinsics.

    Parameters
    ----------
    path : str or Path
        A 16-bit PNG (millimetres) or a float ``.npy`` (metres).
    intrinsics_path : str or Path
        JSON or YAML with ``fx, fy, cx, cy, width, height`` (needed).
    rgb_path : str or Path, optional
        A colour image of the same size.

    Returns
    -------
    depth : (h, w) float64
        Metres (0 or NaN: no reading).
    rgb : (h, w, 3) uint8 or None
    intrinsics : dict
    """
    if not intrinsics_path:
        raise ViewError(f"{path}: a depth image needs --intrinsics (JSON or YAML with fx, fy, cx, cy, width, height)")
    depth = read_depth_image(path)
    rgb = None if not rgb_path else read_image(rgb_path, "colour image", "RGB")
    return depth, rgb, read_intrinsics(intrinsics_path, depth.shape)


def read_depth_image(path: StrPath) -> np.ndarray:
    """A depth image in metres: a 16-bit PNG in millimetres or a float ``.npy`` in metres (0 or NaN: no reading).

    Parameters
    ----------
    path : str or Path
        The ``.png`` or ``.npy``.

    Returns
    -------
    (h, w) float64
        Metres.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".npy":
        return _read_npy(path)
    if suffix == ".png":
        return read_image(path, "depth image", "depth") / 1000.0
    raise ViewError(
        f"{path}: unsupported depth file {suffix!r} (a 16-bit PNG in millimetres or a float .npy "
        "in metres; convert EXR to .npy)"
    )


DEPTH_MODES = ("I;16", "I;16B", "I;16L", "I")


def read_image(path: StrPath, what: str, mode: str) -> np.ndarray:
    """An image file as an array, refused in one line when it is missing, corrupt, truncated or too large.

    Every image heatdata reads from a sensor goes through here: depth PNGs, colour images and masks.

    Parameters
    ----------
    path : str or Path
        A PNG (or any format Pillow reads).
    what : str
        What the image is, for messages (``"mask"``).
    mode : {"depth", "RGB", "L"}
        ``"depth"``: a 16-bit image, returned as (h, w) float64 of its integer values (any other mode is
        refused); ``"RGB"``: (h, w, 3) uint8; ``"L"``: (h, w) uint8 grey (a mask).

    Returns
    -------
    numpy.ndarray
        The pixels.

    Raises
    ------
    ViewError
        No such file, not an image Pillow can decode, more pixels than ``MAX_IMAGE_PIXELS``, or (``"depth"``) not
        16-bit.
    """
    path = require_file(path, f"{what} file", ViewError)
    try:
        with Image.open(path) as image:
            if image.size[0] * image.size[1] > MAX_IMAGE_PIXELS:
                raise ViewError(
                    f"{path}: the {what} is {image.size[0]}x{image.size[1]} pixels, above the cap of "
                    f"{MAX_IMAGE_PIXELS / 1e6:.1f} Mpixel"
                )
            if mode == "depth":
                if image.format != "PNG":  # a 32-bit TIFF renamed .png read as millimetres gives kilometres
                    raise ViewError(f"{path}: a depth image ending in .png must be a PNG, this is {image.format}")
                if image.mode not in DEPTH_MODES:
                    raise ViewError(f"{path}: a depth PNG must be 16-bit (millimetres), got mode {image.mode}")
                depth = np.asarray(image, dtype=np.float64)
                if depth.size and (depth.min() < 0 or depth.max() > 65535):
                    raise ViewError(f"{path}: a depth PNG holds 16-bit millimetres, got values up to {depth.max():g}")
                return depth
            return np.asarray(image.convert(mode))
    except (OSError, ValueError, SyntaxError, Image.DecompressionBombError) as error:  # Pillow's errors
        raise ViewError(f"{path}: cannot read the {what} ({error})") from None


def _read_npy(path: Path) -> np.ndarray:
    """A float ``.npy`` depth image in metres; its header is checked before its data are read."""
    require_file(path, "depth file", ViewError)
    try:
        depth = np.load(path, mmap_mode="r", allow_pickle=False)
    except Exception as error:  # numpy parses the header with ast and tokenize: many kinds on a damaged one
        raise ViewError(f"{path}: not a readable .npy depth image ({type(error).__name__}: {error})") from None
    if not isinstance(depth, np.ndarray) or depth.dtype.kind != "f":
        raise ViewError(f"{path}: a .npy depth image holds float metres, got {getattr(depth, 'dtype', depth)}")
    if depth.ndim != 2 or depth.size > MAX_IMAGE_PIXELS:
        raise ViewError(
            f"{path}: a depth image is (h, w) of at most {MAX_IMAGE_PIXELS / 1e6:.1f} Mpixel, got {depth.shape}"
        )
    try:
        return np.array(depth, dtype=np.float64)
    except OSError as error:
        raise ViewError(f"{path}: the .npy depth image cannot be read ({error})") from None


def write_depth(view: View, path: StrPath, intrinsics_path: StrPath | None = None) -> None:
    """The depth image a view corresponds to: a 16-bit PNG in millimetres, and its intrinsics as JSON.

    Each vertex is written at its pixel (``view.pixels``, rounded); pixels without a vertex
    are 0. ``intrinsics_path`` defaults to the PNG's name with ``.json``.

    Parameters
    ----------
    view : View
        A view with pixel coordinates (rendered, or read from a depth frame).
    path : str or Path
        The PNG to write.
    intrinsics_path : str or Path, optional
        Its intrinsics' JSON; default ``path`` with ``.json``.

    Raises
    ------
    OutputError
        ``path`` does not end in ``.png`` (a depth image in millimetres needs a lossless 16-bit format), or a
        file cannot be written. Missing folders are created.
    ViewError
        The view has no intrinsics, or vertices outside the image or beyond 65.5 m.
    """
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise OutputError(f"{path}: a depth image is written as a 16-bit .png in millimetres (lossless)")
    intrinsics_path = Path(intrinsics_path or path.with_suffix(".json"))
    if intrinsics_path.suffix.lower() != ".json":
        raise OutputError(f"{intrinsics_path}: the intrinsics are written as .json")
    k = check_intrinsics(view.intrinsics, name=view.name)
    pixels = np.round(view.pixels).astype(np.int64)
    inside = (pixels[:, 0] >= 0) & (pixels[:, 0] < k["width"]) & (pixels[:, 1] >= 0) & (pixels[:, 1] < k["height"])
    millimetres = np.round(view.vertices[:, 2] * 1000.0)
    if not inside.all() or millimetres.max() > np.iinfo(np.uint16).max:
        raise ViewError(f"{view.name}: vertices outside the image or beyond 65.5 m cannot be written as a depth PNG")
    image = np.zeros((k["height"], k["width"]), np.uint16)
    image[pixels[:, 1], pixels[:, 0]] = millimetres.astype(np.uint16)
    with atomic(path) as temporary:
        Image.fromarray(image).save(temporary)
    with atomic(intrinsics_path) as temporary:
        temporary.write_text(json.dumps(k, indent=1) + "\n")


def pixels_of(points: np.ndarray, k: dict) -> tuple[np.ndarray, np.ndarray]:
    """The pixel ``(u, v)`` each camera-frame point projects to (rounded), and which land inside the image.

    Parameters
    ----------
    points : (n, 3) float
    k : dict
        ``fx, fy, cx, cy, width, height``.

    Returns
    -------
    pixel : (n, 2) int64
        Zero where outside.
    inside : (n,) bool
    """
    z = np.where(points[:, 2] > 0, points[:, 2], np.nan)
    with np.errstate(invalid="ignore"):
        u = np.round(k["fx"] * points[:, 0] / z + k["cx"])
        v = np.round(k["fy"] * points[:, 1] / z + k["cy"])
    inside = np.isfinite(u) & np.isfinite(v) & (u >= 0) & (u < k["width"]) & (v >= 0) & (v < k["height"])
    pixel = np.zeros((len(points), 2), dtype=np.int64)
    pixel[inside] = np.stack([u[inside], v[inside]], axis=1).astype(np.int64)
    return pixel, inside


def nearest_readings(depth: np.ndarray, size: int) -> np.ndarray:
    """Each pixel's nearest reading within a ``size`` x ``size`` window (NaN where none): a point that projects just
    beside an object's outline, onto the background or a pixel the sensor dropped, is compared with the object.

    Parameters
    ----------
    depth : (h, w) float
        z-depth, NaN where the sensor gave no reading.
    size : int
        The window's side, pixels (odd).

    Returns
    -------
    (h, w) float64
    """
    from scipy.ndimage import minimum_filter

    out = np.full(depth.shape, np.nan)
    rows, cols = np.flatnonzero(np.isfinite(depth).any(axis=1)), np.flatnonzero(np.isfinite(depth).any(axis=0))
    if not len(rows):
        return out
    half = size // 2  # only the box of the readings, grown by half a window, can have one within its window
    v0, v1 = max(rows[0] - half, 0), min(rows[-1] + half + 1, depth.shape[0])
    u0, u1 = max(cols[0] - half, 0), min(cols[-1] + half + 1, depth.shape[1])
    box = depth[v0:v1, u0:u1]
    nearest = minimum_filter(np.where(np.isfinite(box), box, np.inf), size=size, mode="constant", cval=np.inf)
    out[v0:v1, u0:u1] = np.where(np.isfinite(nearest), nearest, np.nan)
    return out
