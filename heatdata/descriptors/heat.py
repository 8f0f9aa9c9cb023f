"""The heat kinds: PVHK, C-PVHK and FT-PVHK (thesis 2.3-2.4, 5.3-5.4.1), and what they share.

The PVHK is the temperature on the outer boundary of a view at the stopping time
``t_s = 1/lambda_2`` after a unit heat pulse at a source vertex (Alg. 2.1, eq. 2.9).
C-PVHK does the same with colour-dependent diffusion rates (eq. 2.10-2.11). For complex
objects (ch. 5) the FT-PVHK takes the temperature at a fixed, per-object time (Alg. 5.1)
and comes with part weights for the weighted distance of eq. 5.14.

All three compare curves with the modified Hausdorff distance of eq. 3.1 (eq. 5.14
with part weights), and all three can be computed for many sources of one view from one
eigen-decomposition (6.2.1).
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterable, Mapping, Sequence

import numpy as np

from heatdata.core.distances import mhd_matrix, nearest_mhd
from heatdata.core.spectrum import HeatOperator, eigen_spectrum, lambda2
from heatdata.descriptors.base import (
    Descriptor,
    DescriptorSpec,
    Kind,
    Option,
    integer,
    one_of,
    register,
)
from heatdata.descriptors.boundary import (
    COLOR_MAPS,
    SAMPLINGS,
    SOURCE_RULES,
    color_rates,
    sample_boundary,
)
from heatdata.descriptors.compute import describe
from heatdata.descriptors.work import (
    WEIGHT_MODES,
    ViewWork,
    checked_times,
    heat_operator,
)
from heatdata.errors import SpecError, ViewError
from heatdata.views.view import View

log = logging.getLogger(__name__)

DEFAULT_KIND = "pvhk"  # what a boundary option without a kind asks for (the CLI's --samples, --source, --sampling)
COLOR_KIND = "c-pvhk"  # what a colour map without a kind asks for (the CLI's --color-map)
MIN_MAIN_SHARE = 0.25  # below this share of boundary samples on the main part, part weights are unit
TRUNCATION = 1e-7  # exp(-lambda_k t) of the first mode left out of the multi-source expansion
#: the source rule of the ch. 6 candidate rows (:func:`heatdata.experiments.describe.candidate_rows`); not computable
CANDIDATES_RULE = "candidates"


def _source(value):
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        if value < 0:
            raise ValueError(f"must be a vertex index >= 0 or one of {', '.join(SOURCE_RULES)}, got {value}")
        return int(value)
    if value in SOURCE_RULES or value == CANDIDATES_RULE:
        return value
    raise ValueError(f"must be one of {', '.join(SOURCE_RULES)} or a vertex index, got {value!r}")


def _color_map(value):
    if isinstance(value, str) and value not in COLOR_MAPS:
        raise ValueError(
            f"must be a colour map: one of {', '.join(COLOR_MAPS)} or a function of (n, 3) RGB, got {value!r}"
        )
    if not isinstance(value, str) and not callable(value):
        raise TypeError(f"must be a colour map name or a function, got {value!r}")
    return value


SAMPLES = Option(
    "samples",
    64,
    "boundary samples M (None: one value per boundary vertex)",
    integer(2, 4096, allow_none=True),
    none_is_default=False,
)
SOURCE = Option(
    "source", "closest", "source rule: closest (eq. 2.7), center (eq. 2.8), interior, or a vertex index", _source
)
SAMPLING = Option("sampling", "arclength", "boundary sampling (2.3.3): arclength or polar", one_of(SAMPLINGS))
COLOR_MAP = Option(
    "color_map", None, "colour map of 3.4.2 (c1, c2, c3, c4, hue), sat-hue, or a function of RGB", _color_map
)
CLOCKS = ("color", "shape")
CLOCK = Option(
    "clock",
    "color",
    "whose 1/lambda_2 stops the C-PVHK: color (the coloured operator's, eq. 2.11) "
    "or shape (the colourless Laplacian's, so that a uniform change of colour shows)",
    one_of(CLOCKS, {"colour": "color"}),
)
BOUNDARY_OPTIONS = (SAMPLES, SOURCE, SAMPLING)


def color_name(color_map) -> str | None:
    """A colour map as it is recorded: its name, or a function's ``__name__``."""
    return color_map if isinstance(color_map, (str, type(None))) else getattr(color_map, "__name__", "custom")


class BoundaryKind(Kind):
    """A descriptor read along the outer boundary after a heat pulse at a source (2.3)."""

    options: tuple[Option, ...] = BOUNDARY_OPTIONS
    distance_name = "modified Hausdorff distance, eq. 3.1"
    index_space: str | None = "l1"  # Alg. 6.1's shortlist

    def label(self, options: Mapping) -> str:
        parts = [self.name, options["sampling"], str(options["source"]), str(options["samples"] or "all")]
        if options.get("color_map"):
            parts.append(str(color_name(options["color_map"])))
        return "/".join(parts)

    def size(self, spec: DescriptorSpec, view: View) -> int:
        return spec.samples or len(view.boundary)

    def distance_matrix(self, queries, library, *, query_weights=None, library_weights=None):
        """Eq. 3.1 between the curves (i/M, z_i); eq. 5.14 with part weights."""
        return mhd_matrix(queries, library, query_weights=query_weights, library_weights=library_weights)

    def nearest(self, queries, library, *, query_weights=None, library_weights=None, within=None, chunk=None):
        """Exact search under eq. 3.1 / 5.14 with no distance matrix (:func:`heatdata.core.distances.nearest_mhd`)."""
        return nearest_mhd(
            queries, library, query_weights=query_weights, library_weights=library_weights, within=within
        )

    @staticmethod
    def _common(spec: DescriptorSpec, source: int) -> dict:
        return dict(kind=spec.kind, source=source, sampling=spec.sampling, color_map=color_name(spec.get("color_map")))


class HeatKind(BoundaryKind):
    """PVHK-like kinds: the boundary temperature at one or more times, from a shared heat solve."""

    multi_source = True
    value_label = "temperature (equilibrium = 1)"

    def times(self, work: ViewWork, connected: View, op: HeatOperator, spec: DescriptorSpec, context: dict) -> tuple:
        """The times to read the temperature at; the PVHK's is t_s = 1/lambda_2 (2.3.1)."""
        return (1.0 / work.lambda2(op),)

    def weights(self, work: ViewWork, connected: View, op: HeatOperator, spec: DescriptorSpec, context: dict):
        """(part weights or None, lambda_2 or NaN, repairs)."""
        return None, work.lambda2(op), ()

    def compute(self, work: ViewWork, spec: DescriptorSpec, **context) -> list[Descriptor]:
        connected, s_local, s = work.component(spec.source)
        op = work.operator(connected, spec.get("color_map"))
        repairs = tuple(connected.repairs[len(work.view.repairs) :])
        spec_times = self.times(work, connected, op, spec, context)
        weights, lam2, notes = self.weights(work, connected, op, spec, context)
        temps = work.heat(op, s_local, spec_times, connected.boundary)
        out = []
        for t, row in zip(spec_times, temps, strict=True):
            values, positions = sample_boundary(connected, connected.boundary, row, spec.samples, spec.sampling)
            out.append(
                Descriptor(
                    values=values,
                    positions=positions,
                    time=t,
                    lambda2=lam2,
                    repairs=repairs + notes,
                    weights=weights,
                    **self._common(spec, s),
                )
            )
        return out

    def spectrum_times(self, spectrum, connected: View, spec: DescriptorSpec, times) -> tuple:
        return (1.0 / spectrum.lambda2,)

    def candidates(
        self,
        view: View,
        sources: np.ndarray,
        spec: DescriptorSpec,
        *,
        times: Sequence[float] | None = None,
        modes: int = 32,
    ) -> list[Descriptor]:
        """One descriptor per source from one eigen-decomposition per connected component (6.2.1).

        ``Phi_B diag(exp(-lambda t)) Phi_S^T`` times ``sum(c)`` (eq. 2.9/2.11 with the heat
        kernel's symmetry); the eigenpairs are doubled until the first mode left out weighs
        less than 1e-7 at the earliest time. Source-major; no part weights.
        """
        labels = view.component_labels[sources]
        out: dict[int, list[Descriptor]] = {}
        for label in np.unique(labels):
            group = np.flatnonzero(labels == label)
            connected = view.component_of(int(sources[group[0]]))[0]
            local = np.cumsum(view.component_labels == label) - 1  # view vertex -> component vertex
            on_boundary = np.isin(local[sources[group]], connected.boundary)
            if on_boundary.any():
                log.info(
                    "%s: %d of %d sources are on the outer boundary", view.name, int(on_boundary.sum()), len(group)
                )
            color_map = spec.get("color_map")
            op = heat_operator(connected, None if color_map is None else color_rates(connected, color_map))
            spectrum = eigen_spectrum(op, modes)
            spec_times = self.spectrum_times(spectrum, connected, spec, times)  # lambda_2 stays as modes double
            while spectrum.truncation(min(spec_times)) > TRUNCATION and len(spectrum.values) < op.n - 2:
                spectrum = eigen_spectrum(op, 2 * len(spectrum.values))
            repairs = tuple(connected.repairs[len(view.repairs) :])
            per_time = []
            for t in spec_times:
                heat = spectrum.heat(local[sources[group]], t, at=connected.boundary)  # (s, b)
                values, positions = sample_boundary(connected, connected.boundary, heat, spec.samples, spec.sampling)
                per_time.append(values)
            for row, g in enumerate(group):
                out[int(g)] = [
                    Descriptor(
                        values=v[row],
                        positions=positions,
                        time=t,
                        lambda2=spectrum.lambda2,
                        repairs=repairs,
                        **self._common(spec, int(sources[g])),
                    )
                    for t, v in zip(spec_times, per_time, strict=True)
                ]
        return [d for g in range(len(sources)) for d in out[g]]


class PVHK(HeatKind):
    name = "pvhk"
    summary = "Partial View Heat Kernel: boundary temperature at t_s = 1/lambda_2 (Alg. 2.1, eq. 2.9)"


class ColorPVHK(HeatKind):
    """The C-PVHK of eq. 2.10-2.11, stopped at the coloured or the colourless 1/lambda_2 (option ``clock``).

    With the thesis's clock (``"color"``) the descriptor cannot see a colour that is the
    same all over the view: rates ``c`` everywhere divide lambda_2 by ``c`` and stretch
    the heat's time by ``c``, and the two cancel at t_s, so an object and its colour twin
    give the same curve. The ``"shape"`` clock (not in the thesis) stops at the colourless
    Laplacian's 1/lambda_2 instead: the view's mean rate then shows as a change of time.
    """

    name = "c-pvhk"
    summary = "Colour PVHK: diffusion rates from the view's hue (eq. 2.10-2.11, 3.4.2)"
    options = (*BOUNDARY_OPTIONS, COLOR_MAP, CLOCK)

    def validate(self, options: dict) -> dict:
        if options["color_map"] is None:
            raise SpecError("a c-pvhk needs a color_map (c1, c2, c3, c4, hue, sat-hue or a function)")
        return options

    def label(self, options: Mapping) -> str:
        label = super().label(options)
        return label if options["clock"] == "color" else f"{label}/{options['clock']}-clock"

    def times(self, work, connected, op, spec, context) -> tuple:
        if spec.clock == "shape":
            return (1.0 / work.lambda2(work.operator(connected, None)),)
        return super().times(work, connected, op, spec, context)

    def spectrum_times(self, spectrum, connected, spec, times) -> tuple:
        if spec.clock == "shape":
            return (1.0 / lambda2(heat_operator(connected)),)
        return super().spectrum_times(spectrum, connected, spec, times)


class FixedTimePVHK(HeatKind):
    name = "ft-pvhk"
    summary = "Fixed-time PVHK at the objects' time scales (Alg. 5.1), part-weighted distance (eq. 5.12-5.14, Alg. 5.2)"
    time_scaled = True
    weighted = True
    index_space = None

    def times(self, work, connected, op, spec, context) -> tuple:
        times = context.get("times")
        chosen = times.get(spec.name) if isinstance(times, Mapping) else times
        return checked_times(chosen, f"{work.view.name}: the ft-pvhk {spec.name}")

    def weights(self, work, connected, op, spec, context):
        if not context.get("part_weights", True):
            return None, float("nan"), ()
        weights, notes = _part_weights(work, connected, op, spec.samples, spec.sampling)
        return weights, work.lambda2(op), notes

    def spectrum_times(self, spectrum, connected, spec, times) -> tuple:
        return checked_times(times, f"the ft-pvhk {spec.name}")


for _kind in (PVHK(), ColorPVHK(), FixedTimePVHK()):
    register(_kind)


def _part_weights(
    work: ViewWork, connected: View, op: HeatOperator, samples, sampling: str
) -> tuple[np.ndarray, tuple]:
    """rho of eq. 5.13 at the descriptor's samples, and the repair made (if any)."""
    boundary = connected.boundary
    delta, _ = sample_boundary(connected, boundary, work.global_derivative(op, boundary), samples, sampling)
    mean_square = float(np.mean(delta**2))
    rho = np.exp(-(delta**2) / mean_square) if mean_square > 0 else np.ones_like(delta)
    share = float(np.mean(rho >= 0.5))
    if share < MIN_MAIN_SHARE:
        note = (
            f"part weights: only {share:.0%} of the boundary is on the main part (rho >= 0.5); "
            "unit weights used (eq. 3.1)"
        )
        log.warning("%s: %s", connected.name, note)
        return np.ones_like(rho), (note,)
    return rho, ()


def pvhk(
    view: View,
    samples: int | None = 64,
    source: str | int = "closest",
    *,
    sampling: str = "arclength",
    method: str = "krylov",
    modes: int = 30,
) -> Descriptor:
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


def c_pvhk(
    view: View,
    samples: int | None = 64,
    color_map: str | Callable = "c3",
    source: str | int = "closest",
    *,
    sampling: str = "arclength",
    clock: str = "color",
    method: str = "krylov",
    modes: int = 30,
) -> Descriptor:
    """Colour PVHK (eq. 2.10-2.11): diffusion rates ``c(v)`` from the view's RGB.

    ``color_map`` is one of :data:`COLOR_MAPS` (``c1``..``c4`` of 3.4.2, ``hue``,
    ``sat-hue``) or a function from (n, 3) RGB in [0, 1] to (n,) positive rates.
    ``clock="shape"`` stops at the colourless view's 1/lambda_2 instead of the coloured
    one's (:class:`ColorPVHK`). Other parameters as :func:`pvhk`.

    Parameters
    ----------
    view : View
        A partial view (thesis 2.1).
    samples : int or None
        Boundary samples M; None keeps every boundary vertex.
    color_map : str or callable
        One of :data:`COLOR_MAPS` (``c1``..``c4`` of 3.4.2, ``hue``, ``sat-hue``), or a function
        from (n, 3) RGB in [0, 1] to (n,) positive diffusion rates.
    source : str or int
        The heat source: a rule of :func:`source_vertex` or a vertex index.
    sampling : {"arclength", "polar"}
        How the boundary is sampled (2.5).
    clock : {"color", "shape"}
        Whose 1/lambda_2 stops the diffusion: the coloured operator's (eq. 2.11) or the colourless one's.
    method : {"krylov", "eigen"}
        Heat by a Krylov solve or by ``modes`` eigenpairs.
    modes : int
        Eigenpairs for ``method="eigen"``.

    Returns
    -------
    Descriptor
        Kind ``c-pvhk``: ``values`` (M,) temperatures at t_s = 1/lambda_2, equilibrium 1.
    """
    spec = DescriptorSpec("c-pvhk", samples, source, sampling, color_map, clock)
    return describe(view, [spec], method=method, modes=modes)[0]


def ft_pvhk(
    view: View,
    time: float,
    samples: int | None = 64,
    source: str | int = "closest",
    *,
    sampling: str = "arclength",
    method: str = "krylov",
    modes: int = 30,
) -> Descriptor:
    """Fixed-time PVHK (5.4.1): the PVHK at a given time, e.g. :func:`object_time_scale`.

    Costs one heat solve and no lambda_2 (``Descriptor.lambda2`` is NaN); its part weights
    come from :func:`part_weights`. Other parameters as :func:`pvhk`.

    Parameters
    ----------
    view : View
        A partial view (thesis 2.1).
    time : float
        The fixed diffusion time (e.g. :func:`object_time_scale`), > 0.
    samples, source, sampling, method, modes
        As for :func:`c_pvhk`.

    Returns
    -------
    Descriptor
        Kind ``ft-pvhk``: ``values`` (M,) temperatures at ``time``; ``weights`` (M,) the part weights.
    """
    spec = DescriptorSpec("ft-pvhk", samples, source, sampling)
    return describe(view, [spec], method=method, modes=modes, times=[time], part_weights=False)[0]


def part_weights(
    view: View, samples: int | None = 64, *, sampling: str = "arclength", source: str | int = "closest"
) -> np.ndarray:
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

    Parameters
    ----------
    view : View
        A partial view (thesis 2.1).
    samples, sampling, source
        As for :func:`pvhk`: the weights are at that descriptor's samples.
    """
    work = ViewWork(view, "krylov", 30)
    connected, _, _ = work.component(source)
    weights, _ = _part_weights(work, connected, work.operator(connected, None), samples, sampling)
    return weights


def global_derivative(view: View, source: str | int = "closest", time: float | None = None) -> np.ndarray:
    """Source-position global derivative (eq. 5.12) at every vertex of the source's component (Fig. 5.7).

    ``time`` defaults to t_global = 1/lambda_2. Returns (n_component,) float64.

    Parameters
    ----------
    view : View
        A partial view (thesis 2.1).
    source : str or int
        As for :func:`source_vertex`: it chooses the connected component.
    time : float, optional
        Diffusion time; default t_global = 1/lambda_2.

    Returns
    -------
    (n_component,) float64
        The derivative at every vertex of the source's component, 1/m^2.
    """
    work = ViewWork(view, "eigen", WEIGHT_MODES)
    connected, _, _ = work.component(source)
    return work.global_derivative(
        work.operator(connected, None), np.arange(connected.n_vertices), None if time is None else float(time)
    )


def view_time_scale(view: View, source: str | int = "closest") -> float:
    """t_global = 1/lambda_2 of the component holding the source (2.3.1).

    Parameters
    ----------
    view : View
        A partial view (thesis 2.1).
    source : str or int
        As for :func:`source_vertex`: it chooses the connected component.

    Returns
    -------
    float
        1/lambda_2 of that component, in the mesh's units squared (m^2 for a view in metres).
    """
    work = ViewWork(view, "krylov", 30)
    connected, _, _ = work.component(source)
    return 1.0 / work.lambda2(work.operator(connected, None))


def object_time_scale(views: Iterable[View], source: str | int = "closest") -> float:
    """Main-part time scale of an object (Alg. 5.1): the smallest 1/lambda_2 over its views.

    Parameters
    ----------
    views : iterable of View
        Partial views of one object from several view angles.

    Returns
    -------
    float
        The smallest t_global = 1/lambda_2 among the views (Alg. 5.1).
    """
    scales = {view.name: view_time_scale(view, source) for view in views}
    if not scales:
        raise ViewError("object_time_scale needs at least one view")
    name = min(scales, key=lambda n: scales[n])
    log.info(
        "time scale %.4g from %s (min of %d views; max %.4g)", scales[name], name, len(scales), max(scales.values())
    )
    return scales[name]
