"""The JASNOM cost (eq. 7.2-7.4, made continuous) and the constraint on the scans' orientation."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree
from scipy.special import expit

from heatdata.errors import StitchError
from heatdata.io.models import Model
from heatdata.jasnom.boundary import Boundary, _unit, resample_loop
from heatdata.jasnom.defaults import MAX_WEIGHT
from heatdata.jasnom.rays import RayDepths


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
    def of(cls, loops: list[Boundary], samples: int) -> _Curve:
        loops = [b for b in loops if len(b.loop) >= 3]
        counts = [
            samples if k == 0 else max(3, round(samples * b.length / loops[0].length)) for k, b in enumerate(loops)
        ]
        resampled = [resample_loop(b.points, count, b.normals) for b, count in zip(loops, counts, strict=True)]
        # every loop split to half the finest sample spacing, so that the nearest vertices find the closest segment
        spacing = min(b.length / (2 * count) for b, count in zip(loops, counts, strict=True))
        dense = [_densified(b, spacing) for b in loops]
        counts = [len(points) for points, _ in dense]
        starts = np.cumsum([0, *counts])
        index = np.arange(starts[-1])
        first, size = np.repeat(starts[:-1], counts), np.repeat(counts, counts)
        points = np.vstack([points for points, _ in dense])
        return cls(
            points,
            np.vstack([normals for _, normals in dense]),
            first + (index - first - 1) % size,
            first + (index - first + 1) % size,
            cKDTree(points),
            np.vstack([r[0] for r in resampled]),
            np.vstack([r[1] for r in resampled if r[1] is not None]),
        )

    def closest(self, queries: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(q, 3) closest points on the loops and the boundary normal there (interpolated along the segment).

        The segments tried are the two at each of the 4 nearest vertices.
        """
        nearest = self.tree.query(queries, k=min(4, len(self.points)))[1].reshape(len(queries), -1)
        a = np.concatenate([self.before[nearest], nearest], axis=1)  # (q, 8) segments a -> b
        b = np.concatenate([nearest, self.after[nearest]], axis=1)
        start, segment = self.points[a], self.points[b] - self.points[a]
        squared = np.einsum("qkj,qkj->qk", segment, segment)
        f = np.clip(
            np.einsum("qkj,qkj->qk", queries[:, None] - start, segment) / np.where(squared > 0, squared, 1.0), 0.0, 1.0
        )
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


#: the most points of a scan the free-space term moves into the other's camera frame at each pose: 500 cost a
#: quarter of 2,000's time
FREE_SPACE_PROBES = 500


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
    rays : RayDepths
        The centroids as the camera saw them: what :meth:`in_front` compares with.
    spacing : float
        The mean distance from a centroid to its nearest neighbour: how far in front of the surface a point must
        lie to count (the sampled surface is only known to within it).
    probes : (p, 3) float64
        At most :data:`FREE_SPACE_PROBES` of the centroids (a seeded sample): the points the free-space term moves
        into the other scan's camera frame.
    """

    centroids: np.ndarray
    normals: np.ndarray
    toward_camera: float
    rays: RayDepths
    spacing: float
    probes: np.ndarray

    @classmethod
    def of(cls, model: Model, count: int = 2000) -> ScanSurface:
        corners = model.vertices[model.faces]
        normals = 0.5 * np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        centroids = corners.mean(axis=1)
        area = np.linalg.norm(normals, axis=1)
        if len(area) > count:
            keep = np.random.default_rng(0).choice(len(area), count, replace=False, p=area / area.sum())
            centroids, normals = centroids[keep], normals[keep]
        return cls(
            centroids,
            normals,
            float(np.sign(np.sum(np.einsum("ij,ij->i", -centroids, normals))) or 1.0),
            RayDepths.of(centroids),
            float(cKDTree(centroids).query(centroids, k=2)[0][:, 1].mean()),
            centroids[np.sort(np.random.default_rng(0).permutation(len(centroids))[:FREE_SPACE_PROBES])],
        )

    def faces_camera(self, rotation: np.ndarray, translation: np.ndarray, camera: np.ndarray) -> float:
        """The share of the surface's area, moved by the motion, that faces ``camera`` the way it faced its own."""
        centroids, normals = self.centroids @ rotation.T + translation, self.normals @ rotation.T
        facing = self.toward_camera * np.einsum("ij,ij->i", camera - centroids, normals)
        area = np.linalg.norm(normals, axis=1)
        return float(area[facing > 0].sum() / area.sum())

    def in_front(self, points: np.ndarray) -> np.ndarray:
        """How far each of ``points`` (m, 3), in this scan's camera frame, stands in front of the surface the camera
        measured along its ray, beyond :attr:`spacing` (0 behind it, and off the scan's rays).

        Returns
        -------
        (m,) float64
        """
        return np.nan_to_num(np.maximum(self.rays.in_front(points) - self.spacing, 0.0), nan=0.0)

    def free_space(self, other: ScanSurface, rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
        """The free-space residuals of two scans at ``x1 = rotation @ x2 + translation`` (``self`` is scan 1): the
        RMS of how far scan 2's probes stand in front of what camera 1 measured, and scan 1's in camera 2.

        Returns
        -------
        (2,) float64
            In the scans' units; 0 where each lies behind the other's surface or off its rays.
        """
        ahead = (
            self.in_front(other.probes @ rotation.T + translation),
            other.in_front((self.probes - translation) @ rotation),
        )
        return np.array([np.sqrt(np.mean(f**2)) for f in ahead])


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


def _residuals(
    rotation: np.ndarray, translation: np.ndarray, c1: _Curve, c2: _Curve, w: _Weights
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


def _flat_residuals(weighted: np.ndarray, scale: float) -> np.ndarray:
    """Weighted pair residuals (p, 7) as one vector whose squares sum to their J: each through the soft-L1 loss of
    width ``scale`` (sign kept), over the square root of the pairs, so J is a mean over pairs."""
    if scale > 0:
        weighted = np.sign(weighted) * np.sqrt(_robust(weighted**2, scale))
    return weighted.ravel() / np.sqrt(len(weighted))


def _robust(squares: np.ndarray, scale: float) -> np.ndarray:
    """Squared residuals through the soft-L1 loss of width ``scale`` (0: as they are)."""
    return squares if scale <= 0 else 2 * scale**2 * (np.sqrt(1.0 + squares / scale**2) - 1.0)


def check_weights(**weights: float) -> None:
    """Refuse a JASNOM weight that is not a finite number in [0, :data:`MAX_WEIGHT`] (``alpha`` must be > 0), before
    any arithmetic.

    Parameters
    ----------
    **weights : float
        ``alpha``, ``beta``, ``gamma``, ``along``, ``robust``, ``table`` or ``free_space``, by name.

    Raises
    ------
    StitchError
    """
    for name, value in weights.items():
        low = 0.0 if name == "alpha" else None
        if not (np.isfinite(value) and 0 <= value <= MAX_WEIGHT) or (low is not None and value <= low):
            kind = "positive" if low is not None else "non-negative"
            raise StitchError(f"{name} must be a finite {kind} number of at most {MAX_WEIGHT:g}, got {value}")


def _weights(
    c1: _Curve, alpha: float, beta: float, gamma: float, along: float, robust: float, samples: int
) -> _Weights:
    """The weights of J for ``c1``'s scale and spacing (the callers have checked them: :func:`check_weights`)."""
    x = c1.samples
    scale = float(np.sqrt(np.mean(np.sum((x - x.mean(axis=0)) ** 2, axis=1))))
    spacing = float(np.mean(np.linalg.norm(np.roll(x[:samples], -1, axis=0) - x[:samples], axis=1)))
    if not scale > 0:
        raise StitchError("the first boundary has no extent (all its vertices coincide)")
    root = np.sqrt([1.0, 1.0, 1.0, 1.0, beta, beta, gamma])
    return _Weights(alpha, beta, gamma, along, scale, spacing, root, robust)
