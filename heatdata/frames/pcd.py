"""PCD files as PCL writes them, read and written through ``pypcd4``: ``DATA ascii``, ``binary`` and
``binary_compressed`` (LZF), any fields, organized (``HEIGHT`` > 1) or not."""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from heatdata.errors import ViewError
from heatdata.io.files import atomic
from heatdata.typing import StrPath
from heatdata.views.depth import pixels_of
from heatdata.views.view import MAX_IMAGE_PIXELS, View

log = logging.getLogger(__name__)

COLOUR_FIELDS = ("rgb", "rgba")


@dataclass
class PcdCloud:
    """A PCD file's points.

    Attributes
    ----------
    points : (height, width, 3) float64
        x y z in the file's units, NaN where there is no reading (an unorganized cloud has ``height`` 1).
    colors : (height, width, 3) float64 in [0, 1] or None
        From a packed ``rgb`` or ``rgba`` field.
    fields : dict of str to (height, width) ndarray
        Every other one-number field (``label``, ``normal_x``, ``intensity`` ...).
    organized : bool
        ``HEIGHT`` > 1: the points lie on the sensor's pixel grid.
    """

    points: np.ndarray
    colors: np.ndarray | None
    fields: dict[str, np.ndarray]
    organized: bool


def read_pcd(path: StrPath) -> PcdCloud:
    """A PCD file of any ``DATA`` kind (thesis 2.1's sensor input, as PCL's ``io::savePCDFile`` writes it).

    Parameters
    ----------
    path : str or Path
        The ``.pcd``.

    Returns
    -------
    PcdCloud

    Raises
    ------
    ViewError
        One line naming the file and the problem: not a PCD header, an unknown DATA kind, truncated or corrupt
        data, ``POINTS`` that is not ``WIDTH x HEIGHT``, no ``x y z`` fields, more than ``MAX_IMAGE_PIXELS`` points.
    """
    from pypcd4 import PointCloud

    path = Path(path)
    header, offset = _header(path)
    fields, sizes, types, counts = (header.get(key, []) for key in ("FIELDS", "SIZE", "TYPE", "COUNT"))
    counts = counts or ["1"] * len(fields)
    if not len(fields) == len(sizes) == len(types) == len(counts):
        raise ViewError(
            f"{path}: the PCD header gives {len(fields)} FIELDS, {len(sizes)} SIZE, {len(types)} TYPE and "
            f"{len(counts)} COUNT entries; they must match"
        )
    if "POINTS" not in header:
        raise ViewError(f"{path}: the PCD header has no POINTS line (PCL writes one: WIDTH x HEIGHT)")
    try:
        width, height, count = (int(header.get(key, ["?"])[0]) for key in ("WIDTH", "HEIGHT", "POINTS"))
        itemsize = sum(int(size) * int(times) for size, times in zip(sizes, counts))
    except ValueError:
        raise ViewError(
            f"{path}: the PCD header's WIDTH, HEIGHT, POINTS, SIZE or COUNT is not a whole number"
        ) from None
    if not 0 < width * height <= MAX_IMAGE_PIXELS:
        raise ViewError(f"{path}: a {width}x{height} grid is not read (1 to {MAX_IMAGE_PIXELS} points, a 4K frame)")
    if width * height != count:
        raise ViewError(f"{path}: the PCD header says {count} POINTS for a grid of WIDTH {width} x HEIGHT {height}")
    data = header.get("DATA", ["?"])[0].lower()
    if data not in ("ascii", "binary", "binary_compressed"):
        raise ViewError(f"{path}: PCD DATA {data!r} is not a kind PCL writes (ascii, binary, binary_compressed)")
    available = path.stat().st_size - offset
    if data == "binary" and available < itemsize * count:
        raise ViewError(f"{path}: truncated: {available} bytes of data for {width}x{height} points of {itemsize} bytes")
    try:
        cloud = PointCloud.from_path(path)
    except (ValueError, RuntimeError, TypeError, KeyError, OSError, EOFError) as error:  # pydantic's: a ValueError
        if data == "ascii":
            raise ViewError(f"{path}: {_ascii_problem(path, offset, len(fields), counts)}") from None
        reason = str(error).splitlines()[0] if str(error) else type(error).__name__
        raise ViewError(f"{path}: cannot read the PCD ({data} data: {reason})") from None
    except Exception as error:  # the LZF decoder and struct raise their own kinds on a damaged stream
        raise ViewError(f"{path}: cannot read the PCD's {data} data ({type(error).__name__}: {error})") from None
    table = np.atleast_1d(cloud.pc_data)  # one point of an ascii block comes back as a 0-d array
    if len(table) != count:
        raise ViewError(f"{path}: truncated: {len(table)} of the {count} points the header announces")
    names = table.dtype.names or ()
    if not {"x", "y", "z"} <= set(names):
        raise ViewError(f"{path}: the cloud has no x y z fields ({' '.join(names)})")
    shape = (height, width)
    points = np.stack([table[a].astype(np.float64) for a in "xyz"], axis=-1).reshape(*shape, 3)
    colors = None
    colour = next((f for f in COLOUR_FIELDS if f in names), None)
    if colour is not None:
        packed = np.ascontiguousarray(table[colour])
        packed = packed.view(np.uint32) if packed.dtype.itemsize == 4 else packed.astype(np.uint32)
        colors = PointCloud.decode_rgb(packed).reshape(*shape, 3) / 255.0
    others = {f: np.asarray(table[f]).reshape(shape) for f in names if f not in ("x", "y", "z", colour)}
    if not np.isfinite(points).all(axis=-1).any():
        raise ViewError(f"{path}: no point of the {count} has finite x y z (all NaN): an empty frame")
    return PcdCloud(points, colors, others, organized=height > 1)


def _header(path: Path) -> tuple[dict[str, list[str]], int]:
    """The PCD header's lines up to ``DATA`` as a mapping, and where the data start (checked before pypcd4 reads
    the data)."""
    header: dict[str, list[str]] = {}
    with open(path, "rb") as file:
        for _ in range(64):
            line = file.readline(4096)
            if not line:
                break
            text = line.decode("ascii", "replace").strip()
            if not text or text.startswith("#"):
                continue
            key, *values = text.split()
            header[key.upper()] = values
            if key.upper() == "DATA":
                return header, file.tell()
    raise ViewError(f"{path}: not a PCD file (no DATA line in its header)")


def _ascii_problem(path: Path, offset: int, fields: int, counts: list[str]) -> str:
    """Why ASCII PCD data do not read: rows of the wrong length, or not numbers."""
    numbers = sum(int(c) for c in counts)
    with open(path, "rb") as file:
        file.seek(offset)
        for line in file:
            row = line.split()
            if not row:
                continue
            if len(row) != numbers:
                return f"the PCD's ASCII rows have {len(row)} numbers, its header {numbers} for {fields} fields"
            try:
                [float(value) for value in row]
            except ValueError:
                return f"the PCD's ASCII data are not rows of numbers (a row reads {line[:60]!r})"
    return "the PCD's ASCII data do not read as its header describes"


def write_pcd(
    path: StrPath, points: np.ndarray, colors: np.ndarray | None = None, *, data: str = "binary_compressed"
) -> Path:
    """Write an organized cloud as PCL reads it: ``x y z`` (float32, NaN = no reading) and a packed ``rgb``.

    Parameters
    ----------
    path : str or Path
        The ``.pcd`` to write (atomically).
    points : (height, width, 3) float
        Camera-frame points in metres.
    colors : (height, width, 3) float in [0, 1] or uint8, optional
        Their colours.
    data : {"binary_compressed", "binary", "ascii"}
        PCL's DATA kind.

    Returns
    -------
    Path
    """
    from pypcd4 import Encoding, PointCloud

    points = np.asarray(points, np.float32)
    height, width = points.shape[:2]
    columns = [points[..., i].ravel() for i in range(3)]
    fields, types = ["x", "y", "z"], [np.float32] * 3
    if colors is not None:
        rgb = np.asarray(colors)
        rgb = np.round(rgb * 255) if rgb.dtype.kind == "f" else rgb
        columns.append(PointCloud.encode_rgb(rgb.reshape(-1, 3).astype(np.uint8)))
        fields.append("rgb")
        types.append(np.float32)
    cloud = PointCloud.from_points(columns, fields, types)
    cloud.metadata = cloud.metadata.derive(width=width, height=height)
    with atomic(path) as temporary:
        cloud.save(temporary, encoding=Encoding(data))
    return Path(path)


def write_view_pcd(view: View, path: StrPath) -> Path:
    """A view as the organized cloud a sensor would have given: each vertex on its pixel of the view's camera, NaN
    on the other pixels, with its colour (:func:`write_pcd`, binary_compressed).

    Parameters
    ----------
    view : View
        Camera-frame vertices with intrinsics.
    path : str or Path
        The ``.pcd`` to write.

    Returns
    -------
    Path
    """
    k = view.intrinsics
    pixels, inside = pixels_of(view.vertices, k)
    points = np.full((int(k["height"]), int(k["width"]), 3), np.nan)
    colors = np.zeros(points.shape)
    order = np.flatnonzero(inside)[np.argsort(-view.vertices[inside, 2], kind="stable")]  # the nearest written last
    points[pixels[order, 1], pixels[order, 0]] = view.vertices[order]
    colors[pixels[order, 1], pixels[order, 0]] = np.clip(view.colors[order], 0.0, 1.0)
    return write_pcd(path, points, colors)
