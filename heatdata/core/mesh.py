"""Mesh functions shared by views and models: consistent winding, boundary loops, surface distances.

Both a rendered view (a surface with a boundary, thesis 2.3.3) and a scanned or cut
model (JASNOM's inputs, thesis 7.3) are triangle lists; the topology functions see only
the faces.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse import csgraph
from scipy.spatial import cKDTree


def mesh_edges(faces: np.ndarray, n: int) -> np.ndarray:
    """(e, 2) int64: the unique undirected edges ``i < j`` of triangles over ``n`` vertices, sorted."""
    f = np.asarray(faces)
    a = np.concatenate([f[:, 0], f[:, 1], f[:, 2]])
    b = np.concatenate([f[:, 1], f[:, 2], f[:, 0]])
    adjacency = sp.csr_matrix((np.ones(len(a), np.int8), (np.minimum(a, b), np.maximum(a, b))), shape=(n, n))
    adjacency.sum_duplicates()
    rows = np.repeat(np.arange(n), np.diff(adjacency.indptr))
    return np.column_stack([rows, adjacency.indices]).astype(np.int64)


def component_labels(edges: np.ndarray, n: int) -> np.ndarray:
    """(n,) int: the connected-component index of each of ``n`` vertices joined by ``edges`` (e, 2)."""
    graph = sp.csr_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    return csgraph.connected_components(graph, directed=False)[1]


def merged_vertices(vertices: np.ndarray, tolerance: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertices closer than ``tolerance`` merged into one (the lowest index of each chain of such pairs).

    Parameters
    ----------
    vertices : (n, 3) float
    tolerance : float
        Vertices at most this far apart are merged (scipy's ``cKDTree.query_pairs``), and
        so are chains of such pairs (their connected components).

    Returns
    -------
    index : (n,) int64
        The new index of each vertex; the kept vertices are ``vertices[first]`` in their
        original order.
    first : (k,) int64
        The kept vertex of each merged group, ascending.
    """
    n = len(vertices)
    pairs = cKDTree(vertices).query_pairs(tolerance, output_type="ndarray")
    labels = component_labels(pairs.reshape(-1, 2), n)
    first = np.full(labels.max() + 1 if n else 0, n, np.int64)
    np.minimum.at(first, labels, np.arange(n))
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return rank[labels].astype(np.int64), first[order]


def consistent_winding(faces: np.ndarray) -> tuple[np.ndarray, int]:
    """Faces wound consistently with their neighbours, and how many were reversed.

    Two faces sharing an edge agree when they traverse it in opposite directions. A
    breadth-first pass over each connected patch of faces sets every face's winding from
    its parent's; per patch, the winding most of the given faces had is kept.
    """
    m = len(faces)
    half = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    owner = np.tile(np.arange(m), 3)
    key = np.minimum(half[:, 0], half[:, 1]) * (int(faces.max()) + 1) + np.maximum(half[:, 0], half[:, 1])
    order = np.argsort(key, kind="stable")
    key, owner, forward = key[order], owner[order], (half[:, 0] < half[:, 1])[order]
    pair = np.flatnonzero(
        (key[:-1] == key[1:]) & ((np.r_[True, key[1:-1] != key[:-2]]) & (np.r_[key[2:] != key[1:-1], True]))
    )  # edges of exactly 2 faces
    a, b = owner[pair], owner[pair + 1]
    parity = (forward[pair] == forward[pair + 1]).astype(np.int8)  # same direction: one of the two is reversed
    if not parity.any():  # consistent already (every rendered view)
        return faces, 0
    graph = sp.coo_matrix((parity + 1, (a, b)), shape=(m, m)).tocsr()
    graph = graph + graph.T
    flip = np.zeros(m, dtype=bool)
    seen = np.zeros(m, dtype=bool)
    for root in range(m):
        if seen[root]:
            continue
        patch, parent = csgraph.breadth_first_order(graph, root, directed=False, return_predecessors=True)
        children = patch[1:]
        # a face alone in its patch has no children, and indexing the graph with no pairs gives no array
        reverse = (np.asarray(graph[parent[children], children]).ravel() == 2).tolist() if len(children) else []
        state = flip.tolist()
        for node, up, rev in zip(children.tolist(), parent[children].tolist(), reverse, strict=True):
            state[node] = state[up] ^ rev  # BFS order: a parent is set before its children
        flip = np.array(state)
        seen[patch] = True
        if flip[patch].sum() * 2 > len(patch):  # keep the majority's winding
            flip[patch] = ~flip[patch]
    if not flip.any():
        return faces, 0
    faces = faces.copy()
    faces[flip] = faces[flip][:, ::-1]
    return faces, int(flip.sum())


def boundary_loops(faces: np.ndarray, planar: np.ndarray | None = None) -> list[np.ndarray]:
    """Closed loops of directed boundary half-edges (those without a twin), in the faces' winding.

    Parameters
    ----------
    faces : (m, 3) int
        Triangles, consistently wound (:func:`consistent_winding`).
    planar : (n, 2) float, optional
        2D positions of the vertices (a view's image plane): at a pinch vertex, where
        several boundary loops touch, the loop takes the sharpest left turn. Without them
        it takes the last outgoing half-edge found.

    Returns
    -------
    list of (b,) int64
        Vertex indices of each loop, in the direction of its half-edges (a closed surface
        has none).
    """
    half = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    n = int(faces.max()) + 1
    directed = sp.csr_matrix((np.ones(len(half), np.int32), (half[:, 0], half[:, 1])), shape=(n, n))
    unmatched = (directed - directed.T).tocoo()  # +1 where a half-edge has no twin
    keep = unmatched.data > 0
    boundary = np.column_stack([unmatched.row[keep], unmatched.col[keep]])
    if len(boundary) == 0:
        return []
    # outgoing boundary half-edges per vertex (several at pinch vertices)
    outgoing: dict[int, list[int]] = {}
    for a, b in boundary.tolist():
        outgoing.setdefault(a, []).append(b)
    loops = []
    for first in list(outgoing):
        while outgoing.get(first):
            loop, a = [first], first
            b = outgoing[a].pop()
            while b != first:
                loop.append(b)
                candidates = outgoing.get(b)
                if not candidates:
                    break
                if len(candidates) > 1 and planar is not None:  # pinch vertex: take the sharpest left turn
                    incoming = planar[b] - planar[a]
                    turns = [_turn(incoming, planar[c] - planar[b]) for c in candidates]
                    a, b = b, candidates.pop(int(np.argmax(turns)))
                else:
                    a, b = b, candidates.pop()
            loops.append(np.array(loop, np.int64))
    return loops


def _turn(incoming: np.ndarray, outgoing: np.ndarray) -> float:
    return float(np.arctan2(incoming[0] * outgoing[1] - incoming[1] * outgoing[0], incoming @ outgoing))


def surface_samples(vertices: np.ndarray, faces: np.ndarray, count: int, seed: int = 0) -> np.ndarray:
    """(count, 3) points drawn uniformly by area over a triangle mesh (seeded)."""
    corners = vertices[faces]
    area = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    if not area.sum() > 0:
        raise ValueError("the mesh has no area to sample")
    rng = np.random.default_rng(seed)
    face = rng.choice(len(faces), size=count, p=area / area.sum())
    u, v = rng.random(count), rng.random(count)
    flip = u + v > 1.0
    u, v = np.where(flip, 1.0 - u, u), np.where(flip, 1.0 - v, v)
    a, b, c = corners[face, 0], corners[face, 1], corners[face, 2]
    return a + u[:, None] * (b - a) + v[:, None] * (c - a)


def surface_distances(
    first: tuple[np.ndarray, np.ndarray], second: tuple[np.ndarray, np.ndarray], *, samples: int = 20000, seed: int = 0
) -> tuple[np.ndarray, np.ndarray]:
    """Distances from surface samples of each mesh to the other's surface.

    Parameters
    ----------
    first, second : (vertices (n, 3), faces (m, 3))
    samples : int
        Points drawn uniformly by area on each mesh.

    Returns
    -------
    (samples,), (samples,) float64
        From ``first``'s samples to ``second``'s surface, and back. The maximum of both
        is the symmetric Hausdorff distance; the first's mean says how far a
        reconstruction lies from the truth, whatever the truth has that it lacks.
    """
    import open3d as o3d

    def to_surface(points: np.ndarray, mesh: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
        scene = o3d.t.geometry.RaycastingScene()
        scene.add_triangles(
            o3d.core.Tensor(np.asarray(mesh[0], np.float32)), o3d.core.Tensor(np.asarray(mesh[1], np.uint32))
        )
        return scene.compute_distance(o3d.core.Tensor(points.astype(np.float32))).numpy().astype(np.float64)

    return (
        to_surface(surface_samples(*first, samples, seed), second),
        to_surface(surface_samples(*second, samples, seed + 1), first),
    )


def farthest_points(points: np.ndarray, chosen: list[int], count: int) -> list[int]:
    """Extend ``chosen`` (indices into ``points``; empty: start at the point nearest the centroid) to ``count``
    indices by farthest-point sampling, or to every point if there are fewer."""
    if not chosen:
        chosen = [int(np.argmin(np.linalg.norm(points - points.mean(axis=0), axis=1)))]
    nearest = np.min(np.linalg.norm(points[:, None, :] - points[chosen][None, :, :], axis=2), axis=1)
    while len(chosen) < min(count, len(points)):
        far = int(np.argmax(nearest))
        chosen.append(far)
        nearest = np.minimum(nearest, np.linalg.norm(points - points[far], axis=1))
    return chosen
