"""JASNOM (thesis ch. 7): one closed model from two non-overlapping meshes, aligned and stitched by their boundaries.

Two scans of an object (standing, then flipped; or two opposite cameras) cover it
together without overlapping, so overlap-based registration cannot align them. JASNOM
aligns them by their boundary loops, B1 and B2, and stitches the gap between them with a
triangle strip (7.4). Loops that pass a vertex twice (a pinch) are split there, so two
meshes that share a boundary see the same loops.

**The cost** (eq. 7.2-7.4, made continuous). Each mesh's loops are resampled uniformly by
arc length (7.5): ``samples`` points on the longest, proportionally many on the others.
Each sample is paired with the *closest point* on the other mesh's loops (after the
motion), both ways, so J is continuous in the rotation and translation: there is no
discrete shift in it, and at the true motion of two halves that share their boundary
every pair is at distance 0. The pair's edge vector ``xi`` points from B2 to B1 (eq.
7.1). Every term is divided by ``s^2`` (``s``: the RMS radius of B1's samples about their
centroid) and averaged over the pairs, so the weights are unitless whatever the object's
size and sampling:

- **J1, the edges** (eq. 7.2): ``|xi_across|^2 + along * |xi_along|^2``. ``xi_along`` is
  the component along the seam's continuation ``m = (n2 - n1) / |n2 - n1|``, where ``n1``,
  ``n2`` are the boundary normals (Fig. 7.3: in the boundary face's plane, perpendicular
  to the boundary, pointing away from the mesh). With ``along = 1`` it is the squared
  edge length of eq. 7.2. A surface that leaves B2 along ``n2`` and arrives at B1 along
  ``-n1`` on a circular arc has its chord along ``m``; ``along < 1`` tolerates such a band
  of unseen surface between two scans without letting the boundaries slide.
- **J2, the interpenetration** (replacing the logistic of eq. 7.3): how far a boundary
  lies *over* the other mesh. ``d1 = xi . n1 > 0`` when B2's point lies on mesh 1's side of
  B1, and ``d2 = -xi . n2 > 0`` when B1's point lies on mesh 2's side of B2. Each costs
  ``(d / s)^2 * logistic(alpha * d / h)`` (``h``: the mean sample spacing): nothing when the
  boundaries meet exactly (``xi = 0``, where eq. 7.3's logistic of a random direction gave
  about 0.5), growing with the square of the depth, and switching on over a width of
  ``h / alpha``, relative to the sampling rather than absolute.
- **J3, the crease**: ``|n1 + n2|^2 / 4`` is 0 where the surface continues straight across
  the seam and 1 where the meshes fold onto each other. Its default weight is 0: on
  coarse models cut along sharp edges the crease at the truth is large, and a nonzero
  weight pulled the optimum off it (measured by ``scripts/jasnom_cuts.py``).

``J = J1 + beta * J2 + gamma * J3`` (eq. 7.4), optionally through a soft-L1 loss
(``robust``), for boundaries with parts that have no partner.

**The orientation constraint** (7.3). Poses where the meshes lie on the same side of the
seam (the mean cosine of paired boundary normals above 0: the second mesh on top of the
first) have J = +inf. Two depth scans are different: a silhouette cut where the depth
jumps keeps faces that are not grazing, and their boundary normals point outwards from
the object in both scans (their mean cosine at the truth is +0.2 to +0.5 on the embedded
objects). With ``scans``, the constraint is instead that each scan lies on the far side of
the object from the other's camera (:class:`ScanSurface`).

**The search** (eq. 7.5-7.6). Every shift tau of B2's resampled origin, in both orders
(the thesis's reversed order of 7.3, and the mirrored order of a mesh wound the other
way round the object, whose faces are then reversed with a warning), gives a
correspondence of the longest loops; its closed-form rigid alignment (Kabsch) is a
candidate. J is evaluated at all ``2 * samples`` candidates, and the cheapest ``refine``
that are at least 10 deg or 5% of the size apart are refined over all six degrees of
freedom (scipy's trust-region least squares on J's residuals, then closest-point Kabsch
steps while J decreases). The best is kept; the best *different* refined pose (more than
2 deg or 1% of the size away) is the runner-up, whose J says whether the answer is
ambiguous (:attr:`Alignment.ambiguous`): a symmetric boundary, such as a circle, fits as
well at other turns.

**The stitch** (7.4). At the motion, each vertex of B2 is assigned its nearest vertex of
B1, made monotone along the loops (the order constraint of eq. 7.7), and the strip of
7.4 walks both loops; the other loops are paired by their mean distance and similar length.
Strip edges shorter than a hundredth of the seam's median edge join vertices that
coincide: they are welded and the strip's degenerate triangles dropped, so two halves
that share a boundary become one watertight, consistently wound mesh, also when a reader
merges coincident vertices. The output stays in the first mesh's frame.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation
from scipy.special import expit

from .errors import HeatdataError
from .mesh import boundary_loops, component_labels, consistent_winding, mesh_edges
from .models import Model, vertex_colors

log = logging.getLogger(__name__)

ALPHA = 4.0
"""Steepness of the interpenetration penalty: it switches on over ``h / ALPHA`` (h: the sample spacing)."""
BETA = 1.0
"""Weight of the interpenetration term J2 (eq. 7.4)."""
GAMMA = 0.0
"""Weight of the crease term J3."""
ALONG = 1.0
"""Weight of the edge component along the seam's continuation direction in J1 (1: the squared length)."""
SCAN_ALONG, SCAN_ROBUST = 0.1, 0.05
"""``along`` and ``robust`` for two depth scans (``stitch(..., scans=True)``): a band of unseen surface lies between
them, along the seam's continuation, and parts of either boundary (self-occlusions) have no partner."""
REFINE = 4
"""Distinct coarse candidates refined over six degrees of freedom."""
AMBIGUOUS = 1.25
"""A runner-up whose J is below this many times the best's makes the answer ambiguous."""
POOR_GAP = 0.02
"""A seam whose mean gap exceeds this fraction of the object's size is a poor stitch."""
DISTINCT_DEGREES, DISTINCT_SIZE = 2.0, 0.01
"""Poses closer than this (rotation, translation over the size) are the same answer."""
MIN_BOUNDARY = 4
"""Vertices a longest boundary needs before it can fix a motion."""


class StitchError(HeatdataError):
    """Two meshes cannot be stitched (no boundary, too short, not a 2-manifold)."""


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
        raise StitchError(f"{name}: {overfull} edge(s) belong to more than two faces: not a "
                          "2-manifold mesh (clean it first, e.g. pymeshlab's meshing_repair_non_manifold_edges)")


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
        found.append(Boundary(loop=loop, points=points, normals=_boundary_normals(model.vertices, faces, loop),
                              arclength=arclength, length=length, loops=len(loops)))
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
            for u in path[start + 1:]:
                del where[u]
            del path[start + 1:]
        else:
            where[v] = len(path)
            path.append(v)
    return found + [np.array(path, dtype=np.int64)]


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


def resample_loop(points: np.ndarray, count: int, normals: np.ndarray | None = None
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


@dataclass(frozen=True)
class Alignment:
    """The best rigid motion of the second mesh onto the first, what it costs and how it was found.

    Attributes
    ----------
    rotation : (3, 3) float64
    translation : (3,) float64
        ``x = rotation @ y + translation`` maps the second mesh into the first's frame.
    cost, edge_cost, crossing_cost, crease_cost : float
        J, J1, J2 and J3 at the motion (module docstring); ``J = J1 + beta J2 + gamma J3``.
    runner_up : float
        J of the best pose found more than 2 deg or 1% of the size away (NaN when the
        search found none, or no search was made).
    gap : float
        Mean length of the paired edge vectors at the motion (the seam's mean gap), in
        the meshes' units.
    size : float
        Bounding-box diagonal of the two boundaries at the motion (what ``gap`` and the
        distinct-pose threshold are relative to).
    facing : float
        Mean cosine between paired boundary normals: near -1 when the meshes face each
        other across their boundaries, positive when they lie on the same side.
    candidates : int
        Poses evaluated (coarse candidates and refinement steps).
    seconds : float
    """

    rotation: np.ndarray
    translation: np.ndarray
    cost: float
    edge_cost: float
    crossing_cost: float
    crease_cost: float
    runner_up: float
    gap: float
    size: float
    facing: float
    candidates: int
    seconds: float

    @property
    def ambiguous(self) -> bool:
        """A different pose is nearly as cheap (its J below :data:`AMBIGUOUS` times the best's)."""
        return bool(np.isfinite(self.runner_up) and self.runner_up < AMBIGUOUS * self.cost + 1e-12)

    @property
    def poor(self) -> bool:
        """The seam's mean gap exceeds :data:`POOR_GAP` of the size."""
        return bool(self.gap > POOR_GAP * self.size)


@dataclass(frozen=True)
class _Curve:
    """A mesh's boundary loops as the cost sees them: their polylines (for closest points) and uniform samples.

    The longest loop's ``samples`` samples come first (the coarse search's correspondences); each other loop adds
    samples in proportion to its length, at least 3.
    """

    points: np.ndarray  # (b, 3) every loop's vertices, loop after loop
    normals: np.ndarray  # (b, 3)
    before: np.ndarray  # (b,) the previous vertex in its loop
    after: np.ndarray  # (b,) the next
    tree: cKDTree
    samples: np.ndarray  # (S', 3)
    sample_normals: np.ndarray  # (S', 3)

    @classmethod
    def of(cls, loops: list[Boundary], samples: int) -> "_Curve":
        loops = [b for b in loops if len(b.loop) >= 3]
        counts = [samples if k == 0 else max(3, round(samples * b.length / loops[0].length)) for k, b in enumerate(loops)]
        resampled = [resample_loop(b.points, count, b.normals) for b, count in zip(loops, counts, strict=True)]
        # every loop split to half the finest sample spacing, so that the nearest vertices find the closest segment
        spacing = min(b.length / (2 * count) for b, count in zip(loops, counts, strict=True))
        dense = [_densified(b, spacing) for b in loops]
        counts = [len(points) for points, _ in dense]
        starts = np.cumsum([0] + counts)
        index = np.arange(starts[-1])
        first, size = np.repeat(starts[:-1], counts), np.repeat(counts, counts)
        points = np.vstack([points for points, _ in dense])
        return cls(points, np.vstack([normals for _, normals in dense]), first + (index - first - 1) % size,
                   first + (index - first + 1) % size, cKDTree(points), np.vstack([r[0] for r in resampled]),
                   np.vstack([r[1] for r in resampled]))

    def closest(self, queries: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(q, 3) closest points on the loops and the boundary normal there (interpolated along the segment).

        The segments tried are the two at each of the 4 nearest vertices.
        """
        nearest = self.tree.query(queries, k=min(4, len(self.points)))[1].reshape(len(queries), -1)
        a = np.concatenate([self.before[nearest], nearest], axis=1)  # (q, 8) segments a -> b
        b = np.concatenate([nearest, self.after[nearest]], axis=1)
        start, segment = self.points[a], self.points[b] - self.points[a]
        squared = np.einsum("qkj,qkj->qk", segment, segment)
        f = np.clip(np.einsum("qkj,qkj->qk", queries[:, None] - start, segment) / np.where(squared > 0, squared, 1.0),
                    0.0, 1.0)
        point = start + f[..., None] * segment
        best = np.argmin(np.einsum("qkj,qkj->qk", queries[:, None] - point, queries[:, None] - point), axis=1)
        rows = np.arange(len(queries))
        f = f[rows, best][:, None]
        normal = (1.0 - f) * self.normals[a[rows, best]] + f * self.normals[b[rows, best]]
        return point[rows, best], _unit(normal)


def _densified(b: Boundary, spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """A loop's vertices and normals with points added along its edges longer than ``spacing``."""
    following = np.roll(np.arange(len(b.loop)), -1)
    pieces = np.maximum(1, np.ceil(np.linalg.norm(b.points[following] - b.points, axis=1) / spacing)).astype(int)
    edge = np.repeat(np.arange(len(b.loop)), pieces)
    f = (np.arange(pieces.sum()) - np.repeat(np.cumsum(pieces) - pieces, pieces)) / np.repeat(pieces, pieces)
    f = f[:, None]
    points = (1.0 - f) * b.points[edge] + f * b.points[following[edge]]
    return points, _unit((1.0 - f) * b.normals[edge] + f * b.normals[following[edge]])


def _unit(v: np.ndarray) -> np.ndarray:
    length = np.linalg.norm(v, axis=1, keepdims=True)
    return v / np.where(length > 0, length, 1.0)


@dataclass(frozen=True)
class ScanSurface:
    """A depth scan's surface as the scan constraint sees it: where its faces are, which way they face, and which
    way it faced its own camera, at the origin of its frame (a depth sensor writes its scans so).

    Attributes
    ----------
    centroids : (f, 3) float64
        At most 2,000 face centroids (every face's when there are fewer; else a seeded sample by area).
    normals : (f, 3) float64
        The faces' normals as wound, scaled by area.
    toward_camera : float
        +1 if the faces' wound normals point towards the camera on average, -1 if away.
    """

    centroids: np.ndarray
    normals: np.ndarray
    toward_camera: float

    @classmethod
    def of(cls, model: Model, count: int = 2000) -> "ScanSurface":
        corners = model.vertices[model.faces]
        normals = 0.5 * np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        centroids = corners.mean(axis=1)
        area = np.linalg.norm(normals, axis=1)
        if len(area) > count:
            keep = np.random.default_rng(0).choice(len(area), count, replace=False, p=area / area.sum())
            centroids, normals = centroids[keep], normals[keep]
        return cls(centroids, normals, float(np.sign(np.sum(np.einsum("ij,ij->i", -centroids, normals))) or 1.0))

    def faces_camera(self, rotation: np.ndarray, translation: np.ndarray, camera: np.ndarray) -> float:
        """The share of the surface's area, moved by the motion, that faces ``camera`` the way it faced its own."""
        centroids, normals = self.centroids @ rotation.T + translation, self.normals @ rotation.T
        facing = self.toward_camera * np.einsum("ij,ij->i", camera - centroids, normals)
        area = np.linalg.norm(normals, axis=1)
        return float(area[facing > 0].sum() / area.sum())


@dataclass(frozen=True)
class _Weights:
    alpha: float
    beta: float
    gamma: float
    along: float
    scale: float  # s, B1's RMS radius
    spacing: float  # h, the mean sample spacing
    root: np.ndarray  # (7,) square roots of the residual columns' weights
    robust: float  # the soft-L1 width of every residual (0: plain squares)


def _pair_residuals(xi: np.ndarray, n1: np.ndarray, n2: np.ndarray, w: _Weights) -> np.ndarray:
    """(p, 7) unweighted residuals of paired points: J1's edge (3 across, 1 along), J2's depths (2), J3's crease."""
    m = n2 - n1
    length = np.linalg.norm(m, axis=1, keepdims=True)
    m = np.where(length > 1e-9, m / np.where(length > 1e-9, length, 1.0), n2)
    along = np.einsum("ij,ij->i", xi, m)
    across = xi - along[:, None] * m
    depth = np.column_stack([np.einsum("ij,ij->i", xi, n1), -np.einsum("ij,ij->i", xi, n2)])
    penetration = depth / w.scale * np.sqrt(expit(w.alpha * depth / w.spacing))
    crease = np.linalg.norm(n1 + n2, axis=1) / 2.0
    return np.column_stack([across / w.scale, np.sqrt(w.along) * along / w.scale, penetration, crease])


def _residuals(rotation: np.ndarray, translation: np.ndarray, c1: _Curve, c2: _Curve, w: _Weights
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unweighted residuals at a motion of B2, both ways; with the edge vectors and the normals' cosines."""
    y = c2.samples @ rotation.T + translation
    n2 = c2.sample_normals @ rotation.T
    p, n1 = c1.closest(y)  # B2's samples against B1
    q, nq = c2.closest((c1.samples - translation) @ rotation)  # B1's samples against B2, in B2's frame
    q, nq = q @ rotation.T + translation, nq @ rotation.T
    xi = np.vstack([p - y, c1.samples - q])
    first, second = np.vstack([n1, c1.sample_normals]), np.vstack([n2, nq])
    return _pair_residuals(xi, first, second, w), xi, np.einsum("ij,ij->i", first, second)


def _terms(residuals: np.ndarray, w: _Weights) -> tuple[float, float, float, float]:
    """J, J1, J2, J3 from the unweighted residuals of :func:`_pair_residuals`."""
    squares = np.mean(_robust((residuals * w.root) ** 2, w.robust), axis=0)
    edge, crossing, crease = float(squares[:4].sum()), float(squares[4:6].sum()), float(squares[6])
    return edge + crossing + crease, edge, crossing / w.beta if w.beta else 0.0, crease / w.gamma if w.gamma else 0.0


def _robust(squares: np.ndarray, scale: float) -> np.ndarray:
    """Squared residuals through the soft-L1 loss of width ``scale`` (0: as they are)."""
    return squares if scale <= 0 else 2 * scale ** 2 * (np.sqrt(1.0 + squares / scale ** 2) - 1.0)


def _as_loops(b: Boundary | list[Boundary]) -> list[Boundary]:
    return [b] if isinstance(b, Boundary) else list(b)


def _weights(c1: _Curve, alpha: float, beta: float, gamma: float, along: float, robust: float, samples: int
             ) -> _Weights:
    for name, value, low in (("alpha", alpha, 0.0), ("beta", beta, None), ("gamma", gamma, None),
                             ("along", along, None), ("robust", robust, None)):
        if not np.isfinite(value) or value < 0 or (low is not None and value <= low):
            raise StitchError(f"{name} must be a finite {'positive' if low is not None else 'non-negative'} number, "
                              f"got {value}")
    x = c1.samples
    scale = float(np.sqrt(np.mean(np.sum((x - x.mean(axis=0)) ** 2, axis=1))))
    spacing = float(np.mean(np.linalg.norm(np.roll(x[:samples], -1, axis=0) - x[:samples], axis=1)))
    if not scale > 0:
        raise StitchError("the first boundary has no extent (all its vertices coincide)")
    root = np.sqrt([1.0, 1.0, 1.0, 1.0, beta, beta, gamma])
    return _Weights(alpha, beta, gamma, along, scale, spacing, root, robust)


def _kabsch(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotations and translations best mapping ``y`` (S, 3) onto each ``x`` (C, S, 3) in the least-squares sense."""
    cx, cy = x.mean(axis=1), y.mean(axis=0)
    h = np.einsum("si,csj->cij", y - cy, x - cx[:, None])
    u, _, vt = np.linalg.svd(h)
    d = np.sign(np.linalg.det(np.einsum("cji,ckj->cik", vt, u)))
    fix = np.ones((len(x), 3))
    fix[:, 2] = d
    rotation = np.einsum("cji,cj,ckj->cik", vt, fix, u)
    return rotation, cx - np.einsum("cij,j->ci", rotation, cy)


def _differs(a: tuple[np.ndarray, np.ndarray], b: tuple[np.ndarray, np.ndarray], centre: np.ndarray, size: float,
             degrees: float, fraction: float) -> bool:
    """Whether two motions differ by more than ``degrees`` of rotation, or move ``centre`` (B2's centroid) to points
    more than ``fraction`` of ``size`` apart."""
    angle = float(np.degrees(Rotation.from_matrix(a[0] @ b[0].T).magnitude()))
    return angle > degrees or float(np.linalg.norm(a[0] @ centre + a[1] - b[0] @ centre - b[1])) > fraction * size


def align(first: Boundary | list[Boundary], second: Boundary | list[Boundary], *, alpha: float = ALPHA,
          beta: float = BETA, gamma: float = GAMMA, along: float = ALONG, samples: int = 128, refine: int = REFINE,
          robust: float = 0.0,
          scans: tuple[ScanSurface, ScanSurface] | None = None, constrained: bool = True, trace: list | None = None
          ) -> Alignment:
    """Eq. 7.5-7.6: the rigid motion of ``second`` onto ``first`` that minimizes J (module docstring).

    Parameters
    ----------
    first, second : Boundary or list of Boundary
        A mesh's longest boundary, or all its loops longest first (:func:`boundaries`): the
        coarse search pairs the longest loops, and J is measured on every loop.
    alpha, beta, gamma, along : float
        The cost's steepness and weights (module docstring; defaults :data:`ALPHA`,
        :data:`BETA`, :data:`GAMMA`, :data:`ALONG`).
    samples : int
        Points per boundary, uniform by arc length; the coarse search tries ``2 * samples``
        correspondences.
    refine : int
        Distinct coarse candidates refined over six degrees of freedom.
    robust : float
        Width of a soft-L1 loss on every residual, in units of s (0: plain squares): pairs
        farther apart than this count less, as parts of a boundary without a partner.
    scans : (ScanSurface, ScanSurface), optional
        The two meshes as depth scans (:func:`stitch` with ``scans=True``): poses are
        allowed where each lies on the far side from the other's camera, instead of where
        the boundary normals face each other (7.3).
    constrained : bool
        False allows every pose (no orientation constraint; for ablations).
    trace : list, optional
        Receives ``(rotation, translation, J)`` at every pose evaluated (for tests that the
        cost prefers the truth).

    Raises
    ------
    StitchError
        A boundary of fewer than :data:`MIN_BOUNDARY` vertices, or a weight that is not a
        finite number in range.
    """
    first, second = _as_loops(first), _as_loops(second)
    for b in (first[0], second[0]):
        if len(b.loop) < MIN_BOUNDARY:
            raise StitchError(f"a boundary of {len(b.loop)} vertices cannot fix a motion: at least {MIN_BOUNDARY} are "
                              "needed (give --motion if it is known)")
    ratio = max(first[0].length, second[0].length) / min(first[0].length, second[0].length)
    if ratio > 1.5:
        log.warning("the boundaries' lengths differ by a factor %.2f: JASNOM assumes they trace one curve", ratio)
    begin = time.perf_counter()
    c1, c2 = _Curve.of(first, samples), _Curve.of(second, samples)
    w = _weights(c1, alpha, beta, gamma, along, robust, samples)
    size = float(np.linalg.norm(np.ptp(np.vstack([c1.samples, c2.samples - c2.samples.mean(axis=0)
                                                  + c1.samples.mean(axis=0)]), axis=0)))
    centre = c2.samples.mean(axis=0)
    visited: list = []

    def evaluate(rotation, translation) -> tuple[np.ndarray, float]:
        """The weighted residuals and J, +inf where the meshes would lie on one side of the seam (7.3)."""
        residuals, _, cosines = _residuals(rotation, translation, c1, c2, w)
        residuals = residuals * w.root
        if not constrained:
            allowed = True
        elif scans is None:
            allowed = np.mean(cosines) <= 0.0  # the meshes lie on the two sides of the seam (7.3)
        else:  # each scan is the far side of the object from the other's camera
            allowed = max(scans[1].faces_camera(rotation, translation, np.zeros(3)),
                          scans[0].faces_camera(rotation.T, -rotation.T @ translation, np.zeros(3))) < 0.5
        value = float(np.mean(np.sum(_robust(residuals ** 2, w.robust), axis=1))) if allowed else np.inf
        visited.append((rotation, translation, value))
        return residuals, value

    shifts = np.arange(samples)
    order = np.concatenate([(shifts[:, None] - shifts) % samples,  # eq. 7.8 on equal samples: reversed (7.3)
                            (shifts[:, None] + shifts) % samples])  # and the mirrored order
    rotations, translations = _kabsch(c1.samples[:samples][order], c2.samples[:samples])
    coarse = np.array([evaluate(r, t)[1] for r, t in zip(rotations, translations, strict=True)])
    if not np.isfinite(coarse).any():
        raise StitchError(
            "no alignment puts each scan on the far side of the object from the other's camera: are both in their "
            "cameras' frames (camera at the origin), taken from opposite sides?" if scans is not None else
            "the two meshes do not face each other across their boundaries at any alignment (the boundary normals "
            "agree): either both are wound the same way round the cut (reverse one's faces), the second lies on the "
            "first (the same surface twice), or their longest boundaries are not one curve")
    starts: list[tuple[np.ndarray, np.ndarray, float]] = []
    for k in np.argsort(coarse, kind="stable")[:np.isfinite(coarse).sum()]:  # the cheapest, 10 deg or 5% apart
        if all(_differs((rotations[k], translations[k]), start[:2], centre, size, 10.0, 0.05) for start in starts):
            starts.append((rotations[k], translations[k], float(coarse[k])))
        if len(starts) == refine:
            break
    # a refinement that ends where the constraint forbids (J = inf) leaves its start as the candidate
    found = sorted((min((_refine(r, t, r @ centre + t, w, c1, c2, evaluate), (r, t, j)), key=lambda pose: pose[2])
                    for r, t, j in starts), key=lambda pose: pose[2])
    rotation, translation, best = found[0]
    others = [j for r, t, j in found[1:]
              if _differs((r, t), (rotation, translation), centre, size, DISTINCT_DEGREES, DISTINCT_SIZE)]
    if trace is not None:
        trace.extend(visited)
    return _alignment(rotation, translation, c1, c2, w, min(others, default=np.nan), len(visited), begin)


def _refine(rotation0: np.ndarray, translation0: np.ndarray, centre: np.ndarray, w: _Weights, c1: _Curve,
            c2: _Curve, evaluate) -> tuple[np.ndarray, np.ndarray, float]:
    """Trust-region least squares from a pose, over a rotation vector about ``centre`` (B2's moved centroid) and a
    translation in units of s, then :func:`_polished`."""

    def motion(p):
        turn = Rotation.from_rotvec(p[:3]).as_matrix()
        return turn @ rotation0, turn @ (translation0 - centre) + centre + w.scale * p[3:]

    pairs = len(c1.samples) + len(c2.samples)

    def residuals(p):
        return evaluate(*motion(p))[0].ravel() / np.sqrt(pairs)

    result = least_squares(residuals, np.zeros(6), method="trf", x_scale=1.0, ftol=1e-12, xtol=1e-12, gtol=1e-12,
                           max_nfev=300, loss="soft_l1" if w.robust > 0 else "linear",
                           f_scale=w.robust / np.sqrt(pairs) if w.robust > 0 else 1.0)
    rotation, translation = motion(result.x)
    return _polished(rotation, translation, c1, c2, evaluate)


def _polished(rotation: np.ndarray, translation: np.ndarray, c1: _Curve, c2: _Curve, evaluate,
              steps: int = 30) -> tuple[np.ndarray, np.ndarray, float]:
    """A pose improved by closest-point Kabsch steps (ICP on the loops) while J decreases: where the boundaries
    coincide it ends exactly on them, which the least squares, over closest points that switch segments, can
    stop short of."""
    best = evaluate(rotation, translation)[1]
    for _ in range(steps):
        moved = c2.samples @ rotation.T + translation
        targets = np.vstack([c1.closest(moved)[0], c1.samples])
        sources = np.vstack([c2.samples, c2.closest((c1.samples - translation) @ rotation)[0]])
        turn, shift = _kabsch(targets[None], sources)
        cost = evaluate(turn[0], shift[0])[1]
        if not cost < best:
            break
        rotation, translation, best = turn[0], shift[0], cost
    return rotation, translation, best


def alignment_at(first: Boundary | list[Boundary], second: Boundary | list[Boundary], rotation: np.ndarray,
                 translation: np.ndarray, *, alpha: float = ALPHA, beta: float = BETA, gamma: float = GAMMA,
                 along: float = ALONG, robust: float = 0.0, samples: int = 128) -> Alignment:
    """J at a known rigid motion of ``second`` onto ``first`` (registered cameras, a turntable, the truth).

    Nothing is searched, so :func:`stitch` can join scans whose motion is known and an
    experiment can compare J at the true motion with J at :func:`align`'s optimum.
    """
    begin = time.perf_counter()
    c1, c2 = _Curve.of(_as_loops(first), samples), _Curve.of(_as_loops(second), samples)
    w = _weights(c1, alpha, beta, gamma, along, robust, samples)
    return _alignment(np.asarray(rotation, np.float64), np.asarray(translation, np.float64), c1, c2, w, np.nan, 1,
                      begin)


def _alignment(rotation, translation, c1: _Curve, c2: _Curve, w: _Weights, runner_up: float, candidates: int,
               begin: float) -> Alignment:
    residuals, xi, cosines = _residuals(rotation, translation, c1, c2, w)
    cost, edge, crossing, crease = _terms(residuals, w)
    moved = c2.samples @ rotation.T + translation
    size = float(np.linalg.norm(np.ptp(np.vstack([c1.samples, moved]), axis=0)))
    return Alignment(rotation=rotation, translation=translation, cost=cost, edge_cost=edge, crossing_cost=crossing,
                     crease_cost=crease, runner_up=float(runner_up), gap=float(np.mean(np.linalg.norm(xi, axis=1))),
                     size=size, facing=float(np.mean(cosines)), candidates=candidates,
                     seconds=time.perf_counter() - begin)


def nearest_targets(first: Boundary, second: Boundary) -> np.ndarray:
    """(N,) int64: for each vertex of ``second`` (already in ``first``'s frame), the nearest vertex of ``first``."""
    return cKDTree(first.points).query(second.points)[1].astype(np.int64)


def strip_faces(first: Boundary, second: Boundary, targets: np.ndarray, offset: int) -> np.ndarray:
    """7.4: the triangle strip between two boundaries in one frame, from each second vertex's target on the first.

    The second boundary is walked backwards (the boundaries run in opposite directions on
    a consistently oriented surface, 7.3) from the vertex nearest its target; the targets
    are made monotone along the walk (the order constraint of eq. 7.7: steps of more than
    half the first loop are read as steps back, and steps back are held). Each step
    advances on one boundary and adds one triangle, so the strip has ``K + N`` triangles,
    no two of its edges cross, and each boundary edge is used once against its own face:
    the union is a consistently oriented 2-manifold. Vertices of the first boundary
    without an assignment share the previous target (7.4).

    Parameters
    ----------
    first, second : Boundary
    targets : (N,) int
        A vertex index into ``first.loop`` for each vertex of ``second.loop``.
    offset : int
        Added to the second mesh's vertex indices (its vertices follow the first's).

    Returns
    -------
    (K + N, 3) int64
    """
    k, n = len(first.loop), len(second.loop)
    gaps = np.linalg.norm(first.points[targets] - second.points, axis=1)
    origin = int(np.argmin(gaps))
    walk = (origin - np.arange(n)) % n  # the second boundary, backwards from its best-matched vertex
    steps = (np.diff(targets[walk]) + k // 2) % k - k // 2
    unwrapped = targets[walk[0]] + np.concatenate([[0], np.cumsum(steps)])
    unwrapped = np.minimum(np.maximum.accumulate(unwrapped), targets[walk[0]] + k)
    x = lambda j: int(first.loop[j % k])  # noqa: E731
    y = lambda i: int(second.loop[i]) + offset  # noqa: E731
    faces = []
    p = int(unwrapped[0])
    for step in range(n):
        q = walk[step]
        goal = int(unwrapped[step + 1]) if step + 1 < n else int(unwrapped[0]) + k
        while p < goal:  # advance on the first boundary while the second stays at q
            faces.append((x(p + 1), x(p), y(q)))
            p += 1
        following = walk[(step + 1) % n]
        faces.append((y(q), y(following), x(p)))  # advance on the second boundary
    return np.array(faces, dtype=np.int64)


def _weld(vertices: np.ndarray, faces: np.ndarray, strip: np.ndarray, offset: int, tolerance: float
          ) -> tuple[np.ndarray, np.ndarray, int]:
    """The strip's coincident pairs welded: a strip edge between the meshes no longer than ``tolerance`` joins its
    ends, each vertex to at most one, shortest first; the triangles this degenerates are dropped.

    Returns the faces with welded indices (the second mesh's vertex becomes the first's), the mask of faces kept
    and how many pairs were welded. If welding would leave an edge of more than two faces, nothing is welded.
    """
    edges = np.concatenate([strip[:, [0, 1]], strip[:, [1, 2]], strip[:, [2, 0]]])
    cross = np.unique(np.sort(edges[(edges[:, 0] < offset) != (edges[:, 1] < offset)], axis=1), axis=0)
    lengths = np.linalg.norm(vertices[cross[:, 0]] - vertices[cross[:, 1]], axis=1)
    index = np.arange(len(vertices))
    taken: set[int] = set()
    for k in np.argsort(lengths, kind="stable"):
        if lengths[k] > tolerance:
            break
        a, b = (int(v) for v in cross[k])
        if a not in taken and b not in taken:
            taken.update((a, b))
            index[b] = a
    joined = index[faces]
    keep = (joined[:, 0] != joined[:, 1]) & (joined[:, 1] != joined[:, 2]) & (joined[:, 2] != joined[:, 0])
    if taken and _overfull_edges(joined[keep]):
        log.warning("welding the seam's coincident vertices would make an edge of more than two faces: the strip is "
                    "kept whole")
        return faces, np.ones(len(faces), dtype=bool), 0
    return joined, keep, len(taken) // 2


def _same_direction(first: Boundary, second: Boundary) -> bool:
    """Whether two boundaries in one frame run the same way (their nearest vertices' tangents agree on average):
    on one consistently oriented surface they run opposite ways (7.3)."""
    def tangents(b: Boundary) -> np.ndarray:
        return _unit(np.roll(b.points, -1, axis=0) - np.roll(b.points, 1, axis=0))
    targets = nearest_targets(first, second)
    return float(np.mean(np.einsum("ij,ij->i", tangents(first)[targets], tangents(second)))) > 0


def _reversed(model: Model) -> Model:
    """``model`` with every face wound the other way (its corners' colours and texture coordinates with them)."""
    return replace(model, faces=model.faces[:, ::-1].copy(), corner_colors=model.corner_colors[:, ::-1].copy(),
                   corner_uv=model.corner_uv[:, ::-1].copy())


def transformed(model: Model, rotation: np.ndarray, translation: np.ndarray) -> Model:
    """``model`` moved rigidly: ``x -> rotation @ x + translation``."""
    return replace(model, vertices=model.vertices @ np.asarray(rotation).T + np.asarray(translation))


@dataclass(frozen=True)
class Stitched:
    """What :func:`stitch` returns: the stitched model, the alignment, the two longest boundaries (the second moved),
    how many loop pairs were stitched, how many loops stay open, how many vertex pairs were welded and how many
    strip triangles the model keeps (its last faces)."""

    model: Model
    alignment: Alignment
    first: Boundary
    second: Boundary
    loop_pairs: int
    open_loops: int
    welded: int
    strip_faces: int


def rigid_motion(motion) -> np.ndarray:
    """``motion`` as a (4, 4) float64 rigid transform, or a :class:`StitchError`: a rotation (no reflection), a
    translation, last row 0 0 0 1."""
    m = np.asarray(motion, np.float64)
    if (m.shape != (4, 4) or not np.allclose(m[:3, :3] @ m[:3, :3].T, np.eye(3), atol=1e-6)
            or np.linalg.det(m[:3, :3]) < 0 or not np.allclose(m[3], [0.0, 0.0, 0.0, 1.0])):
        raise StitchError(f"motion must be a 4x4 rigid transform (a rotation, no reflection, last row 0 0 0 1), "
                          f"got shape {m.shape}")
    return m


def stitch(first: Model, second: Model, *, alpha: float = ALPHA, beta: float = BETA, gamma: float = GAMMA,
           along: float | None = None, robust: float | None = None, samples: int = 128, scans: bool = False,
           name: str | None = None, motion: np.ndarray | None = None) -> Stitched:
    """JASNOM: align ``second`` onto ``first`` by their longest boundaries and stitch them into one model.

    The longest loops align the meshes (7.2-7.3, 7.5; module docstring). Beyond the
    thesis, the other loops (a cut through a concave object leaves several) are paired by
    their mean distance and similar length and stitched at that alignment.

    Parameters
    ----------
    first, second : Model
        Two meshes that together cover an object without overlapping, each a 2-manifold
        with a boundary, both wound the same way about the object (both outwards, or both
        inwards as two of heatdata's views are, whose faces point away from their cameras).
    alpha, beta, gamma, along, robust, samples
        As for :func:`align`; ``along`` and ``robust`` default to :data:`ALONG` and 0, or
        for scans to :data:`SCAN_ALONG` and :data:`SCAN_ROBUST`.
    scans : bool
        Each mesh is a depth scan in its own camera's frame (the camera at the origin, as
        a sensor writes it), the two taken from roughly opposite sides (the object
        flipped, 7.5). Poses are then allowed where each scan lies on the far side of
        the object from the other's camera (:class:`ScanSurface`), instead of where the
        boundary normals face each other, which silhouettes cut at depth jumps do not.
    name : str, optional
        The stitched model's name (default: ``first.name + "+" + second.name``).
    motion : (4, 4) float, optional
        A known rigid motion of ``second`` into ``first``'s frame (registered cameras, a
        turntable): nothing is searched (:func:`alignment_at`), and boundaries that do not
        face each other there (a gap of grazing surface between two opposite scans) are
        stitched anyway, with a warning.

    Returns
    -------
    Stitched
        ``model`` is in ``first``'s frame: the first mesh's vertices, then the second's
        moved there (less those welded to the first's), and the strip's triangles last
        (coloured by their corners' vertex colours); both meshes' textures are kept.

    Raises
    ------
    StitchError
        As :func:`boundary` and :func:`align` (no pose where the meshes face each other);
        the same mesh twice.
    """
    if (first.vertices.shape == second.vertices.shape and first.faces.shape == second.faces.shape
            and np.array_equal(first.faces, second.faces) and np.allclose(first.vertices, second.vertices)):
        raise StitchError(f"{first.name} and {second.name} are the same mesh: JASNOM joins two different parts of an "
                          "object")
    loops1, loops2 = boundaries(first), boundaries(second)
    b1, b2 = _longest(loops1, first.name), _longest(loops2, second.name)
    weights = {"alpha": alpha, "beta": beta, "gamma": gamma, "samples": samples,
               "along": (SCAN_ALONG if scans else ALONG) if along is None else along,
               "robust": (SCAN_ROBUST if scans else 0.0) if robust is None else robust}
    if motion is None:
        alignment = align(loops1, loops2, **weights,
                          scans=(ScanSurface.of(first), ScanSurface.of(second)) if scans else None)
    else:
        motion = rigid_motion(motion)
        alignment = alignment_at(loops1, loops2, motion[:3, :3], motion[:3, 3], **weights)
    if alignment.facing > 0 and motion is not None and not scans:  # a found motion faces them (align's constraint)
        log.warning("%s and %s do not face each other across their boundaries at the given motion (mean cosine of "
                    "the boundary normals %+.2f): the strip spans a gap the scans did not see", first.name,
                    second.name, alignment.facing)
    if _same_direction(b1, _moved(b2, alignment.rotation, alignment.translation)):
        log.warning("%s is wound the other way round the object from %s (their boundaries run the same way at the "
                    "seam): its faces are reversed", second.name, first.name)
        second = _reversed(second)
        loops2 = boundaries(second)
    moved = transformed(second, alignment.rotation, alignment.translation)
    moved_loops = [_moved(b, alignment.rotation, alignment.translation) for b in loops2]
    moved_b2 = moved_loops[0]
    offset = len(first.vertices)
    pairs = [(b1, moved_b2)] + _pair_loops(loops1[1:], moved_loops[1:])
    strip = np.vstack([strip_faces(l1, l2, nearest_targets(l1, l2), offset) for l1, l2 in pairs])
    open_loops = b1.loops + moved_b2.loops - 2 * len(pairs)
    if open_loops:
        log.warning("%d boundary loop(s) of %s and %s have no partner and stay open", open_loops, first.name,
                    second.name)
    vertices = np.vstack([first.vertices, moved.vertices])
    colors = np.vstack([vertex_colors(first), vertex_colors(moved)])
    faces = np.vstack([first.faces, moved.faces + offset, strip])
    seam = np.concatenate([np.linalg.norm(np.roll(b.points, -1, axis=0) - b.points, axis=1)
                           for pair in pairs for b in pair])
    faces, keep, welded = _weld(vertices, faces, strip, offset, 0.01 * float(np.median(seam)))
    faces = faces[keep]
    used = np.unique(faces)
    index = np.full(len(vertices), -1, np.int64)
    index[used] = np.arange(len(used))
    model = Model(
        name=name or f"{first.name}+{second.name}",
        vertices=vertices[used],
        faces=index[faces],
        corner_colors=np.concatenate([first.corner_colors, moved.corner_colors,
                                      colors[strip].astype(np.float32)])[keep],
        corner_uv=np.concatenate([first.corner_uv, moved.corner_uv, np.zeros((len(strip), 3, 2), np.float32)])[keep],
        face_texture=np.concatenate([first.face_texture,
                                     np.where(moved.face_texture >= 0, moved.face_texture + len(first.textures), -1),
                                     np.full(len(strip), -1)]).astype(np.int32)[keep],
        textures=list(first.textures) + list(moved.textures),
        label=first.label or second.label, source=f"JASNOM of {first.source or first.name} and "
                                                   f"{second.source or second.name}",
        repairs=list(first.repairs) + list(second.repairs))
    strip_kept = int(keep[len(first.faces) + len(second.faces):].sum())
    log.info("stitched %s: J %.4g (J1 %.3g, J2 %.3g, J3 %.3g; runner-up %.4g), mean gap %.3g, %d loop pair(s), "
             "%d vertex pair(s) welded, %d strip triangles, %.1f s", model.name, alignment.cost, alignment.edge_cost,
             alignment.crossing_cost, alignment.crease_cost, alignment.runner_up, alignment.gap, len(pairs), welded,
             strip_kept, alignment.seconds)
    return Stitched(model=model, alignment=alignment, first=b1, second=moved_b2, loop_pairs=len(pairs),
                    open_loops=open_loops, welded=welded, strip_faces=strip_kept)


def _submodel(model: Model, keep: np.ndarray, name: str) -> Model:
    used = np.unique(model.faces[keep])
    index = np.full(len(model.vertices), -1, np.int64)
    index[used] = np.arange(len(used))
    return Model(name=name, vertices=model.vertices[used], faces=index[model.faces[keep]],
                 corner_colors=model.corner_colors[keep], corner_uv=model.corner_uv[keep],
                 face_texture=model.face_texture[keep], textures=list(model.textures), label=model.label,
                 source=model.source, repairs=list(model.repairs))


def split_model(model: Model, normal, *, offset: float = 0.0, amplitude: float = 0.0, waves: int = 3
                ) -> tuple[Model, Model]:
    """Cut a model in two along its edges: the ground truth of the JASNOM experiments.

    Each face goes to the side of the surface ``n . (c - centre) = size * (offset +
    amplitude * sin(waves * phi))`` its centroid c lies on (a plane for ``amplitude`` 0, a
    wavy cut otherwise; phi is the angle about ``n``, size the bounding-box diagonal). The
    halves share their boundary vertices' positions exactly.
    """
    normal = np.asarray(normal, dtype=np.float64)
    normal = normal / np.linalg.norm(normal)
    centroids = model.vertices[model.faces].mean(axis=1) - model.center
    u = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    phi = np.arctan2(centroids @ v, centroids @ u)
    size = float(np.linalg.norm(model.extents))
    side = centroids @ normal > size * (offset + amplitude * np.sin(waves * phi))
    if side.all() or not side.any():
        raise StitchError(f"{model.name}: the cut leaves every face on one side")
    return _submodel(model, side, f"{model.name}-a"), _submodel(model, ~side, f"{model.name}-b")


def closed_part(model: Model, tolerance: float = 1e-6) -> Model:
    """The largest closed 2-manifold piece of a model, or a :class:`StitchError` saying why there is none.

    Vertices closer than ``tolerance`` times the bounding-box diagonal are merged (files
    split vertices at texture seams), faces that collapse are dropped, and the connected
    piece with the most faces is kept if every edge of it has exactly two faces.
    """
    size = float(np.linalg.norm(model.extents))
    keys = np.round(model.vertices / (tolerance * size)).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    faces = first[inverse.ravel()][model.faces]
    good = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    _, unique = np.unique(np.sort(faces, axis=1), axis=0, return_index=True)
    keep = np.zeros(len(faces), dtype=bool)
    keep[unique] = True
    keep &= good
    n = len(model.vertices)
    component = component_labels(mesh_edges(faces[keep], n), n)
    counts = np.bincount(component[faces[keep][:, 0]], minlength=component.max() + 1)
    keep &= component[faces[:, 0]] == int(np.argmax(counts))
    part = _submodel(replace(model, faces=faces), keep, model.name)
    _manifold_edges(part.faces, model.name)
    faces, flipped = consistent_winding(part.faces)
    if flipped or boundary_loops(faces):
        raise StitchError(f"{model.name}: its largest piece ({len(faces)} faces) is not closed and consistently "
                          f"wound")
    corners = part.vertices[part.faces]
    if np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])).sum() < 0:  # wound inwards
        part = _reversed(part)
    return part
