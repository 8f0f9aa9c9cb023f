"""The expensive pieces of one view, each computed once and shared by every descriptor of it.

One factorization per colour map and component, one lambda_2 per factorization, one
heat solve per (source, times), one spectrum per mode count, and the points and normals
the histogram kinds read (thesis 2.2-2.4; the sharing is what makes five descriptors
of a view cost little more than one).
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence

import numpy as np

from heatdata.core.spectrum import (
    HeatOperator,
    Spectrum,
    eigen_spectrum,
    krylov_heat,
    lambda2,
    laplacian,
)
from heatdata.descriptors.boundary import color_rates, source_vertex
from heatdata.errors import SpecError, SpectrumError, ViewError
from heatdata.views.view import View

log = logging.getLogger(__name__)

WEIGHT_MODES = 16  # eigenpairs for the global derivative; doubled while the truncation shows


def heat_operator(view: View, rates: np.ndarray | None = None) -> HeatOperator:
    """The :class:`HeatOperator` of a connected view."""
    if view.n_components > 1:
        raise ViewError(
            f"{view.name}: {view.n_components} connected components; "
            "take one with view.component_of(vertex) or view.largest_component()"
        )
    return HeatOperator(laplacian(view.vertices, view.edges, view.name), rates, view.name)


def checked_times(times, what: str) -> tuple:
    """Diffusion times as a tuple of positive finite floats; a clear error, naming ``what``, for none or a bad list."""
    if times is None:
        raise SpecError(f"{what} needs times= (the object's time scale, Alg. 5.1)")
    values = np.atleast_1d(np.asarray(times, dtype=np.float64)) if np.size(times) else np.array([])
    if values.ndim != 1 or len(values) == 0 or not np.all(np.isfinite(values)) or np.any(values <= 0):
        raise ViewError(f"{what}: times must be one or more positive finite times, got {list(np.ravel(times))}")
    return tuple(float(t) for t in values)


def heat_kernel(
    view: View,
    source: int | str = "closest",
    times: Sequence[float] | None = None,
    *,
    color_map: str | Callable[[np.ndarray], np.ndarray] | None = None,
    tol: float = 1e-7,
) -> np.ndarray:
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
    times = None if times is None else checked_times(times, view.name)
    rates = None if color_map is None else color_rates(view, color_map)
    op = heat_operator(view, rates)
    times = [1.0 / lambda2(op)] if times is None else times
    return krylov_heat(op, source_vertex(view, source), np.asarray(times, float), tol=tol)


class ViewWork:
    """The expensive pieces of one view, each computed once: factorization, lambda_2, spectra, heat."""

    def __init__(self, view: View, method: str = "krylov", modes: int = 30):
        if method not in ("krylov", "eigen"):
            raise ViewError(f"unknown method {method!r} (use 'krylov' or 'eigen')")
        self.view, self.method, self.modes = view, method, modes
        self.cache: dict = {}

    def cached(self, key, compute):
        """The value under ``key``, computed once per view by ``compute()``."""
        if key not in self.cache:
            self.cache[key] = compute()
        return self.cache[key]

    def component(self, source_rule) -> tuple[View, int, int]:
        """(connected component, source index in it, source index in the view)."""
        s = source_vertex(self.view, source_rule)
        label = int(self.view.component_labels[s])
        connected = self.cached(("component", label), lambda: self.view.component_of(s)[0])
        s_local = s if connected is self.view else int(np.sum(self.view.component_labels[:s] == label))
        return connected, s_local, s

    def largest(self) -> View:
        """The view's largest connected component (the view itself when it has one), for kinds without a source."""
        return self.cached(
            ("largest",), lambda: self.view if self.view.n_components == 1 else self.view.largest_component()
        )

    def normals(self) -> np.ndarray:
        """(n, 3) unit vertex normals of the view's mesh (area-weighted face normals), facing the camera."""

        def compute():
            import open3d as o3d

            mesh = o3d.geometry.TriangleMesh(
                o3d.utility.Vector3dVector(np.array(self.view.vertices, np.float64)),
                o3d.utility.Vector3iVector(self.view.faces.astype(np.int32)),
            )
            normals = np.asarray(mesh.compute_vertex_normals().vertex_normals, dtype=np.float64)
            facing_away = np.einsum("ij,ij->i", normals, self.view.vertices) > 0  # camera at the origin
            normals[facing_away] *= -1.0
            return normals

        return self.cached(("normals",), compute)

    def operator(self, connected: View, color_map) -> HeatOperator:
        color = color_map if isinstance(color_map, (str, type(None))) else id(color_map)
        return self.cached(
            ("op", id(connected), color),
            lambda: heat_operator(connected, None if color_map is None else color_rates(connected, color_map)),
        )

    def shifted(self, op: HeatOperator, sigma: float) -> HeatOperator:
        """``op`` factorized at shift ``sigma`` (:meth:`HeatOperator.shifted`), once per view."""
        return self.cached(("shifted", id(op), sigma), lambda: op.shifted(sigma))

    def spectrum(self, op: HeatOperator, modes: int) -> Spectrum:
        return self.cached(("spectrum", id(op), modes), lambda: eigen_spectrum(op, modes))

    def lambda2(self, op: HeatOperator) -> float:
        def compute():
            for key, value in self.cache.items():  # a spectrum already computed gives it for free
                if key[0] == "spectrum" and key[1] == id(op):
                    return value.lambda2
            return self.spectrum(op, self.modes).lambda2 if self.method == "eigen" else lambda2(op)

        return self.cached(("lambda2", id(op)), compute)

    def heat(self, op: HeatOperator, source: int, times: tuple, boundary: np.ndarray) -> np.ndarray:
        """(len(times), b) normalized boundary temperatures."""

        def compute():
            if self.method == "eigen":
                spectrum = self.spectrum(op, self.modes)
                return np.stack([spectrum.heat(np.array([source]), t, at=boundary)[0] for t in times])
            return krylov_heat(op, source, np.asarray(times), at=boundary)

        return self.cached(("heat", id(op), source, times), compute)

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
                    log.info("%s: the global derivative needs more than %d modes; trying %d", op.name, modes, 2 * modes)
                    modes = min(2 * modes, op.n - 2)

        return self.cached(("derivative", id(op), id(at), time), compute)
