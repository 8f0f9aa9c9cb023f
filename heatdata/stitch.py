"""JASNOM (thesis ch. 7): one closed model from two non-overlapping meshes, aligned and stitched by their boundaries.

Two scans of an object (standing, then flipped; or two opposite cameras) cover it
together without overlapping, so overlap-based registration cannot align them. JASNOM
assumes the two boundaries are one curve seen in two frames: for every shift tau of the
second boundary's origin it builds the order-preserving assignment of eq. 7.7-7.8,
starts from the closed-form rigid alignment of the assigned points (Kabsch) and
minimizes J = J1 + beta J2 (eq. 7.2-7.4: squared stitching-edge lengths plus a
logistic penalty on edges that cross the other mesh, by the boundary normals) over
R in SO(3) and t; the best shift's assignment then becomes the triangle strip of 7.4.

Choices the thesis leaves open, decided here:

- J1 is divided by N s^2 (N boundary samples, s the RMS distance of the first boundary's
  samples from their centroid), so beta weighs two unitless terms whatever the object's
  size and the sampling.
- The boundary normal at a boundary vertex lies in its face's plane, perpendicular to
  the boundary, pointing away from the mesh.
- Both boundaries are resampled uniformly by arc length (7.5) to ``samples`` points for
  the alignment; the strip is built on the meshes' own boundary vertices.
"""

from __future__ import annotations

import logging
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import minimize
from scipy.spatial.transform import Rotation

from .errors import HeatdataError
from .mesh import boundary_loops, component_labels, consistent_winding, mesh_edges
from .models import Model, vertex_colors

log = logging.getLogger(__name__)


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


@dataclass(frozen=True)
class Alignment:
    """The best rigid motion of the second mesh onto the first, and how it was found.

    Attributes
    ----------
    rotation : (3, 3) float64
    translation : (3,) float64
        ``x = rotation @ y + translation`` maps the second mesh into the first's frame.
    shift : float
        The second boundary's origin, as a fraction of its length (tau / N).
    cost, edge_cost, crossing_cost : float
        J, J1 (normalized) and J2 at the optimum.
    facing : float
        Mean cosine between assigned boundary normals after the motion: near -1 when the
        meshes face each other across their boundaries, positive when they do not.
    costs : (N,) float64
        J at the optimum of every shift tau.
    seconds : float
    """

    rotation: np.ndarray
    translation: np.ndarray
    shift: float
    cost: float
    edge_cost: float
    crossing_cost: float
    facing: float
    costs: np.ndarray
    seconds: float


def _manifold_edges(faces: np.ndarray, name: str) -> None:
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    if (counts > 2).any():
        raise StitchError(f"{name}: {int((counts > 2).sum())} edge(s) belong to more than two faces: not a "
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
    loops = [loop for loop in boundary_loops(faces) if len(loop) >= 2]
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


def best_shift(first: Boundary, second: Boundary) -> float:
    """The origin of ``second`` (arc-length fraction) whose assignment (eq. 7.8) has the shortest edges (J1).

    For boundaries already in one frame, e.g. the other loops of two meshes aligned by
    their longest ones; every vertex of ``second`` is tried as the origin.
    """
    costs = [np.sum((first.points[order_preserving_assignment(first.arclength, second.arclength, shift)]
                     - second.points) ** 2) for shift in second.arclength]
    return float(second.arclength[int(np.argmin(costs))])


def _pair_loops(first: list[Boundary], second: list[Boundary]) -> list[tuple[Boundary, Boundary]]:
    """Greedy pairs of loops of two aligned meshes: nearest centroids, lengths within a factor 1.5."""
    pairs, taken = [], set()
    for b1 in first:
        best, gap = None, np.inf
        for k, b2 in enumerate(second):
            if k in taken or max(b1.length, b2.length) > 1.5 * min(b1.length, b2.length) or len(b2.loop) < 3:
                continue
            distance = np.linalg.norm(b1.points.mean(axis=0) - b2.points.mean(axis=0))
            if distance < gap and distance < 0.5 * max(b1.length, b2.length) / np.pi:
                best, gap = k, distance
        if best is not None and len(b1.loop) >= 3:
            taken.add(best)
            pairs.append((b1, second[best]))
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


def resample_loop(points: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray]:
    """``count`` points uniformly spaced by arc length along a closed polyline, from its first vertex.

    Returns the (count, 3) points and, for each, the index of the polyline vertex
    nearest along the curve.
    """
    if count < 3:
        raise StitchError(f"a boundary needs at least 3 samples, got {count}")
    closed = np.vstack([points, points[:1]])
    cumulative = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(closed, axis=0), axis=1))])
    targets = np.arange(count) / count * cumulative[-1]
    edge = np.clip(np.searchsorted(cumulative, targets, side="right") - 1, 0, len(points) - 1)
    step = cumulative[edge + 1] - cumulative[edge]
    frac = np.where(step > 0, (targets - cumulative[edge]) / np.where(step > 0, step, 1.0), 0.0)
    resampled = closed[edge] + frac[:, None] * (closed[edge + 1] - closed[edge])
    nearest = np.where(frac < 0.5, edge, (edge + 1) % len(points))
    return resampled, nearest


def order_preserving_assignment(first: np.ndarray, second: np.ndarray, shift: float) -> np.ndarray:
    """Eq. 7.8 with the reversal of 7.3: for each vertex of the second boundary, its vertex on the first.

    Parameters
    ----------
    first, second : (K,), (N,) float
        Normalized arc lengths of the two boundaries' vertices, in loop order, in [0, 1).
    shift : float
        The second boundary's origin tau, as a fraction of its length.

    Returns
    -------
    (N,) int64
        ``j = round(f(phi(l')))``: ``l' = second - shift`` (mod 1) is mapped to
        ``l = 1 - l'`` on the first boundary (the boundaries run in opposite directions
        on a consistently oriented surface) and ``f`` returns the vertex of the first
        boundary nearest to that arc length.
    """
    mapped = (1.0 - (second - shift)) % 1.0
    position = np.searchsorted(first, mapped)
    before = np.clip(position - 1, 0, len(first) - 1)
    after = position % len(first)
    gap_after = (first[after] - mapped) % 1.0
    gap_before = (mapped - first[before]) % 1.0
    return np.where(gap_after < gap_before, after, before).astype(np.int64)


def _rodrigues(w: np.ndarray) -> np.ndarray:
    """The rotation matrix of rotation vector ``w`` (a faster ``Rotation.from_rotvec(w).as_matrix()``)."""
    theta = float(np.sqrt(w @ w))
    if theta < 1e-12:
        return np.eye(3)
    k = w / theta
    cross = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(theta) * cross + (1.0 - np.cos(theta)) * (cross @ cross)


def _cost(params, x, y, n1, n2, scale, alpha, beta, rotation0):
    """J of eq. 7.4 (and J1, J2) for ``y`` centred on its centroid and ``x`` on ``y``'s target centroid.

    ``params``: a rotation vector applied after ``rotation0`` and a translation in units
    of ``scale`` (rotation about the centroid and translation then decouple).
    """
    rotation = _rodrigues(params[:3]) @ rotation0
    return _motion_cost(x, y @ rotation.T + scale * params[3:], n1, n2 @ rotation.T, scale, alpha, beta)


def _motion_cost(x, moved, n1, moved_n2, scale, alpha, beta) -> tuple[float, float, float]:
    """J, J1 and J2 (eq. 7.2-7.4) of assigned points ``x`` and ``moved`` (the second boundary after the motion)."""
    xi = x - moved  # from the second boundary to the first (eq. 7.1)
    edge = float(np.einsum("ij,ij->", xi, xi)) / (len(x) * scale ** 2)  # J1, eq. 7.2 (normalized)
    if beta == 0.0:
        return edge, edge, 0.0
    length = np.sqrt(np.einsum("ij,ij->i", xi, xi))
    unit = xi / np.where(length > 0, length, 1.0)[:, None]
    # eq. 7.3: xi should leave the second mesh along its outward normal and enter the first against its own
    with np.errstate(over="ignore"):
        crossing = float(np.mean(1.0 / (1.0 + np.exp(alpha * np.einsum("ij,ij->i", unit, moved_n2))))
                         + np.mean(1.0 / (1.0 + np.exp(-alpha * np.einsum("ij,ij->i", unit, n1)))))
    return edge + beta * crossing, edge, crossing


def _align_shift(args) -> tuple[float, np.ndarray, np.ndarray, float, float]:
    """The optimum of eq. 7.6 for one shift: Kabsch start, then BFGS over (rotation vector, t)."""
    tau, x_all, n1_all, y, n2, scale, alpha, beta = args
    count = len(y)
    target = (tau - np.arange(count)) % count  # eq. 7.8 on equally resampled loops
    x, n1 = x_all[target], n1_all[target]
    cx, cy = x.mean(axis=0), y.mean(axis=0)
    x, y = x - cx, y - cy
    rotation0 = Rotation.align_vectors(x, y)[0].as_matrix()  # closed form of the relaxed problem (beta = 0)
    result = minimize(lambda p: _cost(p, x, y, n1, n2, scale, alpha, beta, rotation0)[0], np.zeros(6),
                      method="BFGS", options={"gtol": 1e-6, "maxiter": 200})
    cost, edge, crossing = _cost(result.x, x, y, n1, n2, scale, alpha, beta, rotation0)
    rotation = _rodrigues(result.x[:3]) @ rotation0
    return cost, rotation, cx + scale * result.x[3:] - rotation @ cy, edge, crossing


def align(first: Boundary, second: Boundary, *, alpha: float = 10.0, beta: float = 1.0, samples: int = 128,
          workers: int = 2) -> Alignment:
    """Eq. 7.5-7.6: the rigid motion of ``second`` onto ``first`` that minimizes J over every shift tau.

    Parameters
    ----------
    first, second : Boundary
    alpha : float
        Steepness of the logistic crossing penalty (eq. 7.3).
    beta : float
        Weight of the crossing penalty J2 (eq. 7.4); 0 for hole patching (7.5).
    samples : int
        Points per boundary, uniform by arc length (the shifts tau are these N).
    workers : int
        Processes the shifts are spread over (1: in this process).
    """
    if alpha <= 0 or beta < 0:
        raise StitchError(f"alpha must be positive and beta non-negative, got {alpha}, {beta}")
    ratio = max(first.length, second.length) / min(first.length, second.length)
    if ratio > 1.5:
        log.warning("the boundaries' lengths differ by a factor %.2f: the arc-length assignment of eq. 7.8 "
                    "assumes they trace one curve", ratio)
    begin = time.perf_counter()
    x, n1, y, n2, scale = _resampled(first, second, samples)
    jobs = [(tau, x, n1, y, n2, scale, alpha, beta) for tau in range(samples)]
    if workers > 1:
        with ProcessPoolExecutor(workers) as pool:
            results = list(pool.map(_align_shift, jobs, chunksize=max(1, samples // (4 * workers))))
    else:
        results = [_align_shift(job) for job in jobs]
    costs = np.array([r[0] for r in results])
    best = int(np.argmin(costs))
    cost, rotation, translation, edge, crossing = results[best]
    return _alignment(best, costs, rotation, translation, edge, crossing, n1, n2, begin)


def alignment_at(first: Boundary, second: Boundary, rotation: np.ndarray, translation: np.ndarray, *,
                 alpha: float = 10.0, beta: float = 1.0, samples: int = 128) -> Alignment:
    """A known rigid motion of ``second`` onto ``first`` (registered cameras, a turntable) and its best shift.

    Nothing is optimized: J (eq. 7.4) is evaluated at the motion for every shift tau and the
    cheapest is kept, so that :func:`stitch` can join scans whose motion is known, and an
    experiment can compare J at the true motion with J at :func:`align`'s optimum.
    """
    if alpha <= 0 or beta < 0:
        raise StitchError(f"alpha must be positive and beta non-negative, got {alpha}, {beta}")
    begin = time.perf_counter()
    rotation, translation = np.asarray(rotation, np.float64), np.asarray(translation, np.float64)
    x, n1, y, n2, scale = _resampled(first, second, samples)
    moved, moved_n2 = y @ rotation.T + translation, n2 @ rotation.T
    results = [_motion_cost(x[(tau - np.arange(samples)) % samples], moved,
                            n1[(tau - np.arange(samples)) % samples], moved_n2, scale, alpha, beta)
               for tau in range(samples)]
    costs = np.array([r[0] for r in results])
    best = int(np.argmin(costs))
    return _alignment(best, costs, rotation, translation, results[best][1], results[best][2], n1, n2, begin)


def _resampled(first: Boundary, second: Boundary, samples: int):
    """Both boundaries resampled by arc length, their normals there, and the first's RMS radius (J1's scale)."""
    x, nearest1 = resample_loop(first.points, samples)
    y, nearest2 = resample_loop(second.points, samples)
    scale = float(np.sqrt(np.mean(np.sum((x - x.mean(axis=0)) ** 2, axis=1))))
    return x, first.normals[nearest1], y, second.normals[nearest2], scale


def _alignment(best, costs, rotation, translation, edge, crossing, n1, n2, begin) -> Alignment:
    samples = len(costs)
    target = (best - np.arange(samples)) % samples
    facing = float(np.mean(np.sum(n1[target] * (n2 @ rotation.T), axis=1)))
    return Alignment(rotation=rotation, translation=translation, shift=best / samples, cost=float(costs[best]),
                     edge_cost=edge, crossing_cost=crossing, facing=facing, costs=costs,
                     seconds=time.perf_counter() - begin)


def strip_faces(first: Boundary, second: Boundary, shift: float, offset: int) -> np.ndarray:
    """7.4: the triangle strip between two boundaries from the order-preserving assignment of ``shift``.

    Walking the first boundary forwards and the second backwards (their directions are
    opposite), each step advances on one of them and adds one triangle, so the strip has
    ``K + N`` triangles, no two edges cross, and each boundary edge is used once in the
    opposite direction to its own face: the union is a consistently oriented 2-manifold.
    Vertices of the first boundary without an assignment take the previous target (7.4).

    Parameters
    ----------
    offset : int
        Added to the second mesh's vertex indices (its vertices follow the first's).

    Returns
    -------
    (K + N, 3) int64
    """
    k, n = len(first.loop), len(second.loop)
    target = order_preserving_assignment(first.arclength, second.arclength, shift)
    origin = int(np.argmin((second.arclength - shift) % 1.0))  # l' = 0
    walk = (origin - np.arange(n)) % n  # the second boundary, backwards from its origin
    # targets on the first boundary, unwrapped so that they never decrease along the walk
    unwrapped = (target[walk] - target[walk[0]]) % k
    unwrapped = np.maximum.accumulate(unwrapped) + target[walk[0]]
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


def transformed(model: Model, rotation: np.ndarray, translation: np.ndarray) -> Model:
    """``model`` moved rigidly: ``x -> rotation @ x + translation``."""
    return replace(model, vertices=model.vertices @ np.asarray(rotation).T + np.asarray(translation))


@dataclass(frozen=True)
class Stitched:
    """What :func:`stitch` returns: the stitched model, the alignment, the two longest boundaries, how many loop
    pairs were stitched and how many loops stay open."""

    model: Model
    alignment: Alignment
    first: Boundary
    second: Boundary
    loop_pairs: int
    open_loops: int


def rigid_motion(motion) -> np.ndarray:
    """``motion`` as a (4, 4) float64 rigid transform, or a :class:`StitchError`: a rotation (no reflection), a
    translation, last row 0 0 0 1."""
    m = np.asarray(motion, np.float64)
    if (m.shape != (4, 4) or not np.allclose(m[:3, :3] @ m[:3, :3].T, np.eye(3), atol=1e-6)
            or np.linalg.det(m[:3, :3]) < 0 or not np.allclose(m[3], [0.0, 0.0, 0.0, 1.0])):
        raise StitchError(f"motion must be a 4x4 rigid transform (a rotation, no reflection, last row 0 0 0 1), "
                          f"got shape {m.shape}")
    return m


def stitch(first: Model, second: Model, *, alpha: float = 10.0, beta: float = 1.0, samples: int = 128,
           workers: int = 2, name: str | None = None, motion: np.ndarray | None = None) -> Stitched:
    """JASNOM: align ``second`` onto ``first`` by their longest boundaries and stitch them into one model.

    The longest loops align the meshes (7.2-7.3, 7.5). Beyond the thesis, the other loops
    (a cut through a concave object leaves several) are paired by nearest centroid and
    similar length and stitched at that alignment, each at its shortest-edge shift.

    Parameters
    ----------
    first, second : Model
        Two meshes that together cover an object without overlapping, each a 2-manifold
        with a boundary, both wound the same way about the object (both outwards, or both
        inwards as two of heatdata's views are, whose faces point away from their cameras).
    alpha, beta, samples, workers
        As for :func:`align`.
    name : str, optional
        The stitched model's name (default: ``first.name + "+" + second.name``).
    motion : (4, 4) float, optional
        A known rigid motion of ``second`` into ``first``'s frame (registered cameras, a
        turntable): no alignment is searched, only the shift (:func:`alignment_at`), and
        boundaries that do not face each other there (a gap of grazing surface between two
        opposite scans) are stitched anyway, with a warning.

    Returns
    -------
    Stitched
        ``model`` holds the first mesh's vertices, then the second's moved into the first's
        frame, and the strip's triangles last (coloured by their corners' vertex colours);
        both meshes' textures are kept.

    Raises
    ------
    StitchError
        As :func:`boundary`, or bad ``alpha`` / ``beta``.
    """
    loops1, loops2 = boundaries(first), boundaries(second)
    b1, b2 = _longest(loops1, first.name), _longest(loops2, second.name)
    if motion is None:
        alignment = align(b1, b2, alpha=alpha, beta=beta, samples=samples, workers=workers)
    else:
        motion = rigid_motion(motion)
        alignment = alignment_at(b1, b2, motion[:3, :3], motion[:3, 3], alpha=alpha, beta=beta, samples=samples)
    if alignment.facing > 0 and motion is not None:
        log.warning("%s and %s do not face each other across their boundaries at the given motion (mean cosine of "
                    "the boundary normals %+.2f): the strip spans a gap the scans did not see", first.name,
                    second.name, alignment.facing)
    elif alignment.facing > 0:
        raise StitchError(f"{first.name} and {second.name} do not face each other across their boundaries after "
                          f"the best alignment (mean cosine of the boundary normals {alignment.facing:+.2f}): either "
                          "both are wound the same way round the cut (reverse one's faces) or their longest "
                          "boundaries are not one curve (large gaps or missing parts)")
    moved = transformed(second, alignment.rotation, alignment.translation)
    moved_loops = [_moved(b, alignment.rotation, alignment.translation) for b in loops2]
    moved_b2 = moved_loops[0]
    offset = len(first.vertices)
    strips = [strip_faces(b1, moved_b2, alignment.shift, offset)]
    # the other loops (a cut through a concave object leaves several) are stitched at the same alignment
    pairs = _pair_loops(loops1[1:], moved_loops[1:])
    strips += [strip_faces(l1, l2, best_shift(l1, l2), offset) for l1, l2 in pairs]
    open_loops = b1.loops + moved_b2.loops - 2 * (1 + len(pairs))
    if open_loops:
        log.warning("%d boundary loop(s) of %s and %s have no partner and stay open", open_loops, first.name,
                    second.name)
    strip = np.vstack(strips)
    colors = np.vstack([vertex_colors(first), vertex_colors(moved)])
    faces = np.vstack([first.faces, moved.faces + offset, strip])
    model = Model(
        name=name or f"{first.name}+{second.name}",
        vertices=np.vstack([first.vertices, moved.vertices]),
        faces=faces,
        corner_colors=np.concatenate([first.corner_colors, moved.corner_colors,
                                      colors[strip].astype(np.float32)]),
        corner_uv=np.concatenate([first.corner_uv, moved.corner_uv, np.zeros((len(strip), 3, 2), np.float32)]),
        face_texture=np.concatenate([first.face_texture,
                                     np.where(moved.face_texture >= 0, moved.face_texture + len(first.textures), -1),
                                     np.full(len(strip), -1)]).astype(np.int32),
        textures=list(first.textures) + list(moved.textures),
        label=first.label or second.label, source=f"JASNOM of {first.source or first.name} and "
                                                   f"{second.source or second.name}",
        repairs=list(first.repairs) + list(second.repairs))
    log.info("stitched %s: shift %.3f, J %.4g (J1 %.3g, J2 %.3g), %d loop pair(s), %d strip triangles, %.1f s",
             model.name, alignment.shift, alignment.cost, alignment.edge_cost, alignment.crossing_cost,
             1 + len(pairs), len(strip), alignment.seconds)
    return Stitched(model=model, alignment=alignment, first=b1, second=moved_b2, loop_pairs=1 + len(pairs),
                    open_loops=open_loops)


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
        part = replace(part, faces=part.faces[:, ::-1].copy(), corner_colors=part.corner_colors[:, ::-1].copy(),
                       corner_uv=part.corner_uv[:, ::-1].copy())
    return part
