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

from heatdata.core.mesh import boundary_loops, component_labels
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


def close_holes(model: Model, max_edges: int) -> tuple[Model, int]:
    """``model`` with every hole of at most ``max_edges`` boundary edges filled by pymeshlab's
    ``meshing_close_holes`` (no new vertices; self-intersecting patches refused), as after a stitch of scans whose
    scanner missed patches inside their silhouettes.

    Each new face takes its corners' colours from a face already at that vertex; textures and the existing faces are
    kept as they were. A patch that would give an edge more than two faces (holes that meet at a vertex, patched over
    each other) is left out, and its holes stay open: on Stanford's ``bun000``, 18 of the 30 holes are closed at any
    length from 30 edges, and pymeshlab's patches of two more were left out.

    Parameters
    ----------
    model : Model
    max_edges : int
        The longest hole to fill, in boundary edges (at least 3).

    Returns
    -------
    closed : Model
        The existing faces first, in their order, then the patches'; ``repairs`` says how many holes were filled.
    filled : int
        Holes filled.

    Raises
    ------
    StitchError
        ``max_edges`` below 3.
    """
    import pymeshlab

    if not (int(max_edges) == max_edges and max_edges >= 3):
        raise StitchError(f"the longest hole to close must be a whole number of at least 3 edges, got {max_edges}")
    before = len(boundary_loops(model.faces))
    meshes = pymeshlab.MeshSet()
    meshes.add_mesh(pymeshlab.Mesh(vertex_matrix=model.vertices, face_matrix=model.faces.astype(np.int32)))
    # pymeshlab closes the holes of fewer than maxholesize edges
    meshes.meshing_close_holes(maxholesize=int(max_edges) + 1, selfintersection=False)
    mesh = meshes.current_mesh()
    faces = np.asarray(mesh.face_matrix(), np.int64)
    if len(mesh.vertex_matrix()) != len(model.vertices) or not np.array_equal(faces[: len(model.faces)], model.faces):
        raise StitchError(f"{model.name}: closing its holes changed its vertices or faces, not only added faces")
    added = _manifold_patches(faces, len(model.faces), len(model.vertices))
    faces = np.concatenate([model.faces, added])
    vertex_colors = np.zeros((len(model.vertices), 3), np.float32)
    vertex_colors[model.faces.ravel()] = model.corner_colors.reshape(-1, 3)
    closed = Model(
        model.name,
        model.vertices,
        faces,
        np.concatenate([model.corner_colors, vertex_colors[added]]),
        np.concatenate([model.corner_uv, np.zeros((len(added), 3, 2), np.float32)]),
        np.concatenate([model.face_texture, np.full(len(added), -1, np.int32)]),
        model.textures,
        model.label,
        model.source,
        list(model.repairs),
    )
    filled = before - len(boundary_loops(closed.faces))
    if filled:
        closed.repairs.append(f"{filled} hole(s) of up to {int(max_edges)} edges closed ({len(added)} faces)")
    log.info("%s: %d hole(s) of up to %d edges closed with %d faces", model.name, filled, int(max_edges), len(added))
    return closed, filled


def _manifold_patches(faces: np.ndarray, kept: int, vertices: int) -> np.ndarray:
    """The faces after the first ``kept`` of ``faces`` (the patches), less every patch (faces joined by vertices)
    that has an edge shared by more than two faces."""
    added = faces[kept:]
    if not len(added):
        return added
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    _, inverse, counts = np.unique(edges, axis=0, return_inverse=True, return_counts=True)
    overfull = np.any(counts[inverse.reshape(3, -1)] > 2, axis=0)[kept:]
    if not overfull.any():
        return added
    patch = component_labels(np.concatenate([added[:, [0, 1]], added[:, [1, 2]]]), vertices)[added[:, 0]]
    return added[~np.isin(patch, patch[overfull])]
