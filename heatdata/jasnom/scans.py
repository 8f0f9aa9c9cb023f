"""Real range scans as JASNOM's input: a scan file as a mesh in its camera's frame, its loops classed (thesis 7.5).

A real scan's mesh has more boundary loops than a cut half: besides the silhouette, where the surface turns away from
the scanner, every dark or grazing patch the laser missed leaves a hole with a loop of its own. Only the silhouette
is the seam JASNOM closes. On a scan triangulated on its grid the two kinds are told apart in the image plane, where
the mesh lies flat: the boundary of one connected piece runs round its outside one way and round each hole the other,
so the outer loop is the one that encloses the most projected area, and the others are holes.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from heatdata.errors import StitchError
from heatdata.io.models import Model
from heatdata.jasnom.boundary import Boundary, boundaries
from heatdata.typing import StrPath

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class ScanLoops:
    """A scan's boundary loops, classed.

    Attributes
    ----------
    outer : Boundary
        The silhouette: the loop that encloses the scan in its camera's image.
    holes : list of Boundary
        Every other loop (the outlines of what the scanner missed inside the silhouette), longest first.
    """

    outer: Boundary
    holes: list[Boundary]


def is_scan_file(path: StrPath) -> bool:
    """Whether ``path`` is a point cloud on a scanner's grid (a PCD, or a PLY with a ``range_grid`` or a camera)
    rather than a mesh file."""
    from heatdata.frames.range_grid import ply_declares

    path = Path(path)
    if path.suffix.lower() == ".pcd":
        return True
    if path.suffix.lower() != ".ply" or not path.is_file():
        return False
    return ply_declares(path, "range_grid") or ply_declares(path, "camera")


def read_scan(path: StrPath, *, scale: float = 1.0, intrinsics: dict | None = None) -> Model:
    """A scan file as a mesh in its camera's frame (camera at the origin, z forward), its largest piece.

    Parameters
    ----------
    path : str or Path
        A PCD (organized, or unorganized with ``intrinsics``), a Cyberware ``range_grid`` PLY or a MeshLab range
        map (:func:`heatdata.frames.clouds.read_organized_cloud`).
    scale : float
        File units to metres.
    intrinsics : dict, optional
        An unorganized PCD's camera.

    Returns
    -------
    Model
        Triangulated on the scanner's grid; its faces face the camera.
    """
    from heatdata.frames.clouds import read_organized_cloud

    view = read_organized_cloud(path, scale=scale, intrinsics=intrinsics)
    model = Model.untextured(Path(path).stem, view.vertices, view.faces, view.colors[view.faces], source=str(path))
    return model


def scan_loops(model: Model, loops: list[Boundary] | None = None) -> ScanLoops:
    """The outer loop and the holes of a scan in its camera's frame (module docstring).

    Parameters
    ----------
    model : Model
        One connected piece, triangulated on a grid seen from the origin (every vertex at z > 0).
    loops : list of Boundary, optional
        ``model``'s loops when the caller has them already (:func:`heatdata.jasnom.boundary.boundaries`).

    Returns
    -------
    ScanLoops

    Raises
    ------
    StitchError
        A vertex at or behind the camera (not a scan in its camera's frame), or a closed mesh.
    """
    if not np.all(model.vertices[:, 2] > 0):
        raise StitchError(
            f"{model.name}: a vertex lies at or behind the camera (z <= 0): not a scan in its camera's frame"
        )
    loops = boundaries(model) if loops is None else loops
    areas = np.array([abs(_projected_area(model.vertices[b.loop])) for b in loops])
    outer = int(np.argmax(areas))
    holes = [b for k, b in enumerate(loops) if k != outer]
    if holes:
        log.info(
            "%s: the silhouette (%d vertices) and %d hole(s) inside it (%d vertices in all)",
            model.name,
            len(loops[outer].loop),
            len(holes),
            sum(len(b.loop) for b in holes),
        )
    return ScanLoops(outer=loops[outer], holes=holes)


def _projected_area(points: np.ndarray) -> float:
    """The signed area of a closed polygon of camera-frame points in the image plane (x / z, y / z)."""
    u, v = points[:, 0] / points[:, 2], points[:, 1] / points[:, 2]
    return 0.5 * float(np.dot(u, np.roll(v, -1)) - np.dot(np.roll(u, -1), v))
