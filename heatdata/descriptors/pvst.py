"""The Partial View Stochastic Time (thesis 5.4.2, Alg. 5.3): when each boundary point warms up.

For each boundary point, the first time its normalized temperature (equilibrium = 1)
reaches a threshold T_a after a unit pulse at an interior source. Instead of ~1200
eigenpairs, the heat over the window is a shift-invert Krylov projection, an explicit
sum of exponentials in t, bracketed on a log grid and bisected.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping

import numpy as np
from scipy.optimize import brentq

from ..errors import ViewError
from ..spectrum import HeatOperator, first_crossings, heat_models
from ..view import View
from .base import Descriptor, DescriptorSpec, Option, number, register
from .boundary import sample_boundary
from .compute import describe
from .heat import BOUNDARY_OPTIONS, BoundaryKind
from .work import ViewWork

log = logging.getLogger(__name__)

PVST_THRESHOLD = 0.75  # T_a of Alg. 5.3, a fraction of the equilibrium temperature
PVST_WINDOW = 10.0  # t_final = PVST_WINDOW / lambda_2 (Alg. 5.3)


# Widest time ratios one heat model covers: the last chunk, on the PVHK's factorization, and
# earlier ones, each on a factorization shifted to its start (both converge in ~30-70 Krylov steps).
PVST_CHUNK = 1024.0
PVST_EARLY_CHUNK = 256.0
# Convergence tolerance of the PVST's heat models on normalized temperatures: the crossing times
# come out within ~1e-6 relative of a dense reference (benchmarks/bench_pvst.py), the target being 1e-3.
PVST_TOL = 1e-4
MIN_THRESHOLD = 100 * PVST_TOL  # thresholds closer to the model's error give crossings of noise


def _shift(t0: float) -> float:
    """The shift of a heat model whose window starts at ``t0``: ``1/t0`` rounded to a power of 2, so that the
    candidate sources of a view share a few factorizations (the models converge alike within a factor of 2)."""
    return 2.0 ** round(np.log2(1.0 / t0))


def _chunk_models(op: HeatOperator, sources: np.ndarray, boundary: np.ndarray, chunks: list[tuple],
                  shifted: dict) -> list:
    """Heat models converged on each chunk ``(source index, t0, t1, late)``: on the PVHK's factorization for
    the latest chunks, else on one shifted to about ``1/t0`` (cheap: the shifted matrix is diagonally
    dominant; ``shifted`` keeps them by shift). The chunks of one factorization are solved together
    (:func:`heatdata.spectrum.heat_models`)."""
    groups: dict = {}
    for i, (_, t0, _, late) in enumerate(chunks):
        groups.setdefault(None if late else _shift(t0), []).append(i)
    models: list = [None] * len(chunks)
    for sigma, members in groups.items():
        if sigma is not None and sigma not in shifted:
            shifted[sigma] = op.shifted(sigma)
        chunk_op = op if sigma is None else shifted[sigma]
        times = np.stack([np.geomspace(chunks[i][1], chunks[i][2], 16) for i in members])
        found = heat_models(chunk_op, sources[[chunks[i][0] for i in members]], times, at=boundary, tol=PVST_TOL,
                            check_every=4)
        for i, model in zip(members, found, strict=True):
            models[i] = model
    return models


def _pvst_starts(connected: View, sources: np.ndarray, threshold: float) -> np.ndarray:
    """Half the time at which the nearest boundary point would reach the threshold on a plane, per source.

    A pulse on a plane of the view's area A gives, at distance r (the gap to the boundary),
    ``T / T_eq = A / (4 pi t) exp(-r^2 / 4t)`` (time in m^2, eq. 2.3's weights); with
    ``x = r^2 / 4t`` the crossing solves ``k x exp(-x) = T_a`` with ``k = A / (pi r^2)``.
    Curved or irregular views differ, so :func:`_pvst_times` checks the start and moves it
    earlier when needed.
    """
    x = connected.vertices
    gap2 = np.min(((x[sources][:, None, :] - x[connected.boundary][None, :, :]) ** 2).sum(axis=2), axis=1)
    f = connected.faces
    area = 0.5 * float(np.linalg.norm(np.cross(x[f[:, 1]] - x[f[:, 0]], x[f[:, 2]] - x[f[:, 0]]), axis=1).sum())
    targets = threshold * np.pi * gap2 / area  # x exp(-x) = target, on the root x > 1
    roots = [brentq(lambda u: u * np.exp(-u) - target, 1.0, 60.0) if target < np.exp(-1.0) else 1.0
             for target in targets]
    return gap2 / (4.0 * np.array(roots)) / 2.0


def _pvst_times(work: ViewWork, connected: View, op: HeatOperator, sources: np.ndarray, threshold: float,
                t_final: float | None) -> tuple[list[np.ndarray], float, list[tuple]]:
    """First crossing times of the threshold at the boundary vertices, per source (Alg. 5.3, see :func:`pvst`).

    Returns the crossing times (one (b,) array per source), the end of the window, and
    each source's notes on boundary vertices left NaN.
    """
    boundary = connected.boundary
    on_boundary = np.isin(sources, boundary)
    if on_boundary.any():
        raise ViewError(f"{connected.name}: the source vertex {int(sources[on_boundary][0])} is on the outer "
                        "boundary; the PVST needs an interior source (Lemma 1, 5.4.2) - choose another source "
                        "rule or vertex")
    t_end = PVST_WINDOW / work.lambda2(op) if t_final is None else float(t_final)
    starts = _pvst_starts(connected, sources, threshold)
    if not np.all(t_end > starts):
        raise ViewError(f"{connected.name}: the PVST window ends at t = {t_end:.3g}, before it starts "
                        f"({starts.max():.3g})")
    chunks = []  # (source index, t0, t1, late) from the end; a leftover of less than 4x joins its neighbour
    for i, t_start in enumerate(starts):
        edges = [t_end]
        while edges[-1] > t_start:
            ratio = PVST_CHUNK if len(edges) == 1 else PVST_EARLY_CHUNK
            edges.append(edges[-1] / ratio if edges[-1] / ratio > 4.0 * t_start else t_start)
        chunks += [(i, t0, t1, t1 == t_end) for t1, t0 in zip(edges[:-1], edges[1:], strict=True)]
    shifted: dict = {}
    models = _chunk_models(op, sources, boundary, chunks, shifted)
    per_source: list[list] = [[] for _ in sources]  # each source's (t0, t1, model), earliest first
    for chunk, model in zip(chunks, models, strict=True):
        per_source[chunk[0]].insert(0, (chunk[1], chunk[2], model))

    def above_at_start(i: int) -> np.ndarray:
        t0, _, model = per_source[i][0]
        return model(np.array([t0]))[0] >= threshold

    early = [above_at_start(i) for i in range(len(sources))]
    for _ in range(4):  # start earlier while a boundary point is already above the threshold
        again = [(i, per_source[i][0][0] / 16.0, per_source[i][0][0], False)
                 for i in range(len(sources)) if early[i].any()]
        if not again:
            break
        for chunk, model in zip(again, _chunk_models(op, sources, boundary, again, shifted), strict=True):
            per_source[chunk[0]].insert(0, (chunk[1], chunk[2], model))
            early[chunk[0]] = above_at_start(chunk[0])
    crossings, notes = [], []
    for i, chunk_models in enumerate(per_source):
        times = np.full(len(boundary), np.nan)
        for t0, t1, model in chunk_models:  # the first crossing is in the earliest chunk that has one
            found = first_crossings(model, threshold, t0, t1)
            times = np.where(np.isnan(times), found, times)
        times[early[i]] = np.nan  # no crossing from below in the window
        late = np.isnan(times) & ~early[i]
        source_notes = []
        if early[i].any():
            source_notes.append(f"pvst: {int(early[i].sum())} boundary vertices are above T = {threshold:g} "
                                f"already at t = {chunk_models[0][0]:.3g}: NaN")
        if late.any():
            source_notes.append(f"pvst: {int(late.sum())} boundary vertices do not reach T = {threshold:g} by "
                                f"t = {t_end:.3g}: NaN")
        for note in source_notes:
            log.warning("%s: source %d: %s", connected.name, int(sources[i]), note)
        crossings.append(times)
        notes.append(tuple(source_notes))
    return crossings, t_end, notes


class PVST(BoundaryKind):
    name = "pvst"
    summary = "Partial View Stochastic Time: first time each boundary point reaches T_a (Alg. 5.3)"
    options = BOUNDARY_OPTIONS + (Option("threshold", PVST_THRESHOLD, "threshold T_a, a fraction of the "
                                         "equilibrium temperature in (0, 1)", number(0.0, 1.0)),)
    multi_source = True
    value_label = "time to reach T_a (m^2, the unit of t_s = 1/lambda_2)"

    def validate(self, options: dict) -> dict:
        threshold = options["threshold"]
        if threshold >= 1.0:
            raise ViewError(f"pvst: option threshold is a fraction of the equilibrium in (0, 1), got {threshold}")
        if threshold < MIN_THRESHOLD:
            raise ViewError(f"pvst: option threshold must be at least {MIN_THRESHOLD:g}: the heat models are "
                            f"converged to {PVST_TOL:g} of the equilibrium, too coarse to place a crossing of "
                            f"{threshold:g}")
        return options

    def label(self, options: Mapping) -> str:
        return f"{super().label(options)}/T{options['threshold']:g}"

    def compute(self, work: ViewWork, spec: DescriptorSpec, **context) -> list[Descriptor]:
        connected, s_local, s = work.component(spec.source)
        return self._describe(work, connected, np.array([s_local]), np.array([s]), spec, context.get("t_final"))

    def candidates(self, view: View, sources: np.ndarray, spec: DescriptorSpec, *, times=None, modes: int = 32
                   ) -> list[Descriptor]:
        """A PVST's crossing times need early times, where a truncated expansion is not accurate: the
        sources of a connected component share its factorizations and lambda_2, and their heat models
        are built together (:func:`heatdata.spectrum.heat_models`)."""
        work = ViewWork(view)
        out: list = [None] * len(sources)
        by_component: dict = {}
        for i, source in enumerate(sources):
            connected, s_local, _ = work.component(int(source))
            by_component.setdefault(id(connected), (connected, []))[1].append((i, s_local))
        for connected, members in by_component.values():
            index, local = (np.array(column) for column in zip(*members, strict=True))
            for i, d in zip(index, self._describe(work, connected, local, sources[index], spec, None), strict=True):
                out[i] = d
        return out

    def _describe(self, work: ViewWork, connected: View, local: np.ndarray, sources: np.ndarray,
                  spec: DescriptorSpec, t_final: float | None) -> list[Descriptor]:
        """One PVST per source of one connected component (``local``: their indices in it)."""
        op = work.operator(connected, None)
        repairs = tuple(connected.repairs[len(work.view.repairs):])
        crossings, t_end, notes = _pvst_times(work, connected, op, local, spec.threshold, t_final)
        out = []
        for crossing, note, s in zip(crossings, notes, sources, strict=True):
            values, positions = sample_boundary(connected, connected.boundary, crossing, spec.samples, spec.sampling)
            out.append(Descriptor(values=values, positions=positions, time=t_end, lambda2=work.lambda2(op),
                                  repairs=repairs + note, **self._common(spec, int(s))))
        return out


register(PVST())


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
