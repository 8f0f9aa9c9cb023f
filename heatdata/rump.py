"""HBRD, the heat-based rump descriptor (thesis ch. 8, Algorithm 8.1): how far a rump is from flat.

Given a rump surface and four bony landmarks (left and right hip bones, left and right pin
bones), 8.2 rotates the surface so that the landmarks lie in the x-y plane and keeps the
part above it (z > 0, towards the sensor); normalizes x and y by the projective map that
sends the landmarks to canonical positions (z kept); and builds the planar twin, the same
mesh with z = 0. 8.3.2 starts heat at the vertex nearest the landmarks' centre on both
surfaces and compares the temperatures along the planar shortest path from the centre to
the left hip bone, at times t_k spread exponentially from 1/700 to 1/10: z_k is the
maximum over the path of T_rump(t_k) - T_plane(t_k) (eq. 8.1). A flat rump gives z = 0; the
rounder the rump, the slower heat leaves the centre, and the larger z.

Choices the thesis leaves open, decided here:

- The landmark plane is their least-squares plane; the side kept faces ``toward`` (the
  sensor: by default the origin, where a view's camera sits).
- Canonical positions, when not given, are the landmarks' own symmetrized trapezoid (the
  hips' and the pins' mean half-widths, their mean heights): this only corrects the
  landmarks' asymmetry. For a population, pass one canonical set (e.g. the population's
  mean trapezoid) so that every rump is normalized to the same frame, as the thesis does.
- The rump is the connected part above the plane that holds the centre vertex, "above"
  reaching 5% of the landmarks' spread below it, and all of the surface between the four
  bones whatever its height: a thin rump is flat or hollow between its bones, and with
  sensor noise z > 0 alone cuts it into specks.
- Beyond the thesis, ``extent`` keeps only the surface near the bones (their bounding
  box, scaled): a goat's body falls away beyond its hip and pin bones, so z > 0 bounds its
  rump, but a human's buttocks do not (the proxy of ``heatdata.io.bodies``).
- The thesis does not say in which unit its times are; here metres (the canonical
  positions are in metres), so that heat spreads sqrt(4t) = 7.6 cm at 1/700 and 63 cm at
  1/10 over a rump some 20 cm long.
- The heat is eq. 5.2 on the Laplacian of eq. 2.2-2.3, with as many eigenpairs as make
  it exact to 1e-8 at the first time (``exp(-lambda_k t_1)``; the thesis used 300): it
  agrees with the dense Laplacian's whole spectrum to 2e-10, at a small fraction of its cost
  (``benchmarks/bench_hbrd.py``; timings in ``benchmarks/README.md``).
  ``expm_multiply`` costs t ||L||, about 3e6 t on a rump's 2 mm edges: it is not a usable
  reference here. Temperatures are divided by the equilibrium temperature (1/n).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra
from scipy.spatial import cKDTree

from heatdata.core.mesh import component_labels, mesh_edges
from heatdata.core.spectrum import HeatOperator, eigen_spectrum, laplacian
from heatdata.errors import HeatdataError, RumpError

T_FIRST, T_LAST = 1.0 / 700.0, 1.0 / 10.0  # the time window of 8.3.2 (m^2, as L is in 1/m^2)
COPLANAR = 0.25  # landmarks farther than this fraction of the quadrilateral's size from their plane: an error
OFF_MESH = 0.1  # a landmark farther than this fraction of the quadrilateral's size from every vertex: an error
BELOW = 0.05  # the rump reaches this fraction of the landmarks' spread below their plane (sensor noise, thin rumps)
FIRST_MODES, TRUNCATION = 200, 1e-8  # eigenpairs first computed; doubled until exp(-lambda_k t_1) <= TRUNCATION


@dataclass(frozen=True)
class RumpHeat:
    """What :func:`rump_heat` computed.

    Attributes
    ----------
    vertices : (r, 3) float64
        The rump, normalized: canonical x-y, z above the landmark plane (metres).
    faces : (f, 3) int64
    landmarks : (4, 2) float64
        The canonical landmark positions (metres).
    center : int
        The heat source (the vertex nearest the landmarks' centre).
    path : (p,) int64
        The planar shortest path from ``center`` to the left hip bone.
    times : (K,) float64
    difference : (K, r) float64
        T_rump - T_plane at every vertex and time (equilibrium = 1).
    descriptor : (K,) float64
        HBRD, eq. 8.1: the maximum of ``difference`` over ``path`` at each time.
    """

    vertices: np.ndarray
    faces: np.ndarray
    landmarks: np.ndarray
    center: int
    path: np.ndarray
    times: np.ndarray
    difference: np.ndarray
    descriptor: np.ndarray


def hbrd_times(count: int = 32) -> np.ndarray:
    """(count,) times t_k = 0.1 e^{k dt}, k = -(count - 1) .. 0, spanning 1/700 to 1/10 (8.3.2)."""
    return T_LAST * np.exp(np.linspace(np.log(T_FIRST / T_LAST), 0.0, count))


def landmark_frame(landmarks: np.ndarray, toward: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The landmarks' plane as a frame: origin (their centroid) and rotation rows (x left-to-right, y pins-to-hips,
    z the plane's normal towards ``toward``, default towards the origin).

    Raises
    ------
    RumpError
        Not four finite 3D points, degenerate, or far from coplanar.
    """
    p = np.asarray(landmarks, dtype=np.float64)
    if p.shape != (4, 3) or not np.isfinite(p).all():
        raise RumpError(
            f"landmarks must be four finite 3D points (hip left, hip right, pin left, pin right), got "
            f"shape {p.shape}" + ("" if p.shape != (4, 3) else " with NaN")
        )
    origin = p.mean(axis=0)
    size = float(np.mean(np.linalg.norm(p - origin, axis=1)))
    if size <= 0:
        raise RumpError("the four landmarks coincide")
    _, singular, axes = np.linalg.svd(p - origin)
    normal = axes[2]
    if singular[1] < 1e-6 * singular[0]:
        raise RumpError("the four landmarks lie on one line: they span no plane")
    off = float(np.max(np.abs((p - origin) @ normal)))
    if off > COPLANAR * size:
        raise RumpError(
            f"the landmarks are far from coplanar: one lies {off:.3g} from their plane, "
            f"{off / size:.0%} of their spread (at most {COPLANAR:.0%})"
        )
    toward = -origin if toward is None else np.asarray(toward, dtype=np.float64)
    if normal @ toward < 0:
        normal = -normal
    across = 0.5 * (p[1] + p[3]) - 0.5 * (p[0] + p[2])  # left to right
    x = across - normal * (across @ normal)
    if np.linalg.norm(x) < 1e-9 * size:
        raise RumpError("the left and right landmarks coincide")
    x /= np.linalg.norm(x)
    y = np.cross(normal, x)
    if (0.5 * (p[0] + p[1]) - 0.5 * (p[2] + p[3])) @ y < 0:
        raise RumpError(
            "the landmarks are out of order: give hip left, hip right, pin left, pin right, as seen from the sensor"
        )
    return origin, np.vstack([x, y, normal])


def homography(source: np.ndarray, target: np.ndarray) -> np.ndarray:
    """(3, 3) projective map sending four 2D points ``source`` to ``target`` (direct linear transform)."""
    rows, rhs = [], []
    for (x, y), (u, v) in zip(np.asarray(source, float), np.asarray(target, float)):
        rows += [[x, y, 1, 0, 0, 0, -u * x, -u * y], [0, 0, 0, x, y, 1, -v * x, -v * y]]
        rhs += [u, v]
    try:
        h = np.linalg.solve(np.array(rows), np.array(rhs))
    except np.linalg.LinAlgError as error:
        raise RumpError("three of the landmarks are collinear: no projective normalization") from error
    return np.append(h, 1.0).reshape(3, 3)


def apply_homography(h: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(n, 2) points mapped by a (3, 3) homography."""
    mapped = np.column_stack([points, np.ones(len(points))]) @ h.T
    return mapped[:, :2] / mapped[:, 2:]


def landmark_trapezoid(landmarks: np.ndarray, toward: np.ndarray | None = None) -> np.ndarray:
    """(4, 2) the landmarks' symmetrized trapezoid in their plane (metres): the default canonical positions.

    The mean over a population is one canonical frame for all its rumps.
    """
    origin, rotation = landmark_frame(landmarks, toward)
    return symmetric_trapezoid(((np.asarray(landmarks, np.float64) - origin) @ rotation.T)[:, :2])


def symmetric_trapezoid(planar_landmarks: np.ndarray) -> np.ndarray:
    """(4, 2) canonical positions from landmarks in their plane: hips and pins symmetric about x = 0."""
    p = np.asarray(planar_landmarks, dtype=np.float64)
    hip, pin = 0.5 * (p[1, 0] - p[0, 0]), 0.5 * (p[3, 0] - p[2, 0])
    y_hip, y_pin = 0.5 * (p[0, 1] + p[1, 1]), 0.5 * (p[2, 1] + p[3, 1])
    return np.array([[-hip, y_hip], [hip, y_hip], [-pin, y_pin], [pin, y_pin]])


def rump_heat(
    vertices: np.ndarray,
    faces: np.ndarray,
    landmarks: np.ndarray,
    *,
    canonical: np.ndarray | None = None,
    times: np.ndarray | None = None,
    toward: np.ndarray | None = None,
    extent: float | None = None,
) -> RumpHeat:
    """Algorithm 8.1 on a surface with its four landmarks; :func:`hbrd` returns its descriptor.

    Parameters
    ----------
    vertices : (n, 3) float
        Metres (a view's camera-frame vertices, or any mesh with ``toward`` given).
    faces : (m, 3) int
    landmarks : (4, 3) float
        Hip left, hip right, pin left, pin right, on or near the surface.
    canonical : (4, 2) float, optional
        Where the projective normalization sends the landmarks, in metres, centred on the
        origin (default: their own symmetrized trapezoid, :func:`symmetric_trapezoid`).
    times : (K,) float, optional
        Default :func:`hbrd_times`.
    toward : (3,) float, optional
        A direction from the rump to the sensor (default: to the origin).
    extent : float, optional
        Keep only the surface within the canonical landmarks' bounding box scaled by
        ``extent`` about its centre (default: all of it, as the thesis: a goat's body falls
        away beyond its hip and pin bones; a human's buttocks do not).

    Returns
    -------
    RumpHeat
        The normalized rump, its heat source and path, and the HBRD (``descriptor``) at
        :func:`hbrd_times`.

    Raises
    ------
    RumpError
        Bad landmarks (missing, far from coplanar, off the mesh), or nothing of the
        surface above their plane around their centre.
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    if v.ndim != 2 or v.shape[1] != 3 or f.ndim != 2 or f.shape[1] != 3 or not len(f):
        raise RumpError(f"need (n, 3) vertices and (m, 3) faces, got {v.shape} and {f.shape}")
    if f.min() < 0 or f.max() >= len(v):
        raise RumpError(f"face indices run from {f.min()} to {f.max()}, not within the {len(v)} vertices")
    if not np.isfinite(v).all():
        raise RumpError("the vertices hold NaN or infinite coordinates")
    origin, rotation = landmark_frame(landmarks, toward)
    p = np.asarray(landmarks, dtype=np.float64)
    size = float(np.mean(np.linalg.norm(p - origin, axis=1)))
    gap, _ = cKDTree(v).query(p)
    if gap.max() > OFF_MESH * size:
        which = int(np.argmax(gap))
        raise RumpError(
            f"landmark {which} ({('hip left', 'hip right', 'pin left', 'pin right')[which]}) is "
            f"{gap[which]:.3g} from the nearest vertex, off the mesh (at most {OFF_MESH:.0%} of the "
            f"landmarks' spread, {OFF_MESH * size:.3g})"
        )
    local = (v - origin) @ rotation.T
    planar_landmarks = ((p - origin) @ rotation.T)[:, :2]
    target = symmetric_trapezoid(planar_landmarks) if canonical is None else np.asarray(canonical, np.float64)
    if target.shape != (4, 2) or not np.isfinite(target).all():
        raise RumpError(f"canonical must be (4, 2) finite positions, got {target.shape}")
    h = homography(planar_landmarks, target)
    normalized = np.column_stack([apply_homography(h, local[:, :2]), local[:, 2]])
    keep = (normalized[:, 2] > -BELOW * size) | _inside(normalized[:, :2], target)
    if extent is not None:
        if not extent > 0:
            raise RumpError(f"extent must be positive, got {extent}")
        half = extent * np.abs(target - target.mean(axis=0)).max(axis=0)
        keep &= (np.abs(normalized[:, :2] - target.mean(axis=0)) <= half).all(axis=1)
    rump_v, rump_f = _rump(normalized, f, target, keep)
    plane = rump_v.copy()
    plane[:, 2] = 0.0
    center = int(np.argmin(np.linalg.norm(plane[:, :2] - target.mean(axis=0), axis=1)))
    hip = int(np.argmin(np.linalg.norm(plane[:, :2] - target[0], axis=1)))
    edges = mesh_edges(rump_f, len(rump_v))
    path = _shortest_path(plane, edges, center, hip)
    times = hbrd_times() if times is None else np.sort(np.asarray(times, dtype=np.float64))
    if times.ndim != 1 or not len(times) or times[0] <= 0:
        raise RumpError(f"times must be positive, got {times}")
    difference = _heat(rump_v, edges, center, times) - _heat(plane, edges, center, times)
    return RumpHeat(
        vertices=rump_v,
        faces=rump_f,
        landmarks=target,
        center=center,
        path=path,
        times=times,
        difference=difference,
        descriptor=difference[:, path].max(axis=1),
    )


def population_hbrd(
    scans: list[tuple], *, extent: float | None = None, times: np.ndarray | None = None
) -> list[RumpHeat]:
    """:func:`rump_heat` of every ``(view, landmarks)`` with one canonical frame: the population's mean trapezoid."""
    from heatdata.log import progress

    canonical = np.mean([landmark_trapezoid(landmarks) for _, landmarks in scans], axis=0)
    return [
        rump_heat(view.vertices, view.faces, landmarks, canonical=canonical, extent=extent, times=times)
        for view, landmarks in progress(scans, desc="HBRD", unit="rump")
    ]


def condition_measures(descriptors: np.ndarray, condition: np.ndarray, *, n_neighbors: int = 6) -> dict:
    """How well HBRDs order a population by its condition and tell the thinnest third apart (8.4, Fig. 8.8).

    Returns
    -------
    dict
        ``embedding`` (N, 3): the descriptors' 3D Isomap; ``spearman_isomap``: the rank
        correlation of ``condition`` with its first axis (absolute: an axis has no sign);
        ``spearman_sum``: with the descriptor's sum over time; ``thin`` (N,) bool: the
        thinnest third; ``silhouette_thin``: their silhouette against the rest in the
        Isomap; ``loo_accuracy_thin``: leave-one-out accuracy of a logistic regression of
        thinnest third against the rest on the standardized log-descriptors.
    """
    from scipy.stats import spearmanr
    from sklearn.linear_model import LogisticRegression
    from sklearn.manifold import Isomap
    from sklearn.metrics import silhouette_score
    from sklearn.model_selection import LeaveOneOut, cross_val_score
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import StandardScaler

    descriptors, condition = np.asarray(descriptors, np.float64), np.asarray(condition, np.float64)
    if len(descriptors) != len(condition) or len(descriptors) < max(6, n_neighbors + 1):
        raise RumpError(
            f"need one condition per descriptor and more than {max(5, n_neighbors)} of them, got "
            f"{len(descriptors)} and {len(condition)}"
        )
    embedding = Isomap(n_neighbors=n_neighbors, n_components=3).fit_transform(descriptors)
    thin = condition <= np.quantile(condition, 1 / 3)
    classifier = make_pipeline(StandardScaler(), LogisticRegression(max_iter=2000))
    features = np.log(np.maximum(descriptors, 0.0) + 1e-6)
    return {
        "embedding": embedding,
        "thin": thin,
        "spearman_isomap": float(abs(spearmanr(condition, embedding[:, 0])[0])),
        "spearman_sum": float(spearmanr(condition, descriptors.sum(axis=1))[0]),
        "silhouette_thin": float(silhouette_score(embedding, thin)),
        "loo_accuracy_thin": float(cross_val_score(classifier, features, thin, cv=LeaveOneOut()).mean()),
    }


def hbrd(vertices: np.ndarray, faces: np.ndarray, landmarks: np.ndarray, **kwargs) -> np.ndarray:
    """HBRD (eq. 8.1, Algorithm 8.1): (K,) maximum temperature difference, rump minus its planar twin.

    ``landmarks`` (4, 3): hip left, hip right, pin left, pin right. Keywords as :func:`rump_heat`.

    Parameters
    ----------
    vertices : (n, 3) float
        The rump scan's vertices, metres.
    faces : (f, 3) int
        Its triangles.
    landmarks : (4, 3) float
        Hip left, hip right, pin left, pin right.
    **kwargs
        As for :func:`rump_heat`.

    Returns
    -------
    (K,) float64
        The HBRD at the K times of :func:`hbrd_times`.
    """
    return rump_heat(vertices, faces, landmarks, **kwargs).descriptor


def _inside(points: np.ndarray, landmarks: np.ndarray) -> np.ndarray:
    """Which points lie inside the quadrilateral of the landmarks (hip left, hip right, pin right, pin left)."""
    corners = landmarks[[0, 1, 3, 2]]
    edges = np.roll(corners, -1, axis=0) - corners
    cross = edges[:, 0] * (points[:, None, 1] - corners[:, 1]) - edges[:, 1] * (points[:, None, 0] - corners[:, 0])
    return (cross >= 0).all(axis=1) | (cross <= 0).all(axis=1)


def _rump(
    normalized: np.ndarray, faces: np.ndarray, target: np.ndarray, keep: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The connected part of the kept vertices (above the plane) that holds the kept vertex nearest the centre."""
    kept = faces[keep[faces].all(axis=1)]
    if not len(kept):
        raise RumpError(
            "no face of the surface lies above the landmarks' plane (z > 0): is ``toward`` the sensor's side?"
        )
    n = len(normalized)
    label = component_labels(mesh_edges(kept, n), n)
    used = np.unique(kept)
    center = used[np.argmin(np.linalg.norm(normalized[used, :2] - target.mean(axis=0), axis=1))]
    keep = np.zeros(n, bool)
    keep[used[label[used] == label[center]]] = True
    kept = kept[keep[kept[:, 0]]]
    if len(kept) < 3:
        raise RumpError("the part above the landmarks' plane around their centre has fewer than 3 faces")
    index = np.full(n, -1, np.int64)
    index[keep] = np.arange(int(keep.sum()))
    return normalized[keep], index[kept]


def _shortest_path(plane: np.ndarray, edges: np.ndarray, start: int, end: int) -> np.ndarray:
    n = len(plane)
    length = np.linalg.norm(plane[edges[:, 0]] - plane[edges[:, 1]], axis=1)
    graph = sp.coo_matrix((length, (edges[:, 0], edges[:, 1])), shape=(n, n)).tocsr()
    distance, previous = dijkstra(graph, directed=False, indices=start, return_predecessors=True)
    if not np.isfinite(distance[end]):
        raise RumpError("the left hip bone is not connected to the rump's centre above the landmarks' plane")
    path = [end]
    while path[-1] != start:
        path.append(int(previous[path[-1]]))
    return np.array(path[::-1])


def _heat(vertices: np.ndarray, edges: np.ndarray, source: int, times: np.ndarray) -> np.ndarray:
    """(K, n) temperatures after a unit pulse at ``source`` (equilibrium = 1), eq. 5.2 on enough eigenpairs."""
    try:
        op = HeatOperator(laplacian(vertices, edges, "rump"), name="rump")
    except HeatdataError as error:
        raise RumpError(
            f"the rump's planar twin has coincident vertices (the surface folds over the landmarks' plane): {error}"
        ) from error
    k = min(FIRST_MODES, op.n - 2)
    while True:
        spectrum = eigen_spectrum(op, k)
        if spectrum.truncation(times[0]) <= TRUNCATION or k >= op.n - 2:
            break
        k = min(2 * k, op.n - 2)
    decay = np.exp(-np.outer(times, spectrum.values))  # (K, k)
    return (decay * spectrum.vectors[source]) @ spectrum.vectors.T * spectrum.rates.sum()
