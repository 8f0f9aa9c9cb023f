"""Cyberware range scans as the Stanford 3D Scanning Repository ships them: a PLY whose ``range_grid`` element
lists, for each cell of the scanner's ``num_rows`` x ``num_cols`` grid, the vertex seen there (none where the laser
saw nothing), and no faces.

The scanner sweeps its columns linearly (``x`` grows by a fixed step along a row) and looks along ``-z`` of the
file, ``y`` up. The grid is put in a camera's frame (x right, y down, z forward) by a half turn about ``x`` and a
shift along the view, :data:`STANDOFF_PITCHES` column steps in front of the camera: there a depth step of 2% of the
depth (:data:`heatdata.views.depth.MAX_DEPTH_JUMP`, the triangulation's rule for a Kinect at 1 m, 10 of its pixel
spacings) is 10 of the scan's column steps too, so the scan is triangulated by the same rule as any range map.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from heatdata.errors import ViewError
from heatdata.views.view import MAX_IMAGE_PIXELS

STANDOFF_PITCHES = 500.0  # the grid's distance from the camera, in column steps (a Kinect's 1 m is 525 pixels)


def is_range_grid(path: Path) -> bool:
    """Whether a PLY's header declares a ``range_grid`` element."""
    return ply_declares(path, "range_grid")


def ply_declares(path: Path, element: str) -> bool:
    """Whether a PLY's header (its first 200 lines) declares ``element`` (``range_grid``, MeshLab's ``camera``)."""
    declaration = f"element {element}".encode()
    with open(path, "rb") as file:
        for _ in range(200):
            line = file.readline(4096).strip()
            if line.startswith(declaration):
                return True
            if not line or line == b"end_header":
                return False
    return False


def read_range_grid(path: Path) -> tuple[np.ndarray, np.ndarray | None]:
    """A ``range_grid`` PLY's points on their grid, in a camera's frame (module docstring).

    Parameters
    ----------
    path : Path
        The PLY (ASCII or binary).

    Returns
    -------
    points : (num_rows, num_cols, 3) float64
        File units, NaN where the scanner saw nothing; row 0 is the top of the scan.
    colors : None
        Cyberware scans have no colour.

    Raises
    ------
    ViewError
        No ``num_cols``/``num_rows``, a grid whose size is not ``num_rows x num_cols``, or an index outside the
        vertices.
    """
    import trimesh

    size = _grid_size(path)
    try:
        cloud = trimesh.load(path, process=False)
        raw = cloud.metadata["_ply_raw"]
        cells = raw["range_grid"]["data"]["vertex_indices"]
        vertices = np.asarray(cloud.vertices, np.float64)
    except Exception as error:  # trimesh raises many kinds on a bad file
        raise ViewError(f"{path}: cannot read the range grid PLY ({type(error).__name__}: {error})") from None
    rows, cols = size
    if len(cells) != rows * cols:
        raise ViewError(f"{path}: the range_grid has {len(cells)} cells, but num_rows x num_cols is {rows}x{cols}")
    counts = np.fromiter((len(c) for c in cells), np.int64, len(cells))
    if counts.max(initial=0) > 1:
        raise ViewError(f"{path}: a range_grid cell lists {counts.max()} vertices; a range scan sees one per cell")
    seen = np.flatnonzero(counts == 1)
    index = np.fromiter((cells[i][0] for i in seen), np.int64, len(seen))
    if len(index) == 0:
        raise ViewError(f"{path}: the range grid is empty (no cell saw a vertex)")
    if index.min() < 0 or index.max() >= len(vertices):
        raise ViewError(f"{path}: a range_grid cell names a vertex outside the {len(vertices)} vertices")
    grid = np.full((rows * cols, 3), np.nan)
    grid[seen] = vertices[index]
    grid = grid.reshape(rows, cols, 3)[::-1]  # the file's row 0 is the bottom (y up)
    pitch = float(np.nanmedian(np.abs(np.diff(grid[..., 0], axis=1))))
    if not (np.isfinite(pitch) and pitch > 0):
        raise ViewError(f"{path}: the range grid's columns have no step along x (no two neighbours seen)")
    camera = grid * np.array([1.0, -1.0, -1.0])
    camera[..., 2] += STANDOFF_PITCHES * pitch - np.nanmin(camera[..., 2]) + pitch
    return camera, None


def _grid_size(path: Path) -> tuple[int, int]:
    """``num_rows, num_cols`` from the header's ``obj_info`` lines."""
    info: dict[str, str] = {}
    with open(path, "rb") as file:
        for _ in range(200):
            line = file.readline(4096).decode("ascii", "replace").split()
            if not line or line[0] == "end_header":
                break
            if line[0] == "obj_info" and len(line) >= 3:
                info[line[1]] = line[2]
    try:
        rows, cols = int(info["num_rows"]), int(info["num_cols"])
    except (KeyError, ValueError):
        raise ViewError(f"{path}: a range_grid PLY needs obj_info num_rows and num_cols in its header") from None
    if not (rows > 0 and cols > 0 and rows * cols <= MAX_IMAGE_PIXELS):
        raise ViewError(f"{path}: a {cols}x{rows} range grid is not read (at most {MAX_IMAGE_PIXELS} cells)")
    return rows, cols
