"""Candidate heat sources of a view (thesis 6.2): vertices that represent its shape.

The single-source rules of eq. 2.7-2.8 are fragile (6.1): a small change of view angle
can move the source far. Chapter 6 instead describes a view from many candidate
sources, found by simplifying the view's mesh (the thesis: library views simplified to
250 vertices) and taking the view vertices nearest to the simplified ones.
"""

from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np
from scipy.spatial import cKDTree

from .descriptors import Descriptor, DescriptorSpec, color_rates, describe, heat_operator, sample_boundary
from .errors import ViewError
from .spectrum import eigen_spectrum
from .view import View

log = logging.getLogger(__name__)

MAX_PASSES = 8  # quadric decimation passes; an open view needs 2-3 to reach its target
TRUNCATION = 1e-7  # exp(-lambda_k t) of the first mode left out of the multi-source expansion


def _decimated_vertices(view: View, count: int) -> np.ndarray:
    """(<= count, 3) vertices of the view's mesh after quadric edge-collapse decimation (pymeshlab)."""
    import pymeshlab

    meshes = pymeshlab.MeshSet()
    meshes.add_mesh(pymeshlab.Mesh(vertex_matrix=view.vertices, face_matrix=view.faces.astype(np.int32)))
    target = 2 * count  # a closed mesh has ~2 faces per vertex; an open one keeps more vertices on its outline
    for _ in range(MAX_PASSES):
        # The outline must be free to collapse (or decimation stalls at its vertex count) and cheap to
        # collapse, and flat regions need the planar quadric: with the defaults a flat disc keeps only
        # its outline, and on the beer mug the farthest vertex from a candidate is 1.5x farther.
        meshes.meshing_decimation_quadric_edge_collapse(targetfacenum=target, preserveboundary=False,
                                                        preservetopology=False, boundaryweight=0.1,
                                                        planarquadric=True)
        remaining = meshes.current_mesh().vertex_number()
        if remaining <= count:
            break
        target = max(4, int(target * count / remaining) - 1)
    return np.array(meshes.current_mesh().vertex_matrix(), dtype=np.float64)  # a copy: the MeshSet owns it


def _farthest_points(points: np.ndarray, chosen: list[int], count: int) -> list[int]:
    """Extend ``chosen`` (indices into ``points``) to ``count`` by farthest-point sampling."""
    if not chosen:
        chosen = [int(np.argmin(np.linalg.norm(points - points.mean(axis=0), axis=1)))]
    nearest = np.min(np.linalg.norm(points[:, None, :] - points[chosen][None, :, :], axis=2), axis=1)
    while len(chosen) < count:
        far = int(np.argmax(nearest))
        chosen.append(far)
        nearest = np.minimum(nearest, np.linalg.norm(points - points[far], axis=1))
    return chosen


def candidate_sources(view: View, count: int | None = 250) -> np.ndarray:
    """``count`` candidate source vertices spread over the view's shape (6.2).

    The view's mesh is simplified to at most ``count`` vertices by quadric edge
    collapse (pymeshlab); each simplified vertex is replaced by the nearest view vertex
    off the outer boundary (a source there would make the PVST undefined, Lemma 1), and
    if several land on the same vertex the set is topped up to ``count`` by
    farthest-point sampling, which is logged.

    Parameters
    ----------
    view : View
    count : int or None
        Candidates wanted; None: every vertex off the outer boundary (the thesis's test
        views use all vertices).

    Returns
    -------
    (count,) int64
        Distinct vertex indices into ``view``, sorted.

    Raises
    ------
    ViewError
        ``count`` is not positive, or the view has fewer vertices off its outer boundary.
    """
    interior = np.setdiff1d(np.arange(view.n_vertices), view.boundary)
    if count is None:
        return interior.astype(np.int64)
    if count < 1:
        raise ViewError(f"{view.name}: ask for at least one candidate source, not {count}")
    if len(interior) < count:
        raise ViewError(f"{view.name}: {count} candidate sources asked, but the view has only {len(interior)} "
                        "vertices off its outer boundary")
    points = view.vertices[interior]
    _, nearest = cKDTree(points).query(_decimated_vertices(view, count))
    chosen = list(dict.fromkeys(int(i) for i in np.atleast_1d(nearest)))  # distinct, in order
    if len(chosen) < count:
        log.info("%s: %d of %d simplified vertices are distinct view vertices; %d more by farthest-point sampling",
                 view.name, len(chosen), count, count - len(chosen))
        chosen = _farthest_points(points, chosen, count)
    if len(chosen) > count:  # the decimation stopped above its target after MAX_PASSES
        log.info("%s: simplification kept %d vertices; the first %d are used", view.name, len(chosen), count)
    return np.sort(interior[chosen[:count]]).astype(np.int64)


def candidate_descriptors(view: View, sources: np.ndarray, spec: DescriptorSpec, *, times=None,
                          modes: int = 32) -> list[Descriptor]:
    """One descriptor per source, all from one eigen-decomposition per connected component (6.2.1).

    The normalized temperatures at the boundary for every source at once are
    ``Phi_B diag(exp(-lambda t)) Phi_S^T`` times ``sum(c)`` (eq. 2.9/2.11 with the heat
    kernel's symmetry); the eigenpairs are doubled until the first mode left out weighs
    less than 1e-7 at the earliest time.

    A PVST's crossing times need early times, where a truncated expansion is not
    accurate: its sources share one factorization and lambda_2, and each gets its own
    heat model (:func:`heatdata.describe`): 250 took 15.7 s on a 4,263-vertex chair view.

    Parameters
    ----------
    view : View
    sources : (s,) int
        Source vertices (e.g. :func:`candidate_sources`).
    spec : DescriptorSpec
        Any kind; the spec's own source rule is not used.
    times : float or sequence of float
        The fixed times of an ``ft-pvhk`` (one descriptor per source and time).
    modes : int
        Eigenpairs to start with.

    Returns
    -------
    list of Descriptor
        Source-major: for each source in the order given, one per time. No part weights.
    """
    if spec.kind == "ft-pvhk" and times is None:
        raise ViewError(f"{view.name}: the ft-pvhk {spec.name} needs times= (the object's time scale, Alg. 5.1)")
    sources = np.asarray(sources, dtype=np.int64)
    if sources.ndim != 1 or len(sources) == 0 or sources.min() < 0 or sources.max() >= view.n_vertices:
        raise ViewError(f"{view.name}: sources must be a non-empty list of vertex indices in 0..{view.n_vertices - 1}")
    if spec.kind == "pvst":  # one describe call: the sources share the factorization and lambda_2
        return describe(view, [replace(spec, source=int(s)) for s in sources])
    labels = view.component_labels[sources]
    out: dict[int, list[Descriptor]] = {}
    for label in np.unique(labels):
        group = np.flatnonzero(labels == label)
        connected = view.component_of(int(sources[group[0]]))[0]
        local = np.cumsum(view.component_labels == label) - 1  # view vertex -> component vertex
        on_boundary = np.isin(local[sources[group]], connected.boundary)
        if on_boundary.any():
            log.info("%s: %d of %d sources are on the outer boundary", view.name, int(on_boundary.sum()), len(group))
        op = heat_operator(connected, None if spec.color_map is None else color_rates(connected, spec.color_map))
        spectrum = eigen_spectrum(op, modes)
        while True:
            spec_times = (1.0 / spectrum.lambda2,) if spec.kind != "ft-pvhk" else \
                tuple(float(t) for t in np.atleast_1d(times))
            if spectrum.truncation(min(spec_times)) <= TRUNCATION or len(spectrum.values) >= op.n - 2:
                break
            spectrum = eigen_spectrum(op, 2 * len(spectrum.values))
        lam2 = spectrum.lambda2
        repairs = tuple(connected.repairs[len(view.repairs):])
        per_time = []
        for t in spec_times:
            heat = spectrum.heat(local[sources[group]], t, at=connected.boundary)  # (s, b)
            values, positions = sample_boundary(connected, connected.boundary, heat, spec.samples, spec.sampling)
            per_time.append(values)
        for row, g in enumerate(group):
            out[int(g)] = [Descriptor(kind=spec.kind, values=v[row], positions=positions, source=int(sources[g]),
                                      time=t, lambda2=lam2, sampling=spec.sampling, color_map=spec.color_map,
                                      repairs=repairs) for t, v in zip(spec_times, per_time, strict=True)]
    return [d for g in range(len(sources)) for d in out[g]]
