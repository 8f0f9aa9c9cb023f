"""Boundary descriptors of partial views: PVHK, C-PVHK, FT-PVHK and PVST (thesis 2.3-2.4, ch. 5).

The PVHK is the temperature on the outer boundary of a view at the stopping time
``t_s = 1/lambda_2`` after a unit heat pulse at a source vertex (eq. 2.9). C-PVHK does
the same with colour-dependent diffusion rates (eq. 2.10-2.11). For complex objects
(ch. 5) the FT-PVHK takes the temperature at a fixed, per-object time (Alg. 5.1) and
comes with part weights for the weighted distance of eq. 5.14; the PVST records, per
boundary point, the first time its temperature reaches a threshold (Alg. 5.3).

Source rules (2.3.2): ``"closest"`` to the observer (eq. 2.7) or ``"center"`` of the
segmented depth image (eq. 2.8), or any vertex index.

Boundary sampling (2.3.3): ``"arclength"`` takes M samples evenly spaced in 3D length
along the boundary from its origin, interpolating linearly between boundary vertices;
``"polar"`` takes the outermost crossing of the boundary with M rays evenly spaced in
polar angle about the image centre (angle 0 = +x axis, counter-clockwise), falling
back to the nearest-angle boundary vertex for a ray that misses the boundary (a centre
outside the shape). ``samples=None`` returns one value per boundary vertex.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
from matplotlib.colors import rgb_to_hsv
from scipy.optimize import brentq
from scipy.spatial import cKDTree

from .errors import SpectrumError, ViewError
from .spectrum import (HeatOperator, Spectrum, eigen_spectrum, first_crossings, heat_model, krylov_heat, lambda2,
                       laplacian)
from .view import View

log = logging.getLogger(__name__)

SAMPLINGS = ("arclength", "polar")
KINDS = ("pvhk", "c-pvhk", "ft-pvhk", "pvst")
PVST_THRESHOLD = 0.75  # T_a of Alg. 5.3, a fraction of the equilibrium temperature
PVST_WINDOW = 10.0  # t_final = PVST_WINDOW / lambda_2 (Alg. 5.3)
WEIGHT_MODES = 16  # eigenpairs for the global derivative; doubled while the truncation shows
MIN_MAIN_SHARE = 0.25  # below this share of boundary samples on the main part, part weights are unit


def _hue(rgb: np.ndarray) -> np.ndarray:
    return rgb_to_hsv(np.clip(rgb, 0.0, 1.0))[:, 0]


#: Scalar maps of 3.4.2 from RGB to the diffusion rate c(v); h is the hue in [0, 1].
COLOR_MAPS: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "c1": lambda rgb: (_hue(rgb) + 0.5) * 2.0,
    "c2": lambda rgb: (_hue(rgb) + 1e-3) * 2.0,
    "c3": lambda rgb: (_hue(rgb) + 5.0) * 2.0,
    "c4": lambda rgb: (_hue(rgb) + 0.5) * 10.0,
    "hue": lambda rgb: 0.5 + 0.5 * _hue(rgb),  # hue scaled to [0.5, 1], the example of 2.4
}


@dataclass(frozen=True)
class Descriptor:
    """A boundary temperature descriptor.

    Attributes
    ----------
    kind : str
        One of :data:`KINDS`.
    values : (M,) float64
        Normalized temperatures (equilibrium = 1) along the boundary; for ``"pvst"``
        the first times they reach the threshold (NaN where they do not, logged).
    positions : (M,) float64
        Where each value was taken: fraction of the boundary length (arclength, and
        per-vertex descriptors) or polar angle / 2 pi (polar).
    source : int
        Source vertex, indexed in the view passed in.
    time : float
        Stopping time: t_s = 1/lambda_2 (PVHK), the fixed time (FT-PVHK), or the end
        of the search window (PVST).
    lambda2 : float
        First non-zero eigenvalue of the (coloured) view; NaN when it was not needed
        (an FT-PVHK without part weights).
    sampling : str
    color_map : str or None
    repairs : tuple of str
        Repairs made to the view for this descriptor (e.g. a component kept).
    weights : (M,) float64 or None
        Part weights rho of eq. 5.13 at the same samples (FT-PVHK), else None.
    """

    kind: str
    values: np.ndarray
    positions: np.ndarray
    source: int
    time: float
    lambda2: float
    sampling: str
    color_map: str | None = None
    repairs: tuple = field(default_factory=tuple)
    weights: np.ndarray | None = None


def source_vertex(view: View, rule: str | int = "closest") -> int:
    """The heat source of a view: eq. 2.7 (``"closest"``), eq. 2.8 (``"center"``), ``"interior"`` or an index.

    ``"interior"`` (not in the thesis) is the vertex farthest from the outer boundary: never
    on it, as the PVST needs (Lemma 1), and on the view's largest part. On a chair, the
    image centre often falls between the legs or the back's slats, and ``"center"`` then
    picks a vertex of the outline.
    """
    if isinstance(rule, (int, np.integer)):
        if not 0 <= rule < view.n_vertices:
            raise ViewError(f"{view.name}: source vertex {rule} is not in 0..{view.n_vertices - 1}")
        return int(rule)
    x = view.vertices
    if rule == "closest":
        return int(np.argmin(np.einsum("ij,ij->i", x, x)))
    if rule == "center":
        return int(np.argmin(x[:, 0] ** 2 + x[:, 1] ** 2))
    if rule == "interior":
        depth, _ = cKDTree(x[view.boundary]).query(x)
        return int(np.argmax(depth))
    raise ViewError(f"unknown source rule {rule!r} (use 'closest', 'center', 'interior' or a vertex index)")


def color_rates(view: View, color_map: str | Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """Diffusion rates ``c(v)`` of eq. 2.10 from the view's RGB."""
    function = COLOR_MAPS.get(color_map) if isinstance(color_map, str) else color_map
    if function is None:
        raise ViewError(f"unknown colour map {color_map!r} (use one of {', '.join(COLOR_MAPS)} or a function)")
    rates = np.asarray(function(view.colors), dtype=np.float64)
    if rates.shape != (view.n_vertices,) or not np.all(np.isfinite(rates)) or np.any(rates <= 0):
        raise ViewError(f"{view.name}: the colour map must give one positive finite rate per vertex")
    return rates


def heat_operator(view: View, rates: np.ndarray | None = None) -> HeatOperator:
    """The :class:`HeatOperator` of a connected view."""
    if view.n_components > 1:
        raise ViewError(f"{view.name}: {view.n_components} connected components; "
                        "take one with view.component_of(vertex) or view.largest_component()")
    return HeatOperator(laplacian(view.vertices, view.edges, view.name), rates, view.name)


def heat_kernel(view: View, source: int | str = "closest", times=None, *, color_map=None,
                tol: float = 1e-7) -> np.ndarray:
    """Temperatures over the whole view after a unit pulse at ``source`` (eq. 2.5-2.6, 2.11).

    Parameters
    ----------
    view : View
        A connected partial view.
    source : int or str
        Vertex index or source rule.
    times : sequence of float, optional
        Diffusion times; default ``[1 / lambda_2]``.
    color_map : str or callable, optional
        Colour rates for C-PVHK-style diffusion.

    Returns
    -------
    (len(times), n) float64
        Temperatures divided by the equilibrium temperature (equilibrium = 1).
    """
    rates = None if color_map is None else color_rates(view, color_map)
    op = heat_operator(view, rates)
    times = [1.0 / lambda2(op)] if times is None else times
    return krylov_heat(op, source_vertex(view, source), np.asarray(times, float), tol=tol)


def _arclength_positions(view: View, boundary: np.ndarray) -> tuple[np.ndarray, float]:
    points = view.vertices[boundary]
    steps = np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1)
    cumulative = np.concatenate([[0.0], np.cumsum(steps)])
    return cumulative, float(cumulative[-1])


def sample_boundary(view: View, boundary: np.ndarray, temps: np.ndarray, samples: int | None,
                    sampling: str = "arclength") -> tuple[np.ndarray, np.ndarray]:
    """Sample per-boundary-vertex values at M points (2.3.3).

    Parameters
    ----------
    view : View
    boundary : (b,) int
        Ordered boundary loop.
    temps : (b,) or (s, b) float
        Values at the boundary vertices, in loop order (one row per source).
    samples : int or None
        M; None keeps one value per boundary vertex.
    sampling : {"arclength", "polar"}

    Returns
    -------
    values : (M,) or (s, M) float64
    positions : (M,) float64
    """
    temps = np.asarray(temps, float)
    first, frac, positions = _sample_points(view, boundary, samples, sampling)
    second = (first + 1) % len(boundary)
    return (1.0 - frac) * temps[..., first] + frac * temps[..., second], positions


def _sample_points(view: View, boundary: np.ndarray, samples: int | None, sampling: str
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where the M samples fall on the boundary loop: (M,) edge start index and fraction along the edge, and
    the (M,) positions."""
    cumulative, total = _arclength_positions(view, boundary)
    if samples is None:
        return np.arange(len(boundary)), np.zeros(len(boundary)), cumulative[:-1] / total
    if samples < 2:
        raise ViewError(f"samples must be at least 2 or None, got {samples}")
    if sampling == "arclength":
        positions = np.arange(samples) / samples
        first = np.clip(np.searchsorted(cumulative, positions * total, side="right") - 1, 0, len(boundary) - 1)
        step = cumulative[first + 1] - cumulative[first]
        with np.errstate(divide="ignore", invalid="ignore"):
            frac = np.where(step > 0, (positions * total - cumulative[first]) / step, 0.0)
        return first, frac, positions
    if sampling != "polar":
        raise ViewError(f"unknown sampling {sampling!r} (use one of {', '.join(SAMPLINGS)})")
    p = view.planar[boundary]
    q = np.roll(p, -1, axis=0)
    e = q - p
    theta = 2.0 * np.pi * np.arange(samples) / samples
    u = np.column_stack([np.cos(theta), np.sin(theta)])  # (M, 2)
    cross_up = u[:, None, 0] * p[None, :, 1] - u[:, None, 1] * p[None, :, 0]  # (M, b)
    cross_ue = u[:, None, 0] * e[None, :, 1] - u[:, None, 1] * e[None, :, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        f = -cross_up / cross_ue
    radius = (u @ p.T) + f * (u @ e.T)
    hit = (f >= 0) & (f <= 1) & (radius > 0) & np.isfinite(f)
    radius = np.where(hit, radius, -np.inf)
    first = np.argmax(radius, axis=1)
    rows = np.arange(samples)
    frac = np.where(hit[rows, first], f[rows, first], 0.0)
    missed = ~hit.any(axis=1)
    if missed.any():  # a ray that meets no edge takes the boundary vertex nearest in angle
        angles = np.arctan2(p[:, 1], p[:, 0])
        gap = np.abs(np.angle(np.exp(1j * (theta[missed, None] - angles[None, :]))))
        first[missed] = np.argmin(gap, axis=1)
        frac[missed] = 0.0
    return first, frac, theta / (2.0 * np.pi)


@dataclass(frozen=True)
class DescriptorSpec:
    """What to compute for a view: kind, samples, source rule, sampling, colour map, threshold.

    ``threshold`` is the PVST's T_a (default 0.75, Alg. 5.3) and is only taken by a pvst.
    """

    kind: str = "pvhk"
    samples: int | None = 64
    source: str | int = "closest"
    sampling: str = "arclength"
    color_map: str | None = None
    threshold: float | None = None

    @property
    def name(self) -> str:
        """Stable identifier, e.g. ``pvhk/polar/center/64``, ``c-pvhk/arclength/closest/64/c3``,
        ``pvst/polar/center/64/T0.75``."""
        parts = [self.kind, self.sampling, str(self.source), str(self.samples or "all")]
        if self.color_map:
            parts.append(str(self.color_map))
        if self.kind == "pvst":
            parts.append(f"T{self.threshold:g}")
        return "/".join(parts)

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ViewError(f"unknown descriptor kind {self.kind!r} (use one of {', '.join(KINDS)})")
        if (self.kind == "c-pvhk") != (self.color_map is not None):
            raise ViewError(f"a c-pvhk needs a color_map and a {self.kind} takes none")
        if self.sampling not in SAMPLINGS:
            raise ViewError(f"unknown sampling {self.sampling!r} (use one of {', '.join(SAMPLINGS)})")
        if self.kind == "pvst":
            threshold = PVST_THRESHOLD if self.threshold is None else float(self.threshold)
            if not 0.0 < threshold < 1.0:
                raise ViewError(f"the PVST threshold is a fraction of the equilibrium in (0, 1), got {threshold}")
            object.__setattr__(self, "threshold", threshold)
        elif self.threshold is not None:
            raise ViewError(f"a {self.kind} takes no threshold (only a pvst does)")


class _ViewWork:
    """The expensive pieces of one view, each computed once: factorization, lambda_2, spectra, heat."""

    def __init__(self, view: View, method: str, modes: int):
        if method not in ("krylov", "eigen"):
            raise ViewError(f"unknown method {method!r} (use 'krylov' or 'eigen')")
        self.view, self.method, self.modes = view, method, modes
        self.cache: dict = {}

    def _get(self, key, compute):
        if key not in self.cache:
            self.cache[key] = compute()
        return self.cache[key]

    def component(self, source_rule) -> tuple[View, int, int]:
        """(connected component, source index in it, source index in the view)."""
        s = source_vertex(self.view, source_rule)
        label = int(self.view.component_labels[s])
        connected = self._get(("component", label), lambda: self.view.component_of(s)[0])
        s_local = s if connected is self.view else int(np.sum(self.view.component_labels[:s] == label))
        return connected, s_local, s

    def operator(self, connected: View, color_map) -> HeatOperator:
        color = color_map if isinstance(color_map, (str, type(None))) else id(color_map)
        return self._get(("op", id(connected), color), lambda: heat_operator(
            connected, None if color_map is None else color_rates(connected, color_map)))

    def spectrum(self, op: HeatOperator, modes: int) -> Spectrum:
        return self._get(("spectrum", id(op), modes), lambda: eigen_spectrum(op, modes))

    def lambda2(self, op: HeatOperator) -> float:
        def compute():
            for key, value in self.cache.items():  # a spectrum already computed gives it for free
                if key[0] == "spectrum" and key[1] == id(op):
                    return value.lambda2
            return self.spectrum(op, self.modes).lambda2 if self.method == "eigen" else lambda2(op)
        return self._get(("lambda2", id(op)), compute)

    def heat(self, op: HeatOperator, source: int, times: tuple, boundary: np.ndarray) -> np.ndarray:
        """(len(times), b) normalized boundary temperatures."""
        def compute():
            if self.method == "eigen":
                spectrum = self.spectrum(op, self.modes)
                return np.stack([spectrum.heat([source], t, at=boundary)[0] for t in times])
            return krylov_heat(op, source, np.asarray(times), at=boundary)
        return self._get(("heat", id(op), source, times), compute)

    def global_derivative(self, op: HeatOperator, at: np.ndarray, time: float | None = None) -> np.ndarray:
        """Eq. 5.12 at vertices ``at``, at ``time`` (default t_global = 1/lambda_2), with enough modes."""
        def compute():
            modes = WEIGHT_MODES
            while True:
                spectrum = self.spectrum(op, modes)
                try:
                    return spectrum.global_derivative(1.0 / spectrum.lambda2 if time is None else time, at=at)
                except SpectrumError:
                    if modes >= op.n - 2:
                        raise
                    log.info("%s: the global derivative needs more than %d modes; trying %d",
                             op.name, modes, 2 * modes)
                    modes = min(2 * modes, op.n - 2)
        return self._get(("derivative", id(op), id(at), time), compute)


def _part_weights(work: _ViewWork, connected: View, op: HeatOperator, samples, sampling: str
                  ) -> tuple[np.ndarray, tuple]:
    """rho of eq. 5.13 at the descriptor's samples, and the repair made (if any)."""
    boundary = connected.boundary
    delta, _ = sample_boundary(connected, boundary, work.global_derivative(op, boundary), samples, sampling)
    mean_square = float(np.mean(delta ** 2))
    rho = np.exp(-delta ** 2 / mean_square) if mean_square > 0 else np.ones_like(delta)
    share = float(np.mean(rho >= 0.5))
    if share < MIN_MAIN_SHARE:
        note = (f"part weights: only {share:.0%} of the boundary is on the main part (rho >= 0.5); "
                "unit weights used (eq. 3.1)")
        log.warning("%s: %s", connected.name, note)
        return np.ones_like(rho), (note,)
    return rho, ()


# Widest time ratios one heat model covers: the last chunk, on the PVHK's factorization, and
# earlier ones, each on a factorization shifted to its start (both converge in ~30-70 Krylov steps).
PVST_CHUNK = 1024.0
PVST_EARLY_CHUNK = 256.0
# Convergence tolerance of the PVST's heat models on normalized temperatures: the crossing times
# come out within ~1e-6 relative of a dense reference (benchmarks/bench_pvst.py), the target being 1e-3.
PVST_TOL = 1e-4


def _chunk_model(op: HeatOperator, source: int, boundary: np.ndarray, t0: float, t1: float, late: bool):
    """Heat model converged on ``[t0, t1]``: on the PVHK's factorization for the latest chunk,
    else on one shifted to ``1/t0`` (cheap: the shifted matrix is diagonally dominant)."""
    chunk_op = op if late else op.shifted(1.0 / t0)
    return heat_model(chunk_op, source, np.geomspace(t0, t1, 16), at=boundary, tol=PVST_TOL, check_every=4)


def _pvst_start(connected: View, source: int, threshold: float) -> float:
    """Half the time at which the nearest boundary point would reach the threshold on a plane.

    A pulse on a plane of the view's area A gives, at distance r (the gap to the boundary),
    ``T / T_eq = A / (4 pi t) exp(-r^2 / 4t)`` (time in m^2, eq. 2.3's weights); with
    ``x = r^2 / 4t`` the crossing solves ``k x exp(-x) = T_a`` with ``k = A / (pi r^2)``.
    Curved or irregular views differ, so :func:`_pvst_times` checks the start and moves it
    earlier when needed.
    """
    x = connected.vertices
    gap2 = float(np.min(np.sum((x[connected.boundary] - x[source]) ** 2, axis=1)))
    f = connected.faces
    area = 0.5 * float(np.linalg.norm(np.cross(x[f[:, 1]] - x[f[:, 0]], x[f[:, 2]] - x[f[:, 0]]), axis=1).sum())
    target = threshold * np.pi * gap2 / area  # x exp(-x) = target, on the root x > 1
    root = brentq(lambda u: u * np.exp(-u) - target, 1.0, 60.0) if target < np.exp(-1.0) else 1.0
    return gap2 / (4.0 * root) / 2.0


def _pvst_times(work: _ViewWork, connected: View, op: HeatOperator, source: int, threshold: float,
                t_final: float | None) -> tuple[np.ndarray, float, tuple]:
    """First crossing times of the threshold at the boundary vertices (Alg. 5.3, see :func:`pvst`)."""
    boundary = connected.boundary
    if np.any(boundary == source):
        raise ViewError(f"{connected.name}: the source vertex {source} is on the outer boundary; the PVST needs "
                        "an interior source (Lemma 1, 5.4.2) - choose another source rule or vertex")
    t_end = PVST_WINDOW / work.lambda2(op) if t_final is None else float(t_final)
    t_start = _pvst_start(connected, source, threshold)
    if not t_end > t_start:
        raise ViewError(f"{connected.name}: the PVST window ends at t = {t_end:.3g}, before it starts "
                        f"({t_start:.3g})")
    edges = [t_end]  # chunk edges from the end; a leftover of less than 4x joins its neighbour
    while edges[-1] > t_start:
        ratio = PVST_CHUNK if len(edges) == 1 else PVST_EARLY_CHUNK
        edges.append(edges[-1] / ratio if edges[-1] / ratio > 4.0 * t_start else t_start)
    chunks = [(t0, t1, _chunk_model(op, source, boundary, t0, t1, late=t1 == t_end))
              for t1, t0 in zip(edges[:-1], edges[1:], strict=True)][::-1]
    def above_at_start():
        return chunks[0][2](np.array([chunks[0][0]]))[0] >= threshold

    early = above_at_start()
    for _ in range(4):  # start earlier while a boundary point is already above the threshold
        if not early.any():
            break
        t0 = chunks[0][0]
        chunks.insert(0, (t0 / 16.0, t0, _chunk_model(op, source, boundary, t0 / 16.0, t0, late=False)))
        early = above_at_start()
    times = np.full(len(boundary), np.nan)
    for t0, t1, model in chunks:  # the first crossing is in the earliest chunk that has one
        found = first_crossings(model, threshold, t0, t1)
        times = np.where(np.isnan(times), found, times)
    times[early] = np.nan  # no crossing from below in the window
    notes = []
    late = np.isnan(times) & ~early
    if early.any():
        notes.append(f"pvst: {int(early.sum())} boundary vertices are above T = {threshold:g} already at "
                     f"t = {chunks[0][0]:.3g}: NaN")
    if late.any():
        notes.append(f"pvst: {int(late.sum())} boundary vertices do not reach T = {threshold:g} by "
                     f"t = {t_end:.3g}: NaN")
    for note in notes:
        log.warning("%s: %s", connected.name, note)
    return times, t_end, tuple(notes)


def describe(view: View, specs: list[DescriptorSpec], *, method: str = "krylov", modes: int = 30,
             times=None, part_weights: bool = True, t_final: float | None = None) -> list[Descriptor]:
    """Several descriptors of one view, sharing the expensive work.

    Descriptors with the same colour map share one factorization and lambda_2; those
    with the same source share one heat solve; samplings of one solve cost nothing
    more.

    Parameters
    ----------
    view : View
    specs : list of DescriptorSpec
    method, modes
        As in :func:`pvhk`.
    times : sequence of float, or dict from spec name to sequence, optional
        The fixed times of the ``ft-pvhk`` specs (needed if there is one): each such
        spec gives one descriptor per time, all from one Krylov solve. A dict gives
        each ft-pvhk spec its own times (e.g. time scales found with its source rule).
    part_weights : bool
        Give ``ft-pvhk`` descriptors their part weights (eq. 5.13), at the cost of a few
        eigenpairs per view.
    t_final : float, optional
        End of the PVST search window (default ``10 / lambda_2``, Alg. 5.3).

    Returns
    -------
    list of Descriptor
        In spec order; an ``ft-pvhk`` spec contributes ``len(times)`` descriptors.
    """
    work = _ViewWork(view, method, modes)
    results = []
    for spec in specs:
        connected, s_local, s = work.component(spec.source)
        op = work.operator(connected, spec.color_map)
        boundary = connected.boundary
        repairs = tuple(connected.repairs[len(view.repairs):])
        color = spec.color_map if isinstance(spec.color_map, (str, type(None))) else \
            getattr(spec.color_map, "__name__", "custom")
        common = dict(kind=spec.kind, source=s, sampling=spec.sampling, color_map=color)
        if spec.kind == "pvst":
            crossing, t_end, notes = _pvst_times(work, connected, op, s_local, spec.threshold, t_final)
            values, positions = sample_boundary(connected, boundary, crossing, spec.samples, spec.sampling)
            results.append(Descriptor(values=values, positions=positions, time=t_end, lambda2=work.lambda2(op),
                                      repairs=repairs + notes, **common))
            continue
        if spec.kind == "ft-pvhk":
            chosen = times.get(spec.name) if isinstance(times, Mapping) else times
            if chosen is None:
                raise ViewError(f"{view.name}: the ft-pvhk {spec.name} needs times= (the object's time scale, "
                                "Alg. 5.1)")
            spec_times = tuple(float(t) for t in np.atleast_1d(chosen))
            weights, notes = _part_weights(work, connected, op, spec.samples, spec.sampling) if part_weights \
                else (None, ())
            lam2 = work.lambda2(op) if part_weights else float("nan")
        else:
            lam2 = work.lambda2(op)
            spec_times, weights, notes = (1.0 / lam2,), None, ()
        temps = work.heat(op, s_local, spec_times, boundary)
        for t, row in zip(spec_times, temps, strict=True):
            values, positions = sample_boundary(connected, boundary, row, spec.samples, spec.sampling)
            results.append(Descriptor(values=values, positions=positions, time=t, lambda2=lam2,
                                      repairs=repairs + notes, weights=weights, **common))
    return results


def pvhk(view: View, samples: int | None = 64, source: str | int = "closest", *, sampling: str = "arclength",
         method: str = "krylov", modes: int = 30) -> Descriptor:
    """Partial View Heat Kernel (Alg. 2.1, eq. 2.9).

    Parameters
    ----------
    view : View
        If the view has several connected components, the component holding the
        source is used (logged, and recorded in ``Descriptor.repairs``).
    samples : int or None
        Number of boundary samples M; None: one value per vertex of ``view.boundary``.
    source : {"closest", "center", "interior"} or int
        Source rule (eq. 2.7, 2.8) or vertex index.
    sampling : {"arclength", "polar"}
    method : {"krylov", "eigen"}
        ``"krylov"``: exact heat by shift-invert Krylov projection (default, fastest);
        ``"eigen"``: the truncated eigen-expansion of eq. 2.9 with ``modes`` modes.

    Returns
    -------
    Descriptor
    """
    spec = DescriptorSpec("pvhk", samples, source, sampling)
    return describe(view, [spec], method=method, modes=modes)[0]


def c_pvhk(view: View, samples: int | None = 64, color_map: str | Callable = "c3", source: str | int = "closest",
           *, sampling: str = "arclength", method: str = "krylov", modes: int = 30) -> Descriptor:
    """Colour PVHK (eq. 2.10-2.11): diffusion rates ``c(v)`` from the view's RGB.

    ``color_map`` is one of :data:`COLOR_MAPS` (``c1``..``c4`` of 3.4.2, ``hue``) or a
    function from (n, 3) RGB in [0, 1] to (n,) positive rates. Other parameters as
    :func:`pvhk`.
    """
    spec = DescriptorSpec("c-pvhk", samples, source, sampling, color_map)
    return describe(view, [spec], method=method, modes=modes)[0]


def ft_pvhk(view: View, time: float, samples: int | None = 64, source: str | int = "closest", *,
            sampling: str = "arclength", method: str = "krylov", modes: int = 30) -> Descriptor:
    """Fixed-time PVHK (5.4.1): the PVHK at a given time, e.g. :func:`object_time_scale`.

    Costs one heat solve and no lambda_2 (``Descriptor.lambda2`` is NaN); its part weights
    come from :func:`part_weights`. Other parameters as :func:`pvhk`.
    """
    spec = DescriptorSpec("ft-pvhk", samples, source, sampling)
    return describe(view, [spec], method=method, modes=modes, times=[time], part_weights=False)[0]


def pvst(view: View, samples: int | None = 64, threshold: float = PVST_THRESHOLD, source: str | int = "closest",
         *, sampling: str = "arclength", t_final: float | None = None) -> Descriptor:
    """Partial View Stochastic Time (Alg. 5.3, 5.4.2): when each boundary point reaches ``threshold``.

    ``values`` are the first times the normalized temperature (equilibrium = 1) reaches
    ``threshold`` after a unit pulse at the source, in the view's time units
    (metres^2 with the 1/d^2 weights of eq. 2.3). Instead of ~1200 eigenpairs, the heat
    over the window is a shift-invert Krylov projection, an explicit sum of exponentials
    in t, converged to 1e-4 at 16 times of the window; it is bracketed on 256
    log-spaced times (the thesis's log search) and bisected to 1e-9 relative.
    Non-monotone temperatures give their first crossing.

    The window runs from half the time the nearest boundary point would need on a
    plane (moved earlier, by 16x up to 4 times, while a boundary point is already above
    the threshold) to ``t_final``. One model on the PVHK's factorization covers its last
    1024x; earlier times, which such a model resolves slowly (a source near the outline),
    get models of 256x each on factorizations shifted to their start. Against a dense
    reference the crossing times agree to ~1e-6 relative (``benchmarks/bench_pvst.py``).

    Parameters
    ----------
    view : View
    samples : int or None
        M; None: one value per boundary vertex.
    threshold : float
        T_a in (0, 1).
    source : {"closest", "center", "interior"} or int
        Must not be on the outer boundary (Lemma 1): a :class:`ViewError` otherwise.
    sampling : {"arclength", "polar"}
    t_final : float, optional
        End of the search window, default ``10 / lambda_2``. Boundary points that do not
        reach the threshold by then are NaN, logged and listed in ``repairs``.

    Returns
    -------
    Descriptor
        ``time`` is the end of the window.
    """
    spec = DescriptorSpec("pvst", samples, source, sampling, threshold=threshold)
    return describe(view, [spec], t_final=t_final)[0]


def part_weights(view: View, samples: int | None = 64, *, sampling: str = "arclength",
                 source: str | int = "closest") -> np.ndarray:
    """Part weights rho of eq. 5.13, at the samples of a descriptor with the same arguments.

    ``rho_i = exp(-Delta_i^2 / mean(Delta^2))`` with ``Delta`` the source-position global
    derivative (eq. 5.12) at t_global = 1/lambda_2, sampled along the boundary like the
    descriptor: close to 1 on the main part, small on loosely connected parts. The
    source only chooses the connected component. If fewer than 25% of the samples
    have rho >= 0.5 - the boundary runs mostly along small parts, and the weights
    would rest the distance on a few points - unit weights are returned instead,
    with a logged warning.

    Returns
    -------
    (M,) float64
    """
    work = _ViewWork(view, "krylov", 30)
    connected, _, _ = work.component(source)
    weights, _ = _part_weights(work, connected, work.operator(connected, None), samples, sampling)
    return weights


def global_derivative(view: View, source: str | int = "closest", time: float | None = None) -> np.ndarray:
    """Source-position global derivative (eq. 5.12) at every vertex of the source's component (Fig. 5.7).

    ``time`` defaults to t_global = 1/lambda_2. Returns (n_component,) float64.
    """
    work = _ViewWork(view, "eigen", WEIGHT_MODES)
    connected, _, _ = work.component(source)
    return work.global_derivative(work.operator(connected, None), np.arange(connected.n_vertices),
                                  None if time is None else float(time))


def view_time_scale(view: View, source: str | int = "closest") -> float:
    """t_global = 1/lambda_2 of the component holding the source (2.3.1)."""
    work = _ViewWork(view, "krylov", 30)
    connected, _, _ = work.component(source)
    return 1.0 / work.lambda2(work.operator(connected, None))


def object_time_scale(views, source: str | int = "closest") -> float:
    """Main-part time scale of an object (Alg. 5.1): the smallest 1/lambda_2 over its views.

    Parameters
    ----------
    views : iterable of View
        Partial views of one object from several view angles.
    """
    scales = {view.name: view_time_scale(view, source) for view in views}
    if not scales:
        raise ViewError("object_time_scale needs at least one view")
    name = min(scales, key=scales.get)
    log.info("time scale %.4g from %s (min of %d views; max %.4g)", scales[name], name, len(scales),
             max(scales.values()))
    return scales[name]
