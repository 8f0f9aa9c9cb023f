"""Boundary loops of open meshes (thesis 7.2): extracted, split at pinches, paired, resampled by arc length."""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np
from scipy.spatial import cKDTree

from heatdata.core.mesh import (
    boundary_loops,
    consistent_winding,
)
from heatdata.errors import StitchError
from heatdata.io.models import Model

log = logging.getLogger(__name__)


MIN_BOUNDARY = 4


@dataclass(frozen=True)
class Boundary:
    """A boundary loop of a mesh, oriented by the mesh's faces (:func:`boundary` gives the longest, 7.5).

    Attributes
    ----------
    loop : (b,) int64
        Vertex indices in the direction of the boundary half-edges.
    points : (b, 3) float64
    normals : (b, 3) float64
        Unit boundary normals: in the plane of the boundary face, perpendicular to the
        boundary, pointing away from the mesh (Fig. 7.3).
    arclength : (b,) float64
        Arc length from the loop's first vertex, divided by the loop's length.
    length : float
        The loop's length.
    loops : int
        How many boundary loops the mesh has.
    """

    loop: np.ndarray
    points: np.ndarray
    normals: np.ndarray
    arclength: np.ndarray
    length: float
    loops: int


def _overfull_edges(faces: np.ndarray) -> int:
    """How many edges of ``faces`` belong to more than two of them."""
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    return int((np.unique(edges, axis=0, return_counts=True)[1] > 2).sum())


def _manifold_edges(faces: np.ndarray, name: str) -> None:
    overfull = _overfull_edges(faces)
    if overfull:
        raise StitchError(
            f"{name}: {overfull} edge(s) belong to more than two faces: not a "
            "2-manifold mesh (clean it first, e.g. pymeshlab's meshing_repair_non_manifold_edges)"
        )


def boundaries(model: Model) -> list[Boundary]:
    """Every boundary loop of ``model`` with its boundary normals (thesis 7.3), longest first.

    Raises
    ------
    StitchError
        A closed mesh (no boundary), or an edge shared by more than two faces.
    """
    faces, flipped = consistent_winding(np.asarray(model.faces, dtype=np.int64))
    if flipped:
        log.warning("%s: %d face(s) wound against their neighbours were reversed", model.name, flipped)
    _manifold_edges(faces, model.name)
    loops = [simple for loop in boundary_loops(faces) for simple in _simple_loops(loop) if len(simple) >= 2]
    if not loops:
        raise StitchError(f"{model.name}: the mesh is closed (no boundary): there is nothing to stitch")
    found = []
    for loop in loops:
        points = model.vertices[loop]
        steps = np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1)
        length = float(steps.sum())
        arclength = np.concatenate([[0.0], np.cumsum(steps)[:-1]]) / max(length, 1e-300)
        found.append(
            Boundary(
                loop=loop,
                points=points,
                normals=_boundary_normals(model.vertices, faces, loop),
                arclength=arclength,
                length=length,
                loops=len(loops),
            )
        )
    return sorted(found, key=lambda b: -b.length)


def _simple_loops(loop: np.ndarray) -> list[np.ndarray]:
    """A boundary loop split where it passes a vertex twice (a pinch), into loops that visit each vertex once.

    At a pinch the loops a traversal finds depend on which outgoing edge it takes; the split loops do not, so two
    meshes that share a boundary get the same loops.
    """
    path: list[int] = []
    where: dict[int, int] = {}
    found = []
    for v in (int(u) for u in loop):
        if v in where:
            start = where[v]
            found.append(np.array(path[start:], dtype=np.int64))
            for u in path[start + 1 :]:
                del where[u]
            del path[start + 1 :]
        else:
            where[v] = len(path)
            path.append(v)
    return [*found, np.array(path, dtype=np.int64)]


def boundary(model: Model) -> Boundary:
    """The longest boundary loop of ``model`` (7.5), as :func:`boundaries`.

    Raises
    ------
    StitchError
        As :func:`boundaries`, or a longest loop of fewer than 3 vertices.
    """
    return _longest(boundaries(model), model.name)


def _longest(loops: list[Boundary], name: str) -> Boundary:
    if len(loops[0].loop) < 3:
        raise StitchError(f"{name}: the longest boundary has {len(loops[0].loop)} vertices; at least 3 are needed")
    return loops[0]


def _moved(b: Boundary, rotation: np.ndarray, translation: np.ndarray) -> Boundary:
    """A boundary carried by a rigid motion with its mesh (its loop and arc lengths do not change)."""
    return replace(b, points=b.points @ rotation.T + translation, normals=b.normals @ rotation.T)


def _pair_loops(first: list[Boundary], second: list[Boundary]) -> list[tuple[Boundary, Boundary]]:
    """Pairs of loops of two aligned meshes, closest first: by the mean distance from each loop's vertices to the
    other's (both ways), lengths within a factor 1.5, apart by less than a loop's radius."""
    trees = [cKDTree(b2.points) for b2 in second]
    candidates = []
    for i, b1 in enumerate(first):
        tree1 = cKDTree(b1.points)
        for k, b2 in enumerate(second):
            if len(b1.loop) < 3 or len(b2.loop) < 3 or max(b1.length, b2.length) > 1.5 * min(b1.length, b2.length):
                continue
            distance = 0.5 * (trees[k].query(b1.points)[0].mean() + tree1.query(b2.points)[0].mean())
            if distance < 0.5 * max(b1.length, b2.length) / np.pi:
                candidates.append((distance, i, k))
    pairs, taken1, taken2 = [], set(), set()
    for _, i, k in sorted(candidates):
        if i not in taken1 and k not in taken2:
            taken1.add(i)
            taken2.add(k)
            pairs.append((first[i], second[k]))
    return pairs


def _boundary_normals(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray) -> np.ndarray:
    """(b, 3) unit normals to the boundary in the surface, pointing out of the mesh."""
    n = np.int64(len(vertices))
    half = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]).astype(np.int64)
    keys = half[:, 0] * n + half[:, 1]
    order = np.argsort(keys)
    following = np.roll(loop, -1)
    found = order[np.searchsorted(keys[order], loop * n + following)]  # the face of each boundary half-edge
    face = faces[found % len(faces)]
    corners = vertices[face]
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    # the face lies to the left of its half-edge a -> b (counter-clockwise about its normal): outwards is right
    out = np.cross(vertices[following] - vertices[loop], normal)
    normals = out + np.roll(out, 1, axis=0)  # a vertex takes the mean of its two boundary edges' normals
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    return normals / np.where(length > 0, length, 1.0)


def resample_loop(
    points: np.ndarray, count: int, normals: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray | None]:
    """``count`` points uniformly spaced by arc length along a closed polyline, from its first vertex (7.5).

    Returns the (count, 3) points and, given per-vertex ``normals``, the unit normals
    interpolated there (else None).
    """
    if count < 3:
        raise StitchError(f"a boundary needs at least 3 samples, got {count}")
    closed = np.vstack([points, points[:1]])
    cumulative = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(closed, axis=0), axis=1))])
    targets = np.arange(count) / count * cumulative[-1]
    edge = np.clip(np.searchsorted(cumulative, targets, side="right") - 1, 0, len(points) - 1)
    step = cumulative[edge + 1] - cumulative[edge]
    frac = np.where(step > 0, (targets - cumulative[edge]) / np.where(step > 0, step, 1.0), 0.0)[:, None]
    resampled = closed[edge] + frac * (closed[edge + 1] - closed[edge])
    if normals is None:
        return resampled, None
    ends = np.vstack([normals, normals[:1]])
    return resampled, _unit((1.0 - frac) * ends[edge] + frac * ends[edge + 1])


def _as_loops(b: Boundary | list[Boundary]) -> list[Boundary]:
    return [b] if isinstance(b, Boundary) else list(b)


def _unit(v: np.ndarray) -> np.ndarray:
    length = np.linalg.norm(v, axis=1, keepdims=True)
    return v / np.where(length > 0, length, 1.0)
