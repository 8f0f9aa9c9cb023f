"""The spectral core: Laplace-Beltrami operator, its spectrum, and heat diffusion (thesis 2.2, 2.4).

Heat diffuses by ``C^{-1} L T = -dT/dt`` (eq. 2.1, 2.10), with ``L = D - W`` and
``W_ij = 1/||x_i - x_j||^2`` on mesh edges (eq. 2.2-2.3) and ``C = diag(c)`` the colour
rates (``c = 1`` for plain PVHK). With the unit pulse ``T(0) = e_s`` of eq. 2.5 the
total heat ``sum_i c_i T_i`` is conserved and the equilibrium is ``c_s / sum(c)``;
heatdata reports temperatures divided by that equilibrium, so equilibrium = 1.

Everything is computed in the symmetric form ``S = C^{-1/2} L C^{-1/2}`` whose null
vector ``e ~ sqrt(c)`` is known exactly, from one sparse Cholesky factorization
(CHOLMOD, simplicial, AMD ordering) of ``L + sigma C``. Two ways use it:

* :class:`Spectrum` - the smallest eigenpairs by shift-invert Lanczos (ARPACK), the
  form of eq. 2.6/2.9/2.11. One spectrum serves any number of sources and times, so
  many descriptors per view cost one eigen-solve.
* :func:`krylov_heat` - ``exp(-t S) v`` for one source by shift-invert Krylov
  projection (the "restricted rational" Krylov method), with ``lambda_2`` from a short
  Lanczos run on the same factorization. It needs no truncation of the eigen-expansion
  and is the fastest route to a single PVHK (see ``benchmarks/``).

Both are checked against ``scipy.sparse.linalg.expm_multiply`` in the tests.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla
from sksparse.cholmod import CholmodError, Factor, cholesky

from heatdata.errors import SpectrumError

log = logging.getLogger(__name__)

SHIFT = 1e-6  # sigma relative to the mean diagonal of L: keeps L + sigma C positive definite


def laplacian(vertices: np.ndarray, edges: np.ndarray, name: str = "mesh") -> sp.csc_matrix:
    """Laplace-Beltrami operator ``L = D - W`` of eq. 2.2-2.3.

    Parameters
    ----------
    vertices : (n, 3) float64
    edges : (e, 2) int
        Unique undirected edges.

    Returns
    -------
    (n, n) scipy.sparse.csc_matrix
        Symmetric, rows sum to zero.

    Raises
    ------
    SpectrumError
        An edge has zero length (duplicate vertices).
    """
    x = np.asarray(vertices, dtype=np.float64)  # rendered points may be float32: weights need float64
    i, j = edges[:, 0], edges[:, 1]
    length2 = np.sum((x[i] - x[j]) ** 2, axis=1)
    if np.any(length2 <= 0.0):
        raise SpectrumError(f"{name}: {int(np.sum(length2 <= 0))} zero-length edges (duplicate vertices)")
    w = 1.0 / length2
    n = len(x)
    diagonal = np.arange(n)
    degree = np.bincount(i, w, n) + np.bincount(j, w, n)
    rows = np.concatenate([i, j, diagonal])
    cols = np.concatenate([j, i, diagonal])
    return sp.csc_matrix((np.concatenate([-w, -w, degree]), (rows, cols)), shape=(n, n))


class HeatOperator:
    """``L``, the rates ``c`` and one Cholesky factorization of ``L + sigma C``.

    Parameters
    ----------
    L : (n, n) sparse
        Laplace-Beltrami operator.
    rates : (n,) float64, optional
        Diagonal of ``C`` (eq. 2.10); all ones when omitted.
    name : str
        For error messages.
    sigma : float, optional
        The shift; default a tiny one (``SHIFT`` times the mean diagonal of ``L`` over
        that of ``C``), which suits times around 1/lambda_2 and later.
    analysis : sksparse.cholmod.Factor, optional
        A factorization of a matrix of the same pattern, whose ordering and symbolic
        analysis are reused (see :meth:`shifted`).
    """

    def __init__(
        self,
        L: sp.spmatrix,
        rates: np.ndarray | None = None,
        name: str = "mesh",
        *,
        sigma: float | None = None,
        analysis: Factor | None = None,
    ):
        self.name = name
        self.L = sp.csc_matrix(L)
        n = self.L.shape[0]
        self.c = np.ones(n) if rates is None else np.asarray(rates, dtype=np.float64)
        if self.c.shape != (n,) or not np.all(np.isfinite(self.c)) or np.any(self.c <= 0):
            raise SpectrumError(f"{name}: colour rates must be {n} positive finite numbers")
        self.sqrt_c = np.sqrt(self.c)
        self.null = self.sqrt_c / np.linalg.norm(self.sqrt_c)  # null vector of S
        self.sigma = SHIFT * float(self.L.diagonal().mean() / self.c.mean()) if sigma is None else float(sigma)
        shifted = self.L.copy()
        column = np.repeat(np.arange(n), np.diff(shifted.indptr))
        on_diagonal = shifted.indices == column
        shifted.data[on_diagonal] += self.sigma * self.c[shifted.indices[on_diagonal]]
        try:
            self.factor = (
                cholesky(shifted, mode="simplicial", ordering_method="amd")
                if analysis is None
                else analysis.cholesky(shifted)
            )
        except CholmodError as exc:
            raise SpectrumError(f"{name}: L + sigma C is not positive definite ({exc})") from exc

    @property
    def n(self) -> int:
        return self.L.shape[0]

    def shifted(self, sigma: float) -> HeatOperator:
        """The same operator factorized at shift ``sigma``: ``sigma ~ 1/t`` suits early times t,

        where the Krylov space of the default (tiny) shift converges slowly. The pattern is the same, so the
        fill-reducing ordering and symbolic analysis of this factorization are reused.

        Parameters
        ----------
        sigma : float
            The new shift, > 0.

        Returns
        -------
        HeatOperator
            The same L, C and rates, factorized at ``sigma``.
        """
        return HeatOperator(self.L, self.c, self.name, sigma=sigma, analysis=self.factor)

    def apply_inverse(self, y: np.ndarray) -> np.ndarray:
        """``(S + sigma I)^{-1} y`` restricted to the complement of the null vector.

        Parameters
        ----------
        y : (n,) float
            A vector in symmetric coordinates.

        Returns
        -------
        (n,) float64
        """
        out = self.sqrt_c * self.factor.solve_A(self.sqrt_c * y)
        return out - self.null * (self.null @ out)

    def apply_S(self, y: np.ndarray) -> np.ndarray:
        """``S y = C^{-1/2} L C^{-1/2} y`` for (n,) or (n, k) ``y``.

        Parameters
        ----------
        y : (n,) or (n, k) float
            Vectors in symmetric coordinates.

        Returns
        -------
        (n,) or (n, k) float64
        """
        scale = self.sqrt_c if y.ndim == 1 else self.sqrt_c[:, None]
        return (self.L @ (y / scale)) / scale

    def pulse(self, source: int) -> np.ndarray:
        """``C^{1/2} e_s``: the unit pulse of eq. 2.5 in symmetric coordinates.

        Parameters
        ----------
        source : int
            The vertex.

        Returns
        -------
        (n,) float64
        """
        v = np.zeros(self.n)
        v[source] = self.sqrt_c[source]
        return v


def _lanczos(
    op: HeatOperator, start: np.ndarray, max_steps: int, converged, check_every: int = 1
) -> tuple[np.ndarray, np.ndarray, str]:
    """Orthonormal basis ``Q`` (rows) of the shift-invert Krylov space and ``H = Q S Q^T``.

    ``converged(Q, H)`` is asked every ``check_every`` steps from the fourth on; full
    re-orthogonalization (two Gram-Schmidt passes) keeps ``Q`` orthonormal. The status
    is ``"converged"``, ``"invariant"`` (the space is invariant: projections are exact)
    or ``"max_steps"``.
    """
    n = op.n
    steps = min(max_steps, n - 1)
    Q = np.empty((steps + 1, n))  # rows are basis vectors (contiguous slices)
    SQ = np.empty((steps + 1, n))
    H = np.zeros((steps + 1, steps + 1))
    start = start - op.null * (op.null @ start)
    norm = np.linalg.norm(start)
    if norm == 0:
        raise SpectrumError(f"{op.name}: Krylov start vector lies in the null space")
    Q[0] = start / norm
    SQ[0] = op.apply_S(Q[0])
    H[0, 0] = Q[0] @ SQ[0]
    m = 1
    while m <= steps:
        if m == n - 1:  # Q spans the whole complement of the null vector
            return Q[:m], H[:m, :m], "invariant"
        w = op.apply_inverse(Q[m - 1])
        before = np.linalg.norm(w)
        for _ in range(2):
            w -= (Q[:m] @ w) @ Q[:m]
        norm = np.linalg.norm(w)
        if norm <= 1e-10 * before:
            return Q[:m], H[:m, :m], "invariant"
        Q[m] = w / norm
        SQ[m] = op.apply_S(Q[m])
        H[m, : m + 1] = H[: m + 1, m] = Q[: m + 1] @ SQ[m]
        m += 1
        if m >= 4 and m % check_every == 0 and converged(Q[:m], H[:m, :m]):
            return Q[:m], H[:m, :m], "converged"
    return Q[:m], H[:m, :m], "max_steps"


def lambda2(op: HeatOperator, *, rtol: float = 1e-8, max_steps: int = 60, seed: int = 0) -> float:
    """First non-zero eigenvalue of ``L phi = lambda C phi`` (sets t_s = 1/lambda_2, 2.3.1).

    Lanczos on ``(S + sigma I)^{-1}`` from a seeded random start, deflated of the null
    vector, until the smallest Ritz value changes by less than ``rtol``.

    Parameters
    ----------
    op : HeatOperator
        The operator (L, C) of one connected component.
    rtol : float
        Relative change of the smallest Ritz value that stops the iteration.
    max_steps : int
        Lanczos steps at most.
    seed : int
        Seed of the random start.

    Returns
    -------
    float
        lambda_2 > 0.
    """
    if op.n < 3:
        raise SpectrumError(f"{op.name}: too few vertices for a spectrum")
    history: list[float] = []

    def done(Q, H):
        history.append(float(np.linalg.eigvalsh(H)[0]))
        return len(history) > 1 and abs(history[-1] - history[-2]) <= rtol * abs(history[-1])

    start = np.random.default_rng(seed).standard_normal(op.n)
    _Q, H, status = _lanczos(op, start, max_steps, done)
    if status == "max_steps":
        raise SpectrumError(f"{op.name}: lambda_2 did not converge to {rtol:g} in {max_steps} Lanczos steps")
    value = float(np.linalg.eigvalsh(H)[0])
    if not value > 0:
        raise SpectrumError(f"{op.name}: lambda_2 = {value} is not positive (is the mesh connected?)")
    return value


@dataclass
class HeatModel:
    """Temperatures at chosen vertices as an explicit sum of exponentials in time.

    The Krylov projection of :func:`heat_model` gives, for each reported vertex ``j``,
    ``T_j(t) = scale_j (steady_j + sum_m G_mj exp(-theta_m t))``: cheap to evaluate at
    any number of times, and what :func:`first_crossings` brackets and refines.

    Attributes
    ----------
    theta : (m,) float64
        Ritz values (approximate eigenvalues of ``S``); ``theta[0]`` approaches lambda_2.
    weights : (m, b) float64
        ``G`` above.
    steady : (b,) float64
    scale : (b,) float64
        Converts to temperatures divided by the equilibrium temperature.
    """

    theta: np.ndarray
    weights: np.ndarray
    steady: np.ndarray
    scale: np.ndarray

    def __call__(self, times: np.ndarray) -> np.ndarray:
        """(k,) times -> (k, b) normalized temperatures."""
        decay = np.exp(-np.outer(np.atleast_1d(times), self.theta))
        return (self.steady + decay @ self.weights) * self.scale


def heat_model(
    op: HeatOperator,
    source: int,
    times: np.ndarray,
    at: np.ndarray | None = None,
    *,
    tol: float = 1e-7,
    max_steps: int = 120,
    check_every: int = 1,
) -> HeatModel:
    """Project ``exp(-t S)`` onto the shift-invert Krylov space of a unit pulse at ``source``.

    Vectors are added until the normalized temperatures at ``at`` and at every time of
    ``times`` change by less than ``tol`` between steps; the model is then accurate at
    those times (and between them, the approximation being smooth in ``t``).

    Parameters
    ----------
    op : HeatOperator
    source : int
    times : (k,) float
        Positive diffusion times at which convergence is checked.
    at : (b,) int, optional
        Vertices to report (default: all).
    tol : float
        Stopping tolerance on the normalized temperatures.
    max_steps : int
    check_every : int
        Steps between convergence checks (each costs a small eigenproblem and the
        temperatures at ``times``): more than 1 pays when many steps are expected.

    Returns
    -------
    HeatModel
        Temperatures at ``at`` as a function of time, from the Krylov space.
    """
    times = np.atleast_1d(np.asarray(times, dtype=np.float64))
    if np.any(times <= 0) or not np.all(np.isfinite(times)):
        raise SpectrumError(f"{op.name}: diffusion times must be positive and finite, got {times}")
    at = np.arange(op.n) if at is None else np.asarray(at)
    v = op.pulse(source)
    steady = op.null * (op.null @ v)
    r = v - steady
    beta = np.linalg.norm(r)
    equilibrium = op.c[source] / op.c.sum()
    scale = 1.0 / (op.sqrt_c[at] * equilibrium)

    def project(Q, H) -> HeatModel:
        theta, U = np.linalg.eigh(H)
        return HeatModel(theta, beta * (U[0][:, None] * (U.T @ Q[:, at])), steady[at], scale)

    previous: list[np.ndarray] = []

    def done(Q, H):
        previous.append(project(Q, H)(times))
        return len(previous) > 1 and np.max(np.abs(previous[-1] - previous[-2])) <= tol

    Q, H, status = _lanczos(op, r, max_steps, done, check_every)
    if status == "max_steps":
        raise SpectrumError(
            f"{op.name}: heat did not converge to {tol:g} in {max_steps} Krylov steps "
            f"(times {times.min():.3g}..{times.max():.3g})"
        )
    return project(Q, H)


def krylov_heat(
    op: HeatOperator,
    source: int,
    times: np.ndarray,
    at: np.ndarray | None = None,
    *,
    tol: float = 1e-7,
    max_steps: int = 120,
) -> np.ndarray:
    """Normalized temperatures ``T(t)`` after a unit pulse at ``source``.

    Parameters as :func:`heat_model`.

    Returns
    -------
    (k, b) float64
        Temperatures divided by the equilibrium temperature.

    Parameters
    ----------
    op : HeatOperator
        The view's operator.
    source : int
        The vertex the unit pulse starts at.
    times : (k,) float
        Diffusion times, > 0.
    at : (b,) int, optional
        The vertices reported (default all).
    tol : float
        Relative accuracy of the Krylov approximation.
    max_steps : int
        Lanczos steps at most.
    """
    return heat_model(op, source, times, at, tol=tol, max_steps=max_steps)(np.asarray(times, dtype=np.float64))


def first_crossings(
    model: HeatModel, threshold: float, t_start: float, t_end: float, *, grid: int = 256, rtol: float = 1e-9
) -> np.ndarray:
    """First time each reported temperature reaches ``threshold`` (Alg. 5.3, ch. 5.4.2).

    The model is evaluated on ``grid`` log-spaced times in ``[t_start, t_end]`` (the
    thesis's search on a logarithmic scale); the first grid interval where a
    temperature reaches the threshold brackets its first crossing, which bisection in
    ``log t`` then refines to ``rtol`` relative. A temperature that rises above the
    threshold and falls back within one grid step (a factor ``(t_end/t_start)^(1/grid)``)
    is not seen.

    Returns
    -------
    (b,) float64
        Crossing times; NaN where the threshold is not reached by ``t_end``, or is
        already reached at ``t_start`` (no crossing from below in the window).

    Parameters
    ----------
    model : HeatModel
        Temperatures at the reported vertices as a function of time (:func:`heat_model`).
    threshold : float
        T_a, a fraction of the equilibrium temperature.
    t_start, t_end : float
        The window searched, 0 < t_start < t_end.
    grid : int
        Log-spaced times that bracket the crossings.
    rtol : float
        Relative accuracy of the bisection in log t.
    """
    times = np.geomspace(t_start, t_end, grid)
    above = model(times) >= threshold  # (grid, b)
    first = np.argmax(above, axis=0)
    found = above.any(axis=0) & (first > 0)
    columns = np.flatnonzero(found)
    lo = np.log(times[first[columns] - 1])
    hi = np.log(times[first[columns]])
    sub = HeatModel(model.theta, model.weights[:, columns], model.steady[columns], model.scale[columns])
    steps = int(np.ceil(np.log2(max(np.log(times[1] / times[0]) / rtol, 2.0))))
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        t = np.exp(mid)
        decay = np.exp(-t[:, None] * sub.theta[None, :])  # (c, m)
        value = (sub.steady + np.einsum("cm,mc->c", decay, sub.weights)) * sub.scale
        reached = value >= threshold
        hi = np.where(reached, mid, hi)
        lo = np.where(reached, lo, mid)
    out = np.full(model.steady.shape, np.nan)
    out[columns] = np.exp(hi)
    return out


@dataclass
class Spectrum:
    """Smallest eigenpairs of ``L phi = lambda C phi`` (eq. 2.6, 2.9, 2.11).

    Attributes
    ----------
    values : (k,) float64
        Eigenvalues, ascending; ``values[0] = 0``.
    vectors : (n, k) float64
        Eigenvectors, C-orthonormal (``vectors.T @ diag(c) @ vectors = I``).
    rates : (n,) float64
        Diagonal of ``C``.
    """

    values: np.ndarray
    vectors: np.ndarray
    rates: np.ndarray

    @property
    def lambda2(self) -> float:
        return float(self.values[1])

    def truncation(self, time: float) -> float:
        """``exp(-lambda_k t)``: the weight of the first mode left out at ``time``.

        Parameters
        ----------
        time : float
            A diffusion time.

        Returns
        -------
        float
            In (0, 1]: small means the kept modes suffice at ``time``.
        """
        return float(np.exp(-self.values[-1] * time))

    def heat(self, sources: np.ndarray, time: float, at: np.ndarray | None = None) -> np.ndarray:
        """Normalized temperatures for several sources at one time (eq. 2.9/2.11).

        Returns
        -------
        (len(sources), b) float64
            ``Phi_at diag(exp(-lambda t)) Phi_S^T C_S`` divided by the equilibrium.

        Parameters
        ----------
        sources : (s,) int
            Source vertices.
        time : float
            The diffusion time.
        at : (b,) int, optional
            The vertices reported (default all).
        """
        sources = np.atleast_1d(sources)
        rows = slice(None) if at is None else at
        phi_at = self.vectors[rows] * np.exp(-self.values * time)
        kernel = self.vectors[sources] @ phi_at.T  # (s, b)
        return kernel * self.rates.sum()

    def global_derivative(self, time: float, at: np.ndarray | None = None) -> np.ndarray:
        """Source-position global derivative of eq. 5.10-5.12 (thesis 5.3.1).

        ``Delta_s[T_s(t)]_i = sum_{k >= 2} lambda_k [phi_k]_i^2 exp(-2 lambda_k t) / 2``: how much
        the temperature at vertex ``i`` changes when the source moves along an edge, summed
        over all sources - one pass over the eigenpairs, no loop over sources. Temperatures
        are normalized (equilibrium = 1), which scales eq. 5.12 by ``sum(c)^2``.

        Returns
        -------
        (b,) float64
            At the vertices ``at`` (default all).

        Parameters
        ----------
        time : float
            The diffusion time (t_global = 1/lambda_2 in the thesis).
        at : (b,) int, optional
            The vertices reported (default all).

        Raises
        ------
        SpectrumError
            The modes left out could change the result by more than 1e-6 relative (the
            largest kept mode's term ``lambda_k exp(-2 lambda_k t)`` is not negligible);
            compute more modes.
        """
        rows = slice(None) if at is None else at
        decay = self.values[1:] * np.exp(-2.0 * self.values[1:] * time)
        if decay[-1] > 1e-6 * decay.max():
            raise SpectrumError(
                f"the global derivative at t = {time:.3g} needs more than {len(self.values)} "
                f"modes (the last kept mode still weighs {decay[-1] / decay.max():.1e})"
            )
        phi = self.vectors[rows, 1:]
        return 0.5 * (phi**2 @ decay) * self.rates.sum() ** 2


def eigen_spectrum(op: HeatOperator, k: int = 30, *, tol: float = 1e-10) -> Spectrum:
    """The ``k`` smallest eigenpairs by ARPACK shift-invert with the CHOLMOD factor.

    Parameters
    ----------
    op : HeatOperator
        The operator (L, C) of the view.
    k : int
        Eigenpairs, the first (lambda_1 = 0) included.
    tol : float
        ARPACK's relative tolerance.

    Returns
    -------
    Spectrum
        ``values`` (k,) ascending, ``vectors`` (n, k) C-orthonormal, and the rates.
    """
    n = op.n
    k = min(k, n - 2)
    if k < 2:
        raise SpectrumError(f"{op.name}: too few vertices ({n}) for a spectrum")
    opinv = sla.LinearOperator((n, n), matvec=lambda b: op.factor(np.asarray(b).ravel()), dtype=np.float64)
    try:
        values, vectors = sla.eigsh(
            op.L,
            k=k,
            M=sp.diags(op.c).tocsc(),
            sigma=-op.sigma,
            OPinv=opinv,
            which="LM",
            tol=tol,
            v0=np.random.default_rng(0).standard_normal(n),
        )
    except sla.ArpackNoConvergence as exc:
        raise SpectrumError(f"{op.name}: ARPACK did not converge for {k} eigenpairs") from exc
    order = np.argsort(values)
    values, vectors = values[order], vectors[:, order]
    values[0] = 0.0  # the constant mode, exact by construction
    vectors[:, 0] = 1.0 / np.sqrt(op.c.sum())
    return Spectrum(values=values, vectors=vectors, rates=op.c)
