"""A view at a coarser resolution: the vertex budget that bounds what describing a view costs.

A descriptor that solves on the whole surface (the HGD's heat method) costs in proportion to the view's vertices,
and a view has as many vertices as the sensor has pixels on the object: 2,000 for a mug at 1.5 m, 75,000 at 0.3 m.
:func:`coarse_view` sees the same surface as a sensor ``s`` times coarser a side would (``s`` the least whole
stride that brings the view within the budget), so the cost is bounded whatever the view's resolution, and a
library view and a query are described at the same resolution whatever their distances.
"""

from __future__ import annotations

import math

import numpy as np

from heatdata.views.depth import MAX_DEPTH_JUMP, grid_faces
from heatdata.views.view import View


def coarse_view(view: View, vertices: int) -> View:
    """``view`` as seen through pixels ``s`` times wider, when it has more than ``vertices`` vertices.

    Each ``s x s`` block of the view's pixels keeps the vertex nearest its centre, where the coarser pixel's ray
    meets the surface (of two there, the nearer the camera, as a sensor's z-buffer keeps). The kept vertices are
    joined as a depth frame's pixels are (:func:`heatdata.views.depth.grid_faces`, the depth step allowed ``s``
    times a pixel's), and a vertex left in no triangle is dropped. They keep their positions and colours: nothing
    is interpolated.

    Parameters
    ----------
    view : View
        Any view (its vertices in front of the camera).
    vertices : int
        The budget; 0 keeps every vertex.

    Returns
    -------
    View
        ``view`` itself within the budget; else the coarser view, with about ``n / s**2`` vertices (at most about
        ``vertices``; a thin part may keep a few more), its repairs noting the stride; ``view`` itself when the
        coarser pixels would form no triangle, or when its vertices project far beyond its image.
    """
    n = view.n_vertices
    if vertices <= 0 or n <= vertices:
        return view
    stride = math.ceil(math.sqrt(n / vertices))
    pixel = np.round(view.pixels).astype(np.int64)
    cell = pixel // stride
    off_centre = np.square(pixel - (cell * stride + (stride - 1) // 2)).sum(axis=1)  # whole, below 2 stride**2
    cell -= cell.min(axis=0)
    width, height = int(cell[:, 0].max()) + 1, int(cell[:, 1].max()) + 1
    k = view.intrinsics
    if width * height > 4 * (k["width"] // stride + 2) * (k["height"] // stride + 2):
        return view  # its vertices project far beyond its image (not a sensor's view): no grid of blocks to keep
    key = cell[:, 1] * width + cell[:, 0]
    z = view.vertices[:, 2]
    # by block, then nearest its centre, then nearest the camera: one sort of one float key (exact below 2**52)
    order = np.argsort((key * (2 * stride**2 + 1) + off_centre) + z / (2.0 * z.max()))
    first = order[np.r_[True, key[order][1:] != key[order][:-1]]]
    index = np.full((height, width), -1, np.int64)
    index[cell[first, 1], cell[first, 0]] = np.arange(len(first))
    faces = grid_faces(index, view.vertices[first, 2], MAX_DEPTH_JUMP * stride)
    if len(faces) == 0:  # a view thinner than a block everywhere: nothing coarser to see
        return view
    used = np.unique(faces)
    renumber = np.full(len(first), -1, np.int64)
    renumber[used] = np.arange(len(used))
    kept = first[used]
    return View.from_arrays(
        view.vertices[kept],
        renumber[faces],
        view.colors[kept],
        intrinsics=view.intrinsics,
        view_id=view.view_id,
        object_id=view.object_id,
        label=view.label,
        azimuth=view.azimuth,
        elevation=view.elevation,
        distance=view.distance,
        pose=view.pose,
        repairs=[*view.repairs, f"seen {stride} times coarser a side: {len(kept)} of {n} vertices"],
    )
