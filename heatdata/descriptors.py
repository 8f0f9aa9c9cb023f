"""PVHK and C-PVHK descriptors of partial views (thesis 2.3, 2.4, Alg. 2.1).

The PVHK is the temperature on the outer boundary of a view at the stopping time
``t_s = 1/lambda_2`` after a unit heat pulse at a source vertex (eq. 2.9). C-PVHK does
the same with colour-dependent diffusion rates (eq. 2.10-2.11).

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
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from matplotlib.colors import rgb_to_hsv

from .errors import ViewError
from .spectrum import HeatOperator, eigen_spectrum, krylov_heat, lambda2, laplacian
from .view import View

log = logging.getLogger(__name__)

SAMPLINGS = ("arclength", "polar")


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
        ``"pvhk"`` or ``"c-pvhk"``.
    values : (M,) float64
        Normalized temperatures (equilibrium = 1) along the boundary.
    positions : (M,) float64
        Where each value was taken: fraction of the boundary length (arclength, and
        per-vertex descriptors) or polar angle / 2 pi (polar).
    source : int
        Source vertex, indexed in the view passed in.
    time : float
        Stopping time t_s.
    lambda2 : float
        First non-zero eigenvalue of the (coloured) view.
    sampling : str
    color_map : str or None
    repairs : tuple of str
        Repairs made to the view for this descriptor (e.g. a component kept).
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


def source_vertex(view: View, rule: str | int = "closest") -> int:
    """The heat source of a view: eq. 2.7 (``"closest"``), eq. 2.8 (``"center"``) or an index."""
    if isinstance(rule, (int, np.integer)):
        if not 0 <= rule < view.n_vertices:
            raise ViewError(f"{view.name}: source vertex {rule} is not in 0..{view.n_vertices - 1}")
        return int(rule)
    x = view.vertices
    if rule == "closest":
        return int(np.argmin(np.einsum("ij,ij->i", x, x)))
    if rule == "center":
        return int(np.argmin(x[:, 0] ** 2 + x[:, 1] ** 2))
    raise ViewError(f"unknown source rule {rule!r} (use 'closest', 'center' or a vertex index)")


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
    temps : (b,) float
        Values at the boundary vertices, in loop order.
    samples : int or None
        M; None keeps one value per boundary vertex.
    sampling : {"arclength", "polar"}

    Returns
    -------
    values, positions : (M,) float64
    """
    cumulative, total = _arclength_positions(view, boundary)
    if samples is None:
        return np.asarray(temps, float), cumulative[:-1] / total
    if samples < 2:
        raise ViewError(f"samples must be at least 2 or None, got {samples}")
    if sampling == "arclength":
        positions = np.arange(samples) / samples
        closed = np.concatenate([temps, temps[:1]])
        return np.interp(positions * total, cumulative, closed), positions
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
    best = np.argmax(radius, axis=1)
    rows = np.arange(samples)
    frac = np.where(hit[rows, best], f[rows, best], 0.0)
    values = (1 - frac) * temps[best] + frac * np.roll(temps, -1)[best]
    missed = ~hit.any(axis=1)
    if missed.any():
        angles = np.arctan2(p[:, 1], p[:, 0])
        gap = np.abs(np.angle(np.exp(1j * (theta[missed, None] - angles[None, :]))))
        values[missed] = temps[np.argmin(gap, axis=1)]
    return values, theta / (2.0 * np.pi)


@dataclass(frozen=True)
class DescriptorSpec:
    """What to compute for a view: kind, samples, source rule, sampling and colour map."""

    kind: str = "pvhk"
    samples: int | None = 64
    source: str | int = "closest"
    sampling: str = "arclength"
    color_map: str | None = None

    @property
    def name(self) -> str:
        """Stable identifier, e.g. ``pvhk/polar/center/64`` or ``c-pvhk/arclength/closest/64/c3``."""
        parts = [self.kind, self.sampling, str(self.source), str(self.samples or "all")]
        return "/".join(parts + ([str(self.color_map)] if self.color_map else []))

    def __post_init__(self):
        if self.kind not in ("pvhk", "c-pvhk"):
            raise ViewError(f"unknown descriptor kind {self.kind!r} (use 'pvhk' or 'c-pvhk')")
        if (self.kind == "c-pvhk") != (self.color_map is not None):
            raise ViewError("a c-pvhk needs a color_map and a pvhk takes none")
        if self.sampling not in SAMPLINGS:
            raise ViewError(f"unknown sampling {self.sampling!r} (use one of {', '.join(SAMPLINGS)})")


def describe(view: View, specs: list[DescriptorSpec], *, method: str = "krylov", modes: int = 30,
             time: float | None = None) -> list[Descriptor]:
    """Several descriptors of one view, sharing the expensive work.

    Descriptors with the same colour map share one factorization and lambda_2; those
    with the same source share one heat solve; samplings of one solve cost nothing
    more. ``method`` and ``modes`` as in :func:`pvhk`; ``time`` overrides t_s.
    """
    if method not in ("krylov", "eigen"):
        raise ViewError(f"unknown method {method!r} (use 'krylov' or 'eigen')")
    operators: dict = {}
    heats: dict = {}
    results = []
    for spec in specs:
        s = source_vertex(view, spec.source)
        connected, s_local = view.component_of(s)
        component = int(view.component_labels[s])
        key = (component, spec.color_map if isinstance(spec.color_map, (str, type(None))) else id(spec.color_map))
        if key not in operators:
            rates = None if spec.color_map is None else color_rates(connected, spec.color_map)
            op = heat_operator(connected, rates)
            if method == "eigen":
                spectrum = eigen_spectrum(op, modes)
                operators[key] = (op, spectrum.lambda2, spectrum)
            else:
                operators[key] = (op, lambda2(op), None)
        op, lam2, spectrum = operators[key]
        t = 1.0 / lam2 if time is None else float(time)
        boundary = connected.boundary
        if (key, s) not in heats:
            if spectrum is not None:
                heats[key, s] = spectrum.heat([s_local], t, at=boundary)[0]
            else:
                heats[key, s] = krylov_heat(op, s_local, [t], at=boundary)[0]
        values, positions = sample_boundary(connected, boundary, heats[key, s], spec.samples, spec.sampling)
        color = spec.color_map if isinstance(spec.color_map, (str, type(None))) else \
            getattr(spec.color_map, "__name__", "custom")
        results.append(Descriptor(kind=spec.kind, values=values, positions=positions, source=s, time=t,
                                  lambda2=lam2, sampling=spec.sampling, color_map=color,
                                  repairs=tuple(connected.repairs[len(view.repairs):])))
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
    source : {"closest", "center"} or int
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
