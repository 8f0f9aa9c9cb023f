"""Compact libraries: one source per library view, chosen around the view circle (thesis 6.3).

The views of one object, in azimuth order, form the layers of the graph of Fig. 6.5: a
node per candidate source, an edge from each candidate of view i to each candidate of
view i+1 (the last view joins the first) costing the change of descriptor (eq. 6.6, or
g of eq. 6.11). A choice of one source per view is a closed walk once around.

The thesis solves this as the LP of eq. 6.7-6.9 relaxed to [0, 1]. Closed around the
circle, that LP is a circulation carrying one unit across a cut. Its vertices are
cycles that wind once around (integral) but also cycles that wind w > 1 times, taken
with weight 1/w. Those are fractional, and can cost less per turn than any single
winding. :func:`select_sources` therefore:

1. drops every edge that lies on no cheapest cycle. An edge's bound is the cheapest
   cycle through it: a start's distance to the edge's tail, the edge, and the distance
   from its head back around to that start, minimized over the starts of the first layer
   (min-plus products from every start, :mod:`heatdata.recognition._minplus_kernel`; starts whose
   cheapest open walk cannot beat a known cycle are left out). These distances are the
   dynamic program of :func:`cyclic_dp`: the optimum is known before the LP, which is
   solved on the edges of the optimal cycles and certifies it (reduced-cost fixing with
   the optimum as the bound). The earlier bound, the cheapest open walk through the edge,
   kept 550,000 of 2.5M edges on near-flat real costs, and the LP then took minutes
   (``benchmarks/bench_compact_lp.py``);
2. solves the relaxation on the edges kept by column generation (edges of negative
   reduced cost are added from the duals until none is left, which proves the LP
   optimal over all edges kept);
3. if the result is not integral, branches on the nodes of the smallest layer. Fixing
   one node makes the LP a shortest path (totally unimodular, so integral), and
   excluding the nodes already tried bounds the rest; a node whose cheapest cycle costs
   at least the best cycle found is excluded without an LP.
"""

from __future__ import annotations

import contextlib
import logging
import os
import sys
import tempfile
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.spatial.distance import cdist

from heatdata.core.distances import _check_finite, mhd_matrix
from heatdata.descriptors import stack_values
from heatdata.errors import HeatdataError

log = logging.getLogger(__name__)


SOLVER = "HIGHS"


FULL_POOL = 50_000  # when at most this many edges are kept, the first LP has them all


START_EDGES = 4  # else: each node's cheapest kept out-edges in the first edge set


ADD_EDGES = 4  # most negative reduced-cost edges added per node and round


INTEGRAL_TOL = 1e-6


CONSECUTIVE_DISTANCES = ("l1", "mhd")  # d of eq. 6.6


RHO_NORMS = ("l1", "l2")  # the norm of eq. 6.4 and 6.10


def _check(edge_costs: list, name: str) -> list[np.ndarray]:
    costs = [np.asarray(c, dtype=np.float64) for c in edge_costs]
    if len(costs) < 2:
        raise HeatdataError(f"{name}: selecting sources needs at least two views around the circle, got {len(costs)}")
    for i, c in enumerate(costs):
        following = costs[(i + 1) % len(costs)]
        if c.ndim != 2 or 0 in c.shape:
            raise HeatdataError(f"{name}: view {i}: edge costs must be a non-empty 2-D array, got shape {c.shape}")
        if c.shape[1] != following.shape[0]:
            raise HeatdataError(
                f"{name}: view {i}: edge costs of shape {c.shape} do not lead to the "
                f"{following.shape[0]} candidates of view {(i + 1) % len(costs)}"
            )
        if not np.all(np.isfinite(c)):
            raise HeatdataError(f"{name}: view {i}: edge costs must be finite")
    return costs


def _cycle_cost(costs: list[np.ndarray], choice: np.ndarray) -> float:
    """The summed edge cost of one node per layer, around the circle."""
    return float(sum(c[choice[i], choice[(i + 1) % len(costs)]] for i, c in enumerate(costs)))


@dataclass
class _Graph:
    """The layered cyclic graph, with layers rotated so that the smallest comes first."""

    costs: list[np.ndarray]
    offsets: np.ndarray = field(init=False)  # first node id of each layer
    kept: list[np.ndarray] = field(init=False)  # (n_i, n_i+1) bool: edges on a cycle costing at most upper
    upper: float = field(init=False)  # the cost of the cheapest cycle
    start_bound: np.ndarray = field(init=False)  # (n_0,) a lower bound of any cycle through each layer-0 node
    cycle: np.ndarray = field(init=False)  # (K,) the cheapest cycle's node per layer

    def __post_init__(self):
        from heatdata.recognition._minplus_kernel import minplus

        self.offsets = np.concatenate([[0], np.cumsum([c.shape[0] for c in self.costs])])
        # The cheapest open walk once around from each layer-0 node (one backward min-plus sweep) bounds every
        # cycle through it from below: starts that cannot beat the cycle through the best of them are left out.
        walk = np.zeros(self.costs[0].shape[0])
        for c in reversed(self.costs):
            walk = np.min(c + walk[None, :], axis=1)
        first = _cycle_cost(self.costs, self._cheapest_cycle_through(int(np.argmin(walk))))
        starts = np.flatnonzero(walk <= first + self._slack(first))
        # Distances from each start kept to every node: forward[i] is (starts, n_i); forward[K] closes the circle.
        forward: list[np.ndarray] = [np.empty(0), np.ascontiguousarray(self.costs[0][starts])]  # [0] unused
        for c in self.costs[1:]:
            forward.append(minplus(forward[-1], c))
        closed = forward[-1][np.arange(len(starts)), starts]  # the cheapest cycle through each start
        self.start_bound = walk.copy()
        self.start_bound[starts] = closed
        self.cycle = self._cheapest_cycle_through(int(starts[np.argmin(closed)]))
        self.upper = _cycle_cost(self.costs, self.cycle)
        slack = self._slack(self.upper)
        # An edge's bound is the cheapest cycle through it: a start's distance to its tail, the edge, and the
        # distance from its head back to that start (back: (live starts, n_i+1)), minimized over starts.
        live = np.flatnonzero(closed <= self.upper + slack)
        back = np.full((len(live), self.costs[0].shape[0]), np.inf)
        back[np.arange(len(live)), starts[live]] = 0.0
        self.kept = [np.empty(0, dtype=bool)] * self.layers
        for i in range(self.layers - 1, -1, -1):
            c = self.costs[i]
            if i == 0:
                bound = np.full(c.shape, np.inf)
                bound[starts[live]] = c[starts[live]] + back
            else:
                bound = c + minplus(np.ascontiguousarray(forward[i][live].T), back)
                back = minplus(back, np.ascontiguousarray(c.T))
            self.kept[i] = bound <= self.upper + slack

    @staticmethod
    def _slack(cost: float) -> float:
        return 1e-9 * max(1.0, abs(cost))

    def _cheapest_cycle_through(self, start: int) -> np.ndarray:
        """The cheapest closed walk through layer-0 node ``start`` (a shortest path, O(edges))."""
        best, parents = self.costs[0][start], []
        for c in self.costs[1:]:
            total = best[:, None] + c
            parents.append(np.argmin(total, axis=0))
            best = total[parents[-1], np.arange(c.shape[1])]
        node, path = start, [start]
        for parent in reversed(parents):
            node = int(parent[node])
            path.append(node)
        return np.array([start, *path[1:][::-1]], dtype=np.int64)

    @property
    def layers(self) -> int:
        return len(self.costs)

    def nodes(self, layer: int) -> int:
        return self.costs[layer].shape[0]


@contextlib.contextmanager
def _solver_output_to_log(name: str):
    """What the solver library prints from C to standard output (HiGHS's banner, once per process) goes to the
    log at DEBUG: a library must not write to a user's stdout. The redirect is of the process's file
    descriptor 1, for the duration of one solve."""
    sys.stdout.flush()
    saved = os.dup(1)
    with tempfile.TemporaryFile() as sink:
        os.dup2(sink.fileno(), 1)
        try:
            yield
        finally:
            sys.stdout.flush()
            os.dup2(saved, 1)
            os.close(saved)
            sink.seek(0)
            text = sink.read().decode(errors="replace").strip()
            if text:
                log.debug("%s: solver output: %s", name, text)


def _solve(graph: _Graph, pool: list[set], fixed: int | None, excluded: list[int], name: str):
    """Column generation for the circulation LP: (value, {layer: (tails, heads, x)}).

    The pool must hold a feasible cycle (see :func:`_add_cycle`); an infeasible LP is an error.
    """
    import cvxpy as cp

    if SOLVER not in cp.installed_solvers():
        raise HeatdataError(f"{name}: the LP solver {SOLVER} is not installed (cvxpy has {cp.installed_solvers()})")
    n_nodes = int(graph.offsets[-1])
    first = graph.nodes(0)
    while True:
        edges = [np.array(sorted(p), dtype=np.int64).reshape(-1, 2) for p in pool]
        sizes = [len(e) for e in edges]
        starts = np.concatenate([[0], np.cumsum(sizes)])
        tails = np.concatenate([graph.offsets[i] + e[:, 0] for i, e in enumerate(edges)])
        heads = np.concatenate([graph.offsets[(i + 1) % graph.layers] + e[:, 1] for i, e in enumerate(edges)])
        columns = np.arange(starts[-1])
        incidence = sp.csr_matrix(
            (
                np.concatenate([np.ones(len(columns)), -np.ones(len(columns))]),
                (np.concatenate([heads, tails]), np.concatenate([columns, columns])),
            ),
            shape=(n_nodes, len(columns)),
        )
        # rows of the layer-0 nodes' out-flows: the cut and the branching constraints
        out0 = sp.csr_matrix((np.ones(sizes[0]), (edges[0][:, 0], np.arange(sizes[0]))), shape=(first, len(columns)))
        cost = np.concatenate([graph.costs[i][e[:, 0], e[:, 1]] for i, e in enumerate(edges)])
        x = cp.Variable(len(columns), nonneg=True)
        conservation = incidence @ x == 0
        cut = cp.sum(out0 @ x) == 1
        node_flow = out0 @ x
        branch = []
        if fixed is not None:
            branch.append(node_flow[fixed] == 1)
        if excluded:
            branch.append(node_flow[np.asarray(excluded)] == 0)
        problem = cp.Problem(cp.Minimize(cost @ x), [conservation, cut, *branch])
        tic = time.perf_counter()
        try:
            with _solver_output_to_log(name):
                problem.solve(solver=SOLVER)
        except (cp.error.SolverError, ValueError) as exc:
            raise HeatdataError(f"{name}: the LP solver {SOLVER} failed on the source-selection LP: {exc}") from exc
        log.debug(
            "%s: LP with %d edges: %.2f s (%s; compile %.2f s, solver %.2f s)",
            name,
            len(columns),
            time.perf_counter() - tic,
            problem.status,
            problem.compilation_time or 0.0,
            problem.solver_stats.solve_time or 0.0,
        )
        if problem.status != cp.OPTIMAL:
            raise HeatdataError(f"{name}: the source-selection LP ended {problem.status}")
        potential = np.asarray(conservation.dual_value)
        layer0 = np.full(first, float(cut.dual_value))
        if fixed is not None:
            layer0[fixed] += float(branch[0].dual_value)
        if excluded:
            layer0[np.asarray(excluded)] += np.asarray(branch[-1].dual_value)
        added = 0
        values = np.asarray(x.value)
        for i, c in enumerate(graph.costs):
            tail = potential[graph.offsets[i] : graph.offsets[i + 1]]
            head = potential[graph.offsets[(i + 1) % graph.layers] : graph.offsets[(i + 1) % graph.layers + 1]]
            # reduced cost c + A^T y with cvxpy's sign of equality duals (the tests fail with the other sign)
            reduced = c + head[None, :] - tail[:, None] + (layer0[:, None] if i == 0 else 0.0)
            reduced[~graph.kept[i]] = np.inf
            scale = max(1.0, float(np.abs(c).max()))
            candidates = np.argwhere(reduced < -1e-9 * scale)
            if len(candidates):
                order = np.argsort(reduced[candidates[:, 0], candidates[:, 1]])
                new = [
                    tuple(e) for e in candidates[order[: ADD_EDGES * c.shape[0]]].tolist() if tuple(e) not in pool[i]
                ]
                pool[i].update(new)
                added += len(new)
        if not added:
            flows = {
                i: (edges[i][:, 0], edges[i][:, 1], values[starts[i] : starts[i + 1]]) for i in range(graph.layers)
            }
            return float(problem.value), flows


def _add_cycle(graph: _Graph, pool: list[set], node: int) -> None:
    """Add a greedy closed walk through layer-0 ``node`` to the edge pool, so that an LP that
    must use that node (or may use it, when others are excluded) is feasible."""
    path = [node]
    for i in range(graph.layers - 1):
        path.append(int(np.argmin(graph.costs[i][path[-1]])))
    path.append(node)
    for i in range(graph.layers):
        pool[i].add((path[i], path[i + 1]))


def _decode(graph: _Graph, flows: dict) -> np.ndarray | None:
    """One node per layer if the flow is integral (one edge at 1 per layer, chained), else None."""
    tails, heads = [], []
    for i in range(graph.layers):
        a, b, x = flows[i]
        if np.any((x > INTEGRAL_TOL) & (x < 1 - INTEGRAL_TOL)) or np.sum(x >= 1 - INTEGRAL_TOL) != 1:
            return None
        k = int(np.argmax(x))
        tails.append(a[k])
        heads.append(b[k])
    if any(heads[i] != tails[(i + 1) % graph.layers] for i in range(graph.layers)):
        return None
    return np.array(tails, dtype=np.int64)


def select_sources(edge_costs: list, *, name: str = "object") -> tuple[np.ndarray, float]:
    """One candidate source per view minimizing the summed edge cost around the circle (eq. 6.7-6.9, 6.12-6.14).

    Parameters
    ----------
    edge_costs : list of K arrays
        The i-th of shape (n_i, n_{(i+1) mod K}): the cost of candidate a in view i
        followed by candidate b in view i+1; the last array closes the circle. Costs may be
        negative: eq. 6.11's rewards ``-(1 - alpha)(rho_a + rho_b)`` are, and a constant added to
        every edge adds K times it to every cycle, so the choice does not change (a test checks it).
    name : str
        The object, for error messages.

    Returns
    -------
    choice : (K,) int64
        A candidate index per view.
    cost : float
        ``sum_i edge_costs[i][choice[i], choice[i+1]]``.

    Raises
    ------
    HeatdataError
        Fewer than two views, an empty or mis-shaped cost array, a non-finite cost, the
        LP solver not installed or the LP not solved.
    """
    costs = _check(edge_costs, name)
    shift = int(np.argmin([c.shape[0] for c in costs]))  # branch, if needed, on the smallest layer
    graph = _Graph(costs[shift:] + costs[:shift])
    kept = sum(int(k.sum()) for k in graph.kept)
    log.debug(
        "%s: %d of %d edges can be on a cycle costing at most %.6g",
        name,
        kept,
        sum(c.size for c in graph.costs),
        graph.upper,
    )
    pool = []
    for c, k in zip(graph.costs, graph.kept, strict=True):
        if kept <= FULL_POOL:
            pool.append({(int(a), int(b)) for a, b in np.argwhere(k)})
            continue
        cheapest = np.argsort(np.where(k, c, np.inf), axis=1)[:, :START_EDGES]
        pool.append({(a, int(b)) for a in range(c.shape[0]) for b in cheapest[a] if k[a, b]})
    for i in range(graph.layers):  # the known cycle keeps the first LP feasible
        pool[i].add((int(graph.cycle[i]), int(graph.cycle[(i + 1) % graph.layers])))
    value, flows = _solve(graph, pool, None, [], name)
    choice = _decode(graph, flows)
    if choice is None:
        log.info(
            "%s: the relaxed LP is fractional (%.6g); branching on the %d candidates of view %d",
            name,
            value,
            graph.nodes(0),
            shift,
        )
        best, choice = graph.upper, graph.cycle
        excluded: list[int] = []
        while True:
            # a start whose cheapest cycle costs at least the best cycle found cannot beat it
            tol = 1e-9 * max(1.0, abs(best))
            hopeless = [int(s) for s in np.flatnonzero(graph.start_bound >= best - tol) if s not in excluded]
            if excluded or hopeless:  # else the relaxation solved above still holds
                excluded += hopeless
                remaining = np.setdiff1d(np.arange(graph.nodes(0)), excluded)
                if len(remaining) == 0:
                    break
                _add_cycle(graph, pool, int(remaining[0]))
                value, flows = _solve(graph, pool, None, excluded, name)
            if value >= best - tol:
                break
            integral = _decode(graph, flows)
            if integral is not None:
                best, choice = value, integral
                break
            node_flow = np.bincount(flows[0][0], weights=flows[0][2], minlength=graph.nodes(0))
            node_flow[excluded] = -1.0
            node = int(np.argmax(node_flow))
            _add_cycle(graph, pool, node)
            fixed_value, fixed_flows = _solve(graph, pool, node, excluded, name)
            path = _decode(graph, fixed_flows)
            if path is None:
                raise HeatdataError(f"{name}: the LP with view {shift}'s candidate {node} fixed is not integral")
            if fixed_value < best:
                best, choice = fixed_value, path
            excluded.append(node)
    choice = np.roll(choice, shift).astype(np.int64)
    return choice, _cycle_cost(costs, choice)


def cyclic_dp(edge_costs: list) -> tuple[np.ndarray, float]:
    """The same optimum by dynamic programming (a min-plus product per view), for checking :func:`select_sources`."""
    costs = _check(edge_costs, "dp")
    n0 = costs[0].shape[0]
    best = costs[0]  # (n0, n1): cheapest walk from each start to each node of the current layer
    parents = []
    for c in costs[1:]:
        total = best[:, :, None] + c[None, :, :]
        parents.append(np.argmin(total, axis=1))
        best = np.min(total, axis=1)
    start = int(np.argmin(best[np.arange(n0), np.arange(n0)]))
    walk = [start]  # walk back from the closing node (= start)
    node = start
    for parent in reversed(parents):
        node = int(parent[start, node])
        walk.append(node)
    return np.array([start, *walk[1:][::-1]], dtype=np.int64), float(best[start, start])


def _stacked_views(views: list, name: str) -> list[np.ndarray]:
    """One object's candidate descriptors per view, each as a finite (n_i, M) array of one M."""
    views = [stack_values(values, f"{name} view {i}") for i, values in enumerate(views)]
    if not views:
        raise HeatdataError(f"{name}: no library views")
    lengths = sorted({v.shape[1] for v in views})
    if len(lengths) > 1:
        raise HeatdataError(f"{name}: views have descriptors of different lengths {lengths}")
    for i, values in enumerate(views):
        _check_finite(values, f"{name} view {i}")
    return views


def consecutive_costs(views: list[np.ndarray], distance: str = "l1") -> list[np.ndarray]:
    """c of eq. 6.6: the distance d from each candidate of view i to each of view i+1 (the last to the first).

    ``"l1"`` (the default) is the distance rho takes (:func:`other_object_distances`), so
    that alpha in eq. 6.11 mixes terms of one unit; for the near matches of neighbouring
    views it is close to the MHD (which it bounds from above), at a fraction of the cost.
    ``"mhd"`` is the descriptor distance of the thesis (eq. 3.1), some hundred times dearer
    (``benchmarks/bench_compact_lp.py``).

    Parameters
    ----------
    views : list of K (n_i, M) arrays, or of K lists of Descriptor
        Candidate descriptors of one object's library views, in azimuth order (one
        :func:`heatdata.descriptors.sources.candidate_descriptors` list per view will do).
    distance : {"l1", "mhd"}

    Returns
    -------
    list of K (n_i, n_{i+1}) float64
    """
    if distance not in CONSECUTIVE_DISTANCES:
        raise HeatdataError(f"unknown distance {distance!r} for c of eq. 6.6 (use one of {CONSECUTIVE_DISTANCES})")
    views = _stacked_views(views, "library")
    pairs = [(views[i], views[(i + 1) % len(views)]) for i in range(len(views))]
    if distance == "mhd":
        return [mhd_matrix(a, b) for a, b in pairs]
    return [cdist(a, b, "cityblock") for a, b in pairs]


def other_object_distances(
    candidates: dict[str, list[np.ndarray]], *, norm: str = "l1", block: int = 1024
) -> dict[str, list[np.ndarray]]:
    """rho of Alg. 6.3 (eq. 6.3-6.4): each candidate's distance to the nearest candidate of another object.

    Eq. 6.3-6.4 and 6.10 write a norm, ``min_z ||z_v - z||``. heatdata's default is the L1
    norm, ``sum_i |z_i - z'_i|`` (an upper bound of the MHD of eq. 3.1, in its units), the
    default for c too; ``"l2"`` is the Euclidean norm.
    The exact MHD over an extended library (40 views x 250 candidates per object) takes tens of
    minutes per chair, and a shortlist by L1 misses the MHD's nearest for ~30% of the
    candidates (``benchmarks/bench_nearest_mhd.py``; its numbers in ``benchmarks/README.md``).

    Parameters
    ----------
    candidates : dict from object to a list of (n_i, M) arrays (or of lists of Descriptor)
        The extended library: every candidate descriptor of every library view.
    norm : {"l1", "l2"}
    block : int
        Candidates per batch (the work array is block x the other objects' candidates).

    Returns
    -------
    dict from object to a list of (n_i,) float64, matching ``candidates``
    """
    if norm not in RHO_NORMS:
        raise HeatdataError(f"unknown norm {norm!r} for rho of eq. 6.4 (use one of {RHO_NORMS})")
    if len(candidates) < 2:
        raise HeatdataError(f"distances to other objects need two or more objects, got {list(candidates)}")
    candidates = {obj: _stacked_views(views, obj) for obj, views in candidates.items()}
    lengths = {obj: views[0].shape[1] for obj, views in candidates.items()}
    if len(set(lengths.values())) > 1:
        raise HeatdataError(f"objects have descriptors of different lengths {lengths}: describe them with one spec")
    stacked = {obj: np.vstack(views) for obj, views in candidates.items()}
    rho = {}
    for obj, views in candidates.items():
        others = np.vstack([d for other, d in stacked.items() if other != obj])
        metric = "cityblock" if norm == "l1" else "euclidean"
        nearest = np.concatenate(
            [cdist(stacked[obj][k : k + block], others, metric).min(axis=1) for k in range(0, len(stacked[obj]), block)]
        )
        rho[obj] = np.split(nearest, np.cumsum([len(v) for v in views])[:-1])
    return rho


def combined_costs(consecutive: list[np.ndarray], rho: list[np.ndarray], alpha: float) -> list[np.ndarray]:
    """g = alpha c + (1 - alpha) w of eq. 6.11, with w of eq. 6.10: ``w_ab = -rho_a - rho_b`` (Alg. 6.3).

    Parameters
    ----------
    consecutive : list of K (n_i, n_{i+1}) arrays
        c, from :func:`consecutive_costs`.
    rho : list of K (n_i,) arrays
        The object's entries of :func:`other_object_distances`.
    alpha : float in [0, 1]
        1: penalize local variability only (Alg. 6.2); 0: reward distance to other objects only.

    Returns
    -------
    list of K (n_i, n_{i+1}) float64
        The edge costs of eq. 6.11 for :func:`select_sources`.
    """
    if not 0.0 <= alpha <= 1.0:
        raise HeatdataError(f"the mixing parameter alpha must be in [0, 1], got {alpha}")
    k = len(consecutive)
    return [
        alpha * c - (1.0 - alpha) * (rho[i][:, None] + rho[(i + 1) % k][None, :]) for i, c in enumerate(consecutive)
    ]
