"""Where a heat kind's heat starts and where it is read: source rules and boundary sampling (thesis 2.3.2-2.3.3).

Source rules (2.3.2): ``"closest"`` to the observer (eq. 2.7) or ``"center"`` of the
segmented depth image (eq. 2.8), ``"interior"``, or any vertex index.

Boundary sampling (2.3.3): ``"arclength"`` takes M samples evenly spaced in 3D length
along the boundary from its origin, interpolating linearly between boundary vertices;
``"polar"`` takes the outermost crossing of the boundary with M rays evenly spaced in
polar angle about the image centre (angle 0 = +x axis, counter-clockwise), falling
back to the nearest-angle boundary vertex for a ray that misses the boundary (a centre
outside the shape). ``samples=None`` returns one value per boundary vertex.

The colour maps of 3.4.2 turn a view's RGB into the diffusion rates of eq. 2.10; ``sat-hue``
(not in the thesis) weighs the hue by the saturation, so that greys, whose hue is undefined
(0, the hue of red, by convention), all get one rate.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.spatial import cKDTree

from heatdata.errors import ViewError
from heatdata.views.view import View

SAMPLINGS = ("arclength", "polar")
SOURCE_RULES = ("closest", "center", "interior")


def _hsv(rgb: np.ndarray) -> np.ndarray:
    """(n, 3) RGB in [0, 1] to HSV (matplotlib's, imported here so that ``import heatdata`` does not load it)."""
    from matplotlib.colors import rgb_to_hsv

    return rgb_to_hsv(np.clip(rgb, 0.0, 1.0))


def _hue(rgb: np.ndarray) -> np.ndarray:
    return _hsv(rgb)[:, 0]


def _saturated_hue(rgb: np.ndarray) -> np.ndarray:
    """Rates ``1 + 8 s h``: 1 on greys (s = 0), up to 9 on saturated colours (the colour twins)."""
    hsv = _hsv(rgb)
    return 1.0 + 8.0 * hsv[:, 1] * hsv[:, 0]


#: Scalar maps of 3.4.2 from RGB to the diffusion rate c(v); h is the hue in [0, 1], s the saturation.
COLOR_MAPS: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "c1": lambda rgb: (_hue(rgb) + 0.5) * 2.0,
    "c2": lambda rgb: (_hue(rgb) + 1e-3) * 2.0,
    "c3": lambda rgb: (_hue(rgb) + 5.0) * 2.0,
    "c4": lambda rgb: (_hue(rgb) + 0.5) * 10.0,
    "hue": lambda rgb: 0.5 + 0.5 * _hue(rgb),  # hue scaled to [0.5, 1], the example of 2.4
    "sat-hue": _saturated_hue,
}


def source_vertex(view: View, rule: str | int = "closest") -> int:
    """The heat source of a view: eq. 2.7 (``"closest"``), eq. 2.8 (``"center"``), ``"interior"`` or an index.

    ``"interior"`` (not in the thesis) is the vertex farthest from the outer boundary: never
    on it, as the PVST needs (Lemma 1), and on the view's largest part. On a chair, the
    image centre often falls between the legs or the back's slats, and ``"center"`` then
    picks a vertex of the outline.

    Parameters
    ----------
    view : View
        A partial view (thesis 2.1).
    rule : {"closest", "center", "interior"} or int
        The rule, or a vertex index (checked).

    Returns
    -------
    int
        The source's vertex index.
    """
    if isinstance(rule, (int, np.integer)):
        if not 0 <= rule < view.n_vertices:
            raise ViewError(f"{view.name}: source vertex {rule} is not in 0..{view.n_vertices - 1}")
        return int(rule)
    x = view.vertices
    if rule == "closest":
        return int(np.argmin(np.einsum("ij,ij->i", x, x)))
    if rule == "center":  # in the camera frame turned to face the segment (View.canonical_rotation)
        c = view.canonical_vertices
        return int(np.argmin(c[:, 0] ** 2 + c[:, 1] ** 2))
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


def _arclength_positions(view: View, boundary: np.ndarray) -> tuple[np.ndarray, float]:
    points = view.vertices[boundary]
    steps = np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1)
    cumulative = np.concatenate([[0.0], np.cumsum(steps)])
    return cumulative, float(cumulative[-1])


def sample_boundary(
    view: View, boundary: np.ndarray, temps: np.ndarray, samples: int | None, sampling: str = "arclength"
) -> tuple[np.ndarray, np.ndarray]:
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


def _sample_points(
    view: View, boundary: np.ndarray, samples: int | None, sampling: str
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
