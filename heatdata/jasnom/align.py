"""The JASNOM search (thesis 7.3): Kabsch candidates at every shift, refined, with a runner-up."""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from heatdata.errors import StitchError
from heatdata.jasnom.boundary import MIN_BOUNDARY, Boundary, _as_loops
from heatdata.jasnom.cost import (
    ScanSurface,
    _Curve,
    _flat_residuals,
    _residuals,
    _terms,
    _Weights,
    _weights,
    check_weights,
)
from heatdata.jasnom.defaults import ALONG, ALPHA, BETA, FREE_SPACE, GAMMA, MAX_SAMPLES, MIN_SAMPLES, TABLE
from heatdata.jasnom.table import TableContact

log = logging.getLogger(__name__)


#: distinct coarse candidates refined over six degrees of freedom
REFINE = 4
#: evaluations of J a refinement may make; with tables fewer, as their quantile and free-space residuals are
#: piecewise linear, where the least squares creeps (the closest-point polish follows either way)
REFINE_STEPS, TABLE_STEPS = 300, 60
#: a runner-up whose J is below this many times the best's makes the answer ambiguous
AMBIGUOUS = 1.25
#: a seam whose mean gap exceeds this fraction of the object's size is a poor stitch
POOR_GAP = 0.02
#: poses closer than this (degrees of rotation, translation over the size) are the same answer
DISTINCT_DEGREES, DISTINCT_SIZE = 2.0, 0.01


@dataclass(frozen=True)
class Alignment:
    """The best rigid motion of the second mesh onto the first, what it costs and how it was found.

    Attributes
    ----------
    rotation : (3, 3) float64
    translation : (3,) float64
        ``x = rotation @ y + translation`` maps the second mesh into the first's frame.
    cost, edge_cost, crossing_cost, crease_cost : float
        J, J1, J2 and J3 at the motion (module docstring); ``J = J1 + beta J2 + gamma J3 + T + F``.
    table_cost : float
        T, the support-plane term (:mod:`heatdata.jasnom.table`), weight included; 0 without tables.
    free_space_cost : float
        F, the free-space term of two depth scans (:class:`Witnesses`), weight included; 0 for meshes.
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
    table_cost: float
    free_space_cost: float
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
class Witnesses:
    """What two scans know beyond their boundaries, as terms of J: their tables (T) and the space their cameras saw
    empty (F).

    ``F = free_space * (r_1^2 + r_2^2) / s^2``, where ``r_1`` is the RMS of how far scan 2's surface samples stand in
    front of what camera 1 measured along its rays, beyond the samples' spacing, and ``r_2`` the same for scan 1 in
    camera 2 (:meth:`ScanSurface.free_space`); ``s`` is J's scale. At the true motion F is 0 up to the sensor's
    noise: each scan lies behind the other's surface, or off its rays. A pose that pushes part of one scan through
    the surface the other measured pays for it (measured: the back bunny scan slid into the front one's seen space,
    a speaker's half turned over), where the boundary terms, on a seam that grazing surface left unscanned, do not
    see it. It does not see two scans drawn apart along the viewing ray: each then lies behind the other.

    Attributes
    ----------
    scans : (ScanSurface, ScanSurface), optional
        The two meshes as depth scans, each in its camera's frame.
    contact : TableContact, optional
        Their table planes (:mod:`heatdata.jasnom.table`).
    table, free_space : float
        T's and F's weights.
    """

    scans: tuple[ScanSurface, ScanSurface] | None = None
    contact: TableContact | None = None
    table: float = TABLE
    free_space: float = FREE_SPACE

    def parts(self, rotation: np.ndarray, translation: np.ndarray, scale: float) -> tuple[np.ndarray, np.ndarray]:
        """T's and F's residuals at a motion, weights included: the squares of each sum to the term."""
        table, free = np.zeros(0), np.zeros(0)
        if self.contact is not None:
            table = np.sqrt(self.table) * self.contact.residuals(rotation, translation, scale)
        if self.scans is not None and self.free_space > 0:
            free = np.sqrt(self.free_space) * self.scans[0].free_space(self.scans[1], rotation, translation) / scale
        return table, free


def free_space_weight(
    free_space: float | None, scans: tuple[ScanSurface, ScanSurface] | None, contact: TableContact | None
) -> float:
    """F's weight: ``free_space`` if given; else :data:`heatdata.jasnom.defaults.FREE_SPACE` for scans without
    tables, and 0 for meshes (no cameras) and for scans on tables, whose term already holds each scan out of the
    space the other's whole depth frame saw empty."""
    if free_space is not None:
        return float(free_space)
    return FREE_SPACE if scans is not None and contact is None else 0.0


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


def _differs(
    a: tuple[np.ndarray, np.ndarray],
    b: tuple[np.ndarray, np.ndarray],
    centre: np.ndarray,
    size: float,
    degrees: float,
    fraction: float,
) -> bool:
    """Whether two motions differ by more than ``degrees`` of rotation, or move ``centre`` (B2's centroid) to points
    more than ``fraction`` of ``size`` apart."""
    angle = float(np.degrees(Rotation.from_matrix(a[0] @ b[0].T).magnitude()))
    return angle > degrees or float(np.linalg.norm(a[0] @ centre + a[1] - b[0] @ centre - b[1])) > fraction * size


def checked_samples(samples: int) -> int:
    """``samples`` if it is a whole number in [:data:`MIN_SAMPLES`, :data:`MAX_SAMPLES`], else a StitchError."""
    if not (MIN_SAMPLES <= samples <= MAX_SAMPLES and int(samples) == samples):
        raise StitchError(f"samples must be a whole number in [{MIN_SAMPLES}, {MAX_SAMPLES}], got {samples}")
    return int(samples)


def align(
    first: Boundary | list[Boundary],
    second: Boundary | list[Boundary],
    *,
    alpha: float = ALPHA,
    beta: float = BETA,
    gamma: float = GAMMA,
    along: float = ALONG,
    samples: int = 128,
    refine: int = REFINE,
    robust: float = 0.0,
    scans: tuple[ScanSurface, ScanSurface] | None = None,
    contact: TableContact | None = None,
    table: float = TABLE,
    free_space: float | None = None,
    constrained: bool = True,
    trace: list | None = None,
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
    contact : TableContact, optional
        The scans' table planes (an object scanned standing, then flipped, on a table): J
        gains the support-plane term T, and the coarse search the flip candidates
        (:mod:`heatdata.jasnom.table`).
    table : float
        T's weight (default :data:`heatdata.jasnom.defaults.TABLE`).
    free_space : float, optional
        F's weight, for scans (:class:`Witnesses`; default :func:`free_space_weight`'s; 0
        leaves it out).
    constrained : bool
        False allows every pose (no orientation constraint; for ablations).
    trace : list, optional
        Receives ``(rotation, translation, J)`` at every pose evaluated (for tests that the
        cost prefers the truth).

    Returns
    -------
    Alignment
        The best pose (``rotation``, ``translation`` moving ``second`` onto ``first``), its cost
        and terms, the runner-up's cost, the seam's mean gap and the candidates tried.

    Raises
    ------
    StitchError
        A boundary of fewer than :data:`MIN_BOUNDARY` vertices, a weight that is not a
        finite number in range, or ``samples`` outside [MIN_SAMPLES, MAX_SAMPLES].
    """
    checked_samples(samples)
    free_space = free_space_weight(free_space, scans, contact)
    check_weights(alpha=alpha, beta=beta, gamma=gamma, along=along, robust=robust, table=table, free_space=free_space)
    first, second = _as_loops(first), _as_loops(second)
    for b in (first[0], second[0]):
        if len(b.loop) < MIN_BOUNDARY:
            raise StitchError(
                f"a boundary of {len(b.loop)} vertices cannot fix a motion: at least {MIN_BOUNDARY} are "
                "needed (give --motion if it is known)"
            )
    ratio = max(first[0].length, second[0].length) / min(first[0].length, second[0].length)
    if ratio > 1.5:
        log.warning("the boundaries' lengths differ by a factor %.2f: JASNOM assumes they trace one curve", ratio)
    begin = time.perf_counter()
    c1, c2 = _Curve.of(first, samples), _Curve.of(second, samples)
    w = _weights(c1, alpha, beta, gamma, along, robust, samples)
    witnesses = Witnesses(scans, contact, float(table), float(free_space))
    size = float(
        np.linalg.norm(
            np.ptp(np.vstack([c1.samples, c2.samples - c2.samples.mean(axis=0) + c1.samples.mean(axis=0)]), axis=0)
        )
    )
    centre = c2.samples.mean(axis=0)
    visited: list = []

    def evaluator(terms: Witnesses):
        def evaluate(rotation, translation) -> tuple[np.ndarray, float]:
            """The residual vector whose squares sum to J (with ``terms``), and J: +inf where the meshes would lie
            on one side of the seam (7.3)."""
            residuals, _, cosines = _residuals(rotation, translation, c1, c2, w)
            vector = np.concatenate(
                [_flat_residuals(residuals * w.root, w.robust), *terms.parts(rotation, translation, w.scale)]
            )
            if not constrained:
                allowed = True
            elif scans is None:
                allowed = np.mean(cosines) <= 0.0  # the meshes lie on the two sides of the seam (7.3)
            else:  # each scan is the far side of the object from the other's camera
                allowed = (
                    max(
                        scans[1].faces_camera(rotation, translation, np.zeros(3)),
                        scans[0].faces_camera(rotation.T, -rotation.T @ translation, np.zeros(3)),
                    )
                    < 0.5
                )
            value = float(vector @ vector) if allowed else np.inf
            visited.append((rotation, translation, value))
            return vector, value

        return evaluate

    # F is left out of the coarse search and the first refinement: measured on two opposite bunny scans, it steers
    # the coarse ranking to a flipped pose (160-170 deg off), while from J's optimum it moves the answer towards the
    # truth
    free = witnesses.free_space > 0 and scans is not None
    evaluate = evaluator(replace(witnesses, free_space=0.0) if free else witnesses)
    shifts = np.arange(samples)
    order = np.concatenate(
        [
            (shifts[:, None] - shifts) % samples,  # eq. 7.8 on equal samples: reversed (7.3)
            (shifts[:, None] + shifts) % samples,
        ]
    )  # and the mirrored order
    rotations, translations = _kabsch(c1.samples[:samples][order], c2.samples[:samples])
    if contact is not None:  # each set on the table; and the half-turns that put the flipped scan on it, slid along it
        translations = np.array([contact.on_table(r, t) for r, t in zip(rotations, translations, strict=True)])
        turns, placed = contact.flip_candidates()
        placed = np.array([_slid(r, t, c1, c2, contact.planes[0, :3]) for r, t in zip(turns, placed, strict=True)])
        rotations, translations = np.concatenate([rotations, turns]), np.concatenate([translations, placed])
    coarse = np.array([evaluate(r, t)[1] for r, t in zip(rotations, translations, strict=True)])
    if not np.isfinite(coarse).any():
        raise StitchError(
            "no alignment puts each scan on the far side of the object from the other's camera: are both in their "
            "cameras' frames (camera at the origin), taken from opposite sides?"
            if scans is not None
            else "the two meshes do not face each other across their boundaries at any alignment (the boundary normals "
            "agree): either both are wound the same way round the cut (reverse one's faces), the second lies on the "
            "first (the same surface twice), or their longest boundaries are not one curve"
        )
    starts: list[tuple[np.ndarray, np.ndarray, float]] = []
    # the cheapest of each family (boundary correspondences; flips), 10 deg or 5% apart
    for family in (slice(0, 2 * samples), slice(2 * samples, len(coarse))):
        chosen = 0
        for k in family.start + np.argsort(coarse[family], kind="stable"):
            if not np.isfinite(coarse[k]) or chosen == refine:
                break
            if all(_differs((rotations[k], translations[k]), start[:2], centre, size, 10.0, 0.05) for start in starts):
                starts.append((rotations[k], translations[k], float(coarse[k])))
                chosen += 1
    # a refinement that ends where the constraint forbids (J = inf) leaves its start as the candidate
    found = sorted(
        (
            min(
                (
                    _refine(r, t, r @ centre + t, w, c1, c2, evaluate, TABLE_STEPS if contact else REFINE_STEPS),
                    (r, t, j),
                ),
                key=lambda pose: pose[2],
            )
            for r, t, j in starts
        ),
        key=lambda pose: pose[2],
    )
    if free:
        evaluate = evaluator(witnesses)
        found = sorted(
            (_refine(r, t, r @ centre + t, w, c1, c2, evaluate, REFINE_STEPS) for r, t, _ in found),
            key=lambda pose: pose[2],
        )
    rotation, translation, _best = found[0]
    others = [
        j
        for r, t, j in found[1:]
        if _differs((r, t), (rotation, translation), centre, size, DISTINCT_DEGREES, DISTINCT_SIZE)
    ]
    if trace is not None:
        trace.extend(visited)
    return _alignment(rotation, translation, c1, c2, w, min(others, default=np.nan), len(visited), begin, witnesses)


def _slid(rotation: np.ndarray, translation: np.ndarray, c1: _Curve, c2: _Curve, normal: np.ndarray, steps: int = 10):
    """A translation moved along the plane of unit ``normal`` (the table) by closest-point steps that bring B2's samples
    onto B1 on average, both ways: the flip candidates' placement, which their footprints' centroids only guess."""
    for _ in range(steps):
        moved = c2.samples @ rotation.T + translation
        back = c2.closest((c1.samples - translation) @ rotation)[0] @ rotation.T + translation
        step = 0.5 * (np.mean(c1.closest(moved)[0] - moved, axis=0) + np.mean(c1.samples - back, axis=0))
        translation = translation + step - (step @ normal) * normal
    return translation


def _refine(
    rotation0: np.ndarray,
    translation0: np.ndarray,
    centre: np.ndarray,
    w: _Weights,
    c1: _Curve,
    c2: _Curve,
    evaluate,
    steps: int,
) -> tuple[np.ndarray, np.ndarray, float]:
    """Trust-region least squares from a pose, over a rotation vector about ``centre`` (B2's moved centroid) and a
    translation in units of s, then :func:`_polished`."""

    def motion(p):
        turn = Rotation.from_rotvec(p[:3]).as_matrix()
        return turn @ rotation0, turn @ (translation0 - centre) + centre + w.scale * p[3:]

    def residuals(p):
        return evaluate(*motion(p))[0]

    result = least_squares(
        residuals, np.zeros(6), method="trf", x_scale=1.0, ftol=1e-12, xtol=1e-12, gtol=1e-12, max_nfev=steps
    )
    rotation, translation = motion(result.x)
    return _polished(rotation, translation, c1, c2, evaluate)


def _polished(
    rotation: np.ndarray, translation: np.ndarray, c1: _Curve, c2: _Curve, evaluate, steps: int = 30
) -> tuple[np.ndarray, np.ndarray, float]:
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


def alignment_at(
    first: Boundary | list[Boundary],
    second: Boundary | list[Boundary],
    rotation: np.ndarray,
    translation: np.ndarray,
    *,
    alpha: float = ALPHA,
    beta: float = BETA,
    gamma: float = GAMMA,
    along: float = ALONG,
    robust: float = 0.0,
    samples: int = 128,
    scans: tuple[ScanSurface, ScanSurface] | None = None,
    contact: TableContact | None = None,
    table: float = TABLE,
    free_space: float | None = None,
) -> Alignment:
    """J at a known rigid motion of ``second`` onto ``first`` (registered cameras, a turntable, the truth).

    Nothing is searched, so :func:`stitch` can join scans whose motion is known and an
    experiment can compare J at the true motion with J at :func:`align`'s optimum.
    """
    free_space = free_space_weight(free_space, scans, contact)
    check_weights(alpha=alpha, beta=beta, gamma=gamma, along=along, robust=robust, table=table, free_space=free_space)
    begin = time.perf_counter()
    c1, c2 = _Curve.of(_as_loops(first), samples), _Curve.of(_as_loops(second), samples)
    w = _weights(c1, alpha, beta, gamma, along, robust, samples)
    return _alignment(
        np.asarray(rotation, np.float64),
        np.asarray(translation, np.float64),
        c1,
        c2,
        w,
        np.nan,
        1,
        begin,
        Witnesses(scans, contact, float(table), float(free_space)),
    )


def _alignment(
    rotation,
    translation,
    c1: _Curve,
    c2: _Curve,
    w: _Weights,
    runner_up: float,
    candidates: int,
    begin: float,
    witnesses: Witnesses,
) -> Alignment:
    residuals, xi, cosines = _residuals(rotation, translation, c1, c2, w)
    cost, edge, crossing, crease = _terms(residuals, w)
    plane, free = (float(part @ part) for part in witnesses.parts(rotation, translation, w.scale))
    moved = c2.samples @ rotation.T + translation
    size = float(np.linalg.norm(np.ptp(np.vstack([c1.samples, moved]), axis=0)))
    return Alignment(
        rotation=rotation,
        translation=translation,
        cost=cost + plane + free,
        edge_cost=edge,
        crossing_cost=crossing,
        crease_cost=crease,
        table_cost=plane,
        free_space_cost=free,
        runner_up=float(runner_up),
        gap=float(np.mean(np.linalg.norm(xi, axis=1))),
        size=size,
        facing=float(np.mean(cosines)),
        candidates=candidates,
        seconds=time.perf_counter() - begin,
    )
