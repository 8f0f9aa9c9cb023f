"""Heat-geodesic distribution (HGD): how far heat must travel on the surface against the straight line.

Not in the thesis; built for its complex objects (ch. 5), where the PVHK's one curve
along the outline loses what tells chairs apart (the chairs' ablation, docs/chapters/complex.md). The
shape-distribution idea is Osada et al.'s D2, which the ESF (3.6.1) refines with its
in/out/mixed lines; here heat decides what the ESF decides with voxels:

0. a view of more than ``vertices`` vertices (the budget, :data:`VERTEX_BUDGET` by default) is seen through
   pixels ``s`` times wider (:func:`heatdata.views.resolution.coarse_view`): the heat method's cost is bounded
   whatever the view's resolution, and a close query is described at about its library views' resolution (the
   share of straight paths grows with it where the sensor's noise is finer than a pixel; a spec saved before the
   budget, as in an older library file, reads as ``vertices=0``, every vertex);
1. ``sources`` vertices are spread over the view by farthest-point sampling, starting
   from its ``"interior"`` source (the vertex farthest from the outer boundary);
2. from each, heat diffuses for a short time and the heat method turns it into
   geodesic distances over the surface (Crane, Weischedel & Wardetzky 2013, "Geodesics
   in heat": one heat step (M + tL) u = delta as in eq. 2.5-2.6, the normalized
   gradient, one Poisson solve; geometry-central's solver through ``potpourri3d``);
3. each (source, vertex) pair, weighted by the vertex's area, falls into a bin of the
   Euclidean distance (``bins`` log-spaced bins from ``near`` to ``far`` metres: a
   depth sensor measures metres, so a stool and an armchair differ by size too) times
   a bin of Euclidean / geodesic distance (:data:`RATIO_EDGES`): near 1 where the
   surface runs straight between the two, small where heat must go round a gap
   between slats or legs, 0 on another connected component (``views.components: all``).

The HGD sees no colour. With ``color: hue-saturation`` it also holds the view's colours:
an area-weighted histogram of :data:`HUES` hues x two saturations, plus one bin for the
greys (saturation below :data:`GREY`, whose hue means nothing), weighted ``color_weight``
against the shape's 1, so that one chi-square distance adds both (colour twins, 3.4).

The histogram (``4 * bins`` values, plus ``2 * HUES + 1`` with colour) is normalized to
sum 1 and compared by the chi-square distance. It is seeded by nothing: the same view
always gives the same HGD.
"""

from __future__ import annotations

import numpy as np

from heatdata.core.mesh import farthest_points
from heatdata.descriptors.base import (
    DescriptorSpec,
    Option,
    integer,
    number,
    one_of,
    register,
)
from heatdata.descriptors.boundary import source_vertex
from heatdata.descriptors.histograms import HistogramKind
from heatdata.errors import SpecError, ViewError
from heatdata.views.resolution import coarse_view

#: bins of Euclidean / geodesic distance: another component or far round, round a gap, bent, straight
RATIO_EDGES = np.array([0.0, 0.5, 0.8, 0.95, 1.0])
HUES = 12  # hue bins of the colour part
GREY = 0.15  # saturation below which a colour is a grey
COLOR_PARTS = ("none", "hue-saturation")
#: the vertices a view is described with at most (:func:`heatdata.views.resolution.coarse_view`): the heat method's
#: cost grows with them, and the share of straight paths with the resolution (docs/guide/speed.md measures both)
VERTEX_BUDGET = 2000


def vertex_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(n,) a third of the area of each vertex's triangles."""
    area = 0.5 * np.linalg.norm(
        np.cross(vertices[faces[:, 1]] - vertices[faces[:, 0]], vertices[faces[:, 2]] - vertices[faces[:, 0]]), axis=1
    )
    return np.bincount(faces.ravel(), np.repeat(area / 3.0, 3), len(vertices))


def geodesic_distances(view, sources: np.ndarray) -> np.ndarray:
    """(len(sources), n) heat-method geodesic distances; inf to the vertices of another component."""
    import potpourri3d as pp3d

    labels = view.component_labels
    out = np.full((len(sources), view.n_vertices), np.inf)
    for component in np.unique(labels[sources]):
        keep = labels == component
        index = np.cumsum(keep) - 1  # old vertex -> its index in the component
        faces = index[view.faces[keep[view.faces].all(axis=1)]]
        solver = pp3d.MeshHeatMethodDistanceSolver(np.asarray(view.vertices[keep], np.float64), faces)
        for row in np.flatnonzero(labels[sources] == component):
            out[row, keep] = solver.compute_distance(int(index[sources[row]]))
    return out


def hgd_histogram(view, *, sources: int = 16, bins: int = 32, near: float = 0.004, far: float = 2.5) -> np.ndarray:
    """The ``(4 * bins,)`` HGD of a view (see the module docstring), summing to 1.

    Parameters
    ----------
    view : View
        A partial view, connected or not; coordinates in metres.
    sources : int
        Source vertices (farthest-point sampling).
    bins : int
        Log-spaced bins of Euclidean distance.
    near, far : float
        The first bin's lower edge and the last bin's upper edge, metres; nearer and
        farther pairs count in the first and last bin.
    """
    x = np.asarray(view.vertices, np.float64)
    area = vertex_areas(x, view.faces)
    if not area.sum() > 0:
        raise ViewError(f"{view.name}: the view has no area; no HGD")
    start = source_vertex(view, "interior")
    chosen = np.array(farthest_points(x, [start], sources))
    geodesic = geodesic_distances(view, chosen)
    euclid = np.linalg.norm(x[None, :, :] - x[chosen][:, None, :], axis=2)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(geodesic > 0, euclid / geodesic, 1.0)  # the source itself: straight
    ratio = np.clip(np.nan_to_num(ratio, nan=0.0), 0.0, 1.0)
    edges = np.geomspace(near, far, bins + 1)
    counts = np.histogram2d(
        np.clip(euclid, near, far).ravel(),
        ratio.ravel(),
        (edges, RATIO_EDGES),
        weights=np.broadcast_to(area, euclid.shape).ravel(),
    )[0]
    return (counts / counts.sum()).ravel()


def color_histogram(colors: np.ndarray, area: np.ndarray) -> np.ndarray:
    """(2 * HUES + 1,) area-weighted: greys, then hue x (saturation below 0.5, from 0.5), summing to 1."""
    from matplotlib.colors import rgb_to_hsv

    hsv = rgb_to_hsv(np.clip(colors, 0.0, 1.0))
    hue = np.minimum((hsv[:, 0] * HUES).astype(np.int64), HUES - 1)
    index = np.where(hsv[:, 1] < GREY, 0, 1 + hue + HUES * (hsv[:, 1] >= 0.5))
    counts = np.bincount(index, area, 2 * HUES + 1)
    return counts / counts.sum()


class HGD(HistogramKind):
    name = "hgd"
    summary = "Heat-geodesic distribution: Euclidean distance x Euclidean/heat-method geodesic ratio"
    options = (
        Option("sources", 16, "source vertices, spread by farthest-point sampling", integer(1, 1024)),
        Option("bins", 32, "log-spaced bins of Euclidean distance", integer(2, 1024)),
        Option("near", 0.004, "lower edge of the first distance bin, metres", number(0.0, 100.0)),
        Option("far", 2.5, "upper edge of the last distance bin, metres", number(0.0, 100.0)),
        Option("color", "none", "hue-saturation: append the view's colour histogram", one_of(COLOR_PARTS)),
        Option("color_weight", 1.0, "the colour part's weight against the shape's 1", number(0.0, 100.0)),
        Option(
            "vertices",
            VERTEX_BUDGET,
            "the vertex budget: a view with more is seen coarser (0: every vertex)",
            integer(0, 10**7),
            before=0,
        ),
    )

    def validate(self, options: dict) -> dict:
        if options["near"] >= options["far"]:
            raise SpecError(f"hgd: near ({options['near']:g} m) must be below far ({options['far']:g} m)")
        return options

    def unavailable(self) -> str | None:
        try:
            import potpourri3d  # noqa: F401
        except ImportError:
            return "potpourri3d is not installed (pip install -r requirements.txt)"
        return None

    def size(self, spec: DescriptorSpec, view) -> int:
        return spec.bins * (len(RATIO_EDGES) - 1) + (2 * HUES + 1) * (spec.color != "none")

    def compute(self, work, spec: DescriptorSpec, **context):
        self.check_points(work.view)
        view = coarse_view(work.view, spec.vertices)
        values = hgd_histogram(view, sources=spec.sources, bins=spec.bins, near=spec.near, far=spec.far)
        if spec.color != "none":
            area = vertex_areas(np.asarray(view.vertices, np.float64), view.faces)
            values = np.concatenate([values, spec.color_weight * color_histogram(view.colors, area)])
        return [self.histogram(spec, values, view)]


register(HGD())
