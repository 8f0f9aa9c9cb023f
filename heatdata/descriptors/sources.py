"""Candidate heat sources of a view (thesis 6.2): vertices that represent its shape.

The single-source rules of eq. 2.7-2.8 are fragile (6.1): a small change of view angle
can move the source far. Chapter 6 instead describes a view from many candidate
sources, found by simplifying the view's mesh (the thesis: library views simplified to
250 vertices) and taking the view vertices nearest to the simplified ones.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence

import numpy as np
from scipy.spatial import cKDTree

from heatdata.core.mesh import farthest_points
from heatdata.descriptors import Descriptor, DescriptorSpec
from heatdata.errors import ViewError
from heatdata.views.view import View

log = logging.getLogger(__name__)

MAX_PASSES = 8  # quadric decimation passes; an open view needs 2-3 to reach its target


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
        meshes.meshing_decimation_quadric_edge_collapse(
            targetfacenum=target, preserveboundary=False, preservetopology=False, boundaryweight=0.1, planarquadric=True
        )
        remaining = meshes.current_mesh().vertex_number()
        if remaining <= count:
            break
        target = max(4, int(target * count / remaining) - 1)
    return np.array(meshes.current_mesh().vertex_matrix(), dtype=np.float64)  # a copy: the MeshSet owns it


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
        raise ViewError(
            f"{view.name}: {count} candidate sources asked, but the view has only {len(interior)} "
            "vertices off its outer boundary"
        )
    points = view.vertices[interior]
    _, nearest = cKDTree(points).query(_decimated_vertices(view, count))
    chosen = list(dict.fromkeys(int(i) for i in np.atleast_1d(nearest)))  # distinct, in order
    if len(chosen) < count:
        log.info(
            "%s: %d of %d simplified vertices are distinct view vertices; %d more by farthest-point sampling",
            view.name,
            len(chosen),
            count,
            count - len(chosen),
        )
        chosen = farthest_points(points, chosen, count)
    if len(chosen) > count:  # the decimation stopped above its target after MAX_PASSES
        log.info("%s: simplification kept %d vertices; the first %d are used", view.name, len(chosen), count)
    return np.sort(interior[chosen[:count]]).astype(np.int64)


def candidate_descriptors(
    view: View, sources: np.ndarray, spec: DescriptorSpec, *, times: Sequence[float] | None = None, modes: int = 32
) -> list[Descriptor]:
    """One descriptor per source of a view (6.2.1), computed the way the spec's kind shares work.

    Heat kinds (PVHK, C-PVHK, FT-PVHK) come from one eigen-decomposition per connected
    component, ``Phi_B diag(exp(-lambda t)) Phi_S^T`` times ``sum(c)`` (eq. 2.9/2.11 with
    the heat kernel's symmetry), with eigenpairs doubled until the first mode left out
    weighs less than 1e-7 at the earliest time. A PVST's crossing times need early
    times, where a truncated expansion is not accurate: its sources share the
    factorizations and lambda_2, and each gets its own heat models (``benchmarks/README.md``
    times them). Kinds without a source (the histogram baselines) are an error.

    Parameters
    ----------
    view : View
    sources : (s,) int
        Source vertices (e.g. :func:`candidate_sources`).
    spec : DescriptorSpec
        A kind with ``multi_source``; the spec's own source rule is not used.
    times : float or sequence of float
        The fixed times of a time-scaled kind (``ft-pvhk``; one descriptor per source and time).
    modes : int
        Eigenpairs to start with.

    Returns
    -------
    list of Descriptor
        Source-major: for each source in the order given, one per time. No part weights.
    """
    sources = np.asarray(sources, dtype=np.int64)
    if sources.ndim != 1 or len(sources) == 0 or sources.min() < 0 or sources.max() >= view.n_vertices:
        raise ViewError(f"{view.name}: sources must be a non-empty list of vertex indices in 0..{view.n_vertices - 1}")
    return spec.impl.candidates(view, sources, spec, times=times, modes=modes)
