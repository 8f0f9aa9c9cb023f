"""The Partial View Stochastic Time (thesis 5.4.2, Alg. 5.3): when each boundary point warms up.

For each boundary point, the first time its normalized temperature (equilibrium = 1)
reaches a threshold T_a after a unit pulse at an interior source. Instead of ~1200
eigenpairs, the heat over the window is a shift-invert Krylov projection, an explicit
sum of exponentials in t, bracketed on a log grid and bisected.
"""

from __future__ import annotations

import dataclasses
import itertools
import logging
from collections.abc import Mapping

import numpy as np
from scipy.optimize import brentq

from heatdata.core.spectrum import HeatOperator, first_crossings, heat_model
from heatdata.descriptors.base import (
    Descriptor,
    DescriptorSpec,
    Option,
    number,
    one_of,
    register,
)
from heatdata.descriptors.boundary import sample_boundary
from heatdata.descriptors.compute import describe
from heatdata.descriptors.heat import SAMPLES, SAMPLING, SOURCE, BoundaryKind
from heatdata.descriptors.work import ViewWork
from heatdata.errors import SpecError, ViewError
from heatdata.views.view import View

log = logging.getLogger(__name__)

PVST_THRESHOLD = 0.75  # T_a of Alg. 5.3, a fraction of the equilibrium temperature
THRESHOLD_KIND = "pvst"  # the kind a threshold without a kind asks for (the CLI's --threshold)
PVST_WINDOW = 10.0  # t_final = PVST_WINDOW / lambda_2 (Alg. 5.3)


# Widest time ratios one heat model covers: the last chunk, on the PVHK's factorization, and
# earlier ones, each on a factorization shifted to its start (both converge in ~30-70 Krylov steps).
PVST_CHUNK = 1024.0
PVST_EARLY_CHUNK = 256.0
# Convergence tolerance of the PVST's heat models on normalized temperatures: the crossing times
# come out within ~1e-6 relative of a dense reference (benchmarks/bench_pvst.py), the target being 1e-3.
PVST_TOL = 1e-4
MIN_THRESHOLD = 100 * PVST_TOL  # thresholds closer to the model's error give crossings of noise
# time_axis "log": a decade of time weighs in the MHD of eq. 3.1 as a tenth of the boundary's length. Chosen by
# leave-one-out among the 58 chairs' library views (no test view): 0.1 75.1%, 0.3 73.3%, 1 67.2%, linear 56.2%.
LOG_TIME_WEIGHT = 0.1
TIME_AXES = ("linear", "log")


def _chunk_model(work: ViewWork, op: HeatOperator, source: int, boundary: np.ndarray, t0: float, t1: float, late: bool):
    """Heat model converged on ``[t0, t1]``: on the PVHK's factorization for the latest chunk, else on one
    shifted to ``1/t0`` rounded to a power of 2 (cheap: the shifted matrix is diagonally dominant). The
    rounding lets the sources of a view share these factorizations (:meth:`ViewWork.shifted`): 64
    candidate sources of a chair view need ~17 instead of ~86."""
    chunk_op = op if late else work.shifted(op, 2.0 ** round(np.log2(1.0 / t0)))
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


def _pvst_times(
    work: ViewWork, connected: View, op: HeatOperator, source: int, threshold: float, t_final: float | None
) -> tuple[np.ndarray, float, tuple]:
    """First crossing times of the threshold at the boundary vertices (Alg. 5.3, see :func:`pvst`)."""
    boundary = connected.boundary
    if np.any(boundary == source):
        raise ViewError(
            f"{connected.name}: the source vertex {source} is on the outer boundary; the PVST needs "
            "an interior source (Lemma 1, 5.4.2) - choose another source rule or vertex"
        )
    t_end = PVST_WINDOW / work.lambda2(op) if t_final is None else float(t_final)
    t_start = _pvst_start(connected, source, threshold)
    if not t_end > t_start:
        raise ViewError(f"{connected.name}: the PVST window ends at t = {t_end:.3g}, before it starts ({t_start:.3g})")
    edges = [t_end]  # chunk edges from the end; a leftover of less than 4x joins its neighbour
    while edges[-1] > t_start:
        ratio = PVST_CHUNK if len(edges) == 1 else PVST_EARLY_CHUNK
        edges.append(edges[-1] / ratio if edges[-1] / ratio > 4.0 * t_start else t_start)
    chunks = [
        (t0, t1, _chunk_model(work, op, source, boundary, t0, t1, late=t1 == t_end))
        for t1, t0 in itertools.pairwise(edges)
    ][::-1]

    def above_at_start():
        return chunks[0][2](np.array([chunks[0][0]]))[0] >= threshold

    early = above_at_start()
    for _ in range(4):  # start earlier while a boundary point is already above the threshold
        if not early.any():
            break
        t0 = chunks[0][0]
        chunks.insert(0, (t0 / 16.0, t0, _chunk_model(work, op, source, boundary, t0 / 16.0, t0, late=False)))
        early = above_at_start()
    times = np.full(len(boundary), np.nan)
    for t0, t1, model in chunks:  # the first crossing is in the earliest chunk that has one
        found = first_crossings(model, threshold, t0, t1)
        times = np.where(np.isnan(times), found, times)
    times[early] = np.nan  # no crossing from below in the window
    notes = []
    late = np.isnan(times) & ~early
    if early.any():
        notes.append(
            f"pvst: {int(early.sum())} boundary vertices are above T = {threshold:g} already at "
            f"t = {chunks[0][0]:.3g}: NaN"
        )
    if late.any():
        notes.append(
            f"pvst: {int(late.sum())} boundary vertices do not reach T = {threshold:g} by t = {t_end:.3g}: NaN"
        )
    for note in notes:
        log.warning("%s: %s", connected.name, note)
    return times, t_end, tuple(notes)


class PVST(BoundaryKind):
    name = THRESHOLD_KIND
    summary = "Partial View Stochastic Time: first time each boundary point reaches T_a (Alg. 5.3)"
    options = (
        SAMPLES,
        # the PVST needs a source off the outer boundary (Lemma 1): the interior rule finds one on every view
        dataclasses.replace(SOURCE, default="interior"),
        SAMPLING,
        Option(
            "threshold",
            PVST_THRESHOLD,
            "threshold T_a, a fraction of the equilibrium temperature in (0, 1)",
            number(0.0, 1.0),
        ),
        Option(
            "time_axis",
            "linear",
            "linear: the crossing times (the thesis's); log: 0.1 log10 of them, so "
            "that eq. 3.1 compares times by their ratios (not in the thesis)",
            one_of(TIME_AXES),
        ),
    )
    multi_source = True
    value_label = "time to reach T_a (m^2, the unit of t_s = 1/lambda_2)"

    def validate(self, options: dict) -> dict:
        threshold = options["threshold"]
        if threshold >= 1.0:
            raise SpecError(f"pvst: option threshold is a fraction of the equilibrium in (0, 1), got {threshold}")
        if threshold < MIN_THRESHOLD:
            raise SpecError(
                f"pvst: option threshold must be at least {MIN_THRESHOLD:g}: the heat models are "
                f"converged to {PVST_TOL:g} of the equilibrium, too coarse to place a crossing of "
                f"{threshold:g}"
            )
        return options

    def label(self, options: Mapping) -> str:
        label = f"{super().label(options)}/T{options['threshold']:g}"
        return label if options["time_axis"] == "linear" else f"{label}/log-time"

    def compute(self, work: ViewWork, spec: DescriptorSpec, **context) -> list[Descriptor]:
        connected, s_local, s = work.component(spec.source)
        op = work.operator(connected, None)
        repairs = tuple(connected.repairs[len(work.view.repairs) :])
        t_final = context.get("t_final")
        crossing, t_end, notes = work.cached(
            ("pvst", id(op), s_local, spec.threshold, t_final),
            lambda: _pvst_times(work, connected, op, s_local, spec.threshold, t_final),
        )  # both time axes of a source: one search
        values, positions = sample_boundary(connected, connected.boundary, crossing, spec.samples, spec.sampling)
        if spec.time_axis == "log":
            values = LOG_TIME_WEIGHT * np.log10(values)
        return [
            Descriptor(
                values=values,
                positions=positions,
                time=t_end,
                lambda2=work.lambda2(op),
                repairs=repairs + notes,
                **self._common(spec, s),
            )
        ]

    def candidates(
        self, view: View, sources: np.ndarray, spec: DescriptorSpec, *, times=None, modes: int = 32
    ) -> list[Descriptor]:
        """A PVST's crossing times need early times, where a truncated expansion is not accurate: the
        sources share the factorizations and lambda_2, and each gets its own heat models (building them
        in lockstep did not pay: ``benchmarks/README.md``)."""
        return describe(view, [spec.replace(source=int(s)) for s in sources])


register(PVST())


def pvst(
    view: View,
    samples: int | None = 64,
    threshold: float = PVST_THRESHOLD,
    source: str | int = "interior",
    *,
    sampling: str = "arclength",
    t_final: float | None = None,
    time_axis: str = "linear",
) -> Descriptor:
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
    source : {"interior", "closest", "center"} or int
        Must not be on the outer boundary (Lemma 1): a :class:`ViewError` otherwise. The default, ``"interior"``,
        is off it on every view; the image centre or the closest point can fall on the outline.
    sampling : {"arclength", "polar"}
    t_final : float, optional
        End of the search window, default ``10 / lambda_2``. Boundary points that do not
        reach the threshold by then are NaN, logged and listed in ``repairs``.
    time_axis : {"linear", "log"}
        ``"log"``: the values are ``0.1 log10(t / m^2)`` (``LOG_TIME_WEIGHT``), so that the MHD
        of eq. 3.1 compares times by their ratios and a decade weighs as a tenth of the
        boundary. Not in the thesis: on 58 chairs it lifts the PVST from 43.3% to 57.9% at
        8 library views, and changes the household objects by -0.9 to +1.2 points
        (``scripts/value_scales.py``).

    Returns
    -------
    Descriptor
        ``time`` is the end of the window.
    """
    spec = DescriptorSpec("pvst", samples, source, sampling, threshold=threshold, time_axis=time_axis)
    return describe(view, [spec], t_final=t_final)[0]
