"""Surfaces of an organized grid split where objects meet: at depth steps and at concave creases (the step that
separates objects that touch, stand on each other or occlude each other)."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
from scipy import ndimage

CUT_BAND = 1  # pixels around a crease or a step also taken out, so that a crease with gaps still cuts
GROW_STEPS = 8  # pixels the labels grow over what the nearest core left (the cut's band and the creases' reach)
NEAR_PIXELS = 3  # pixels apart, at most, two pieces are looked at for joining where there is no support plane
CORE_PIXELS = 50  # a piece of surface between cuts smaller than this is no object's core (a speck of noise)
STEP_BAND = 2  # pixels beside a depth step kept with the surface they border
NORMAL_REACH = 2  # pixels either side a normal's differences span
NORMAL_WINDOW = 5  # pixels: the window a normal is averaged over (a Kinect's depth steps are quantized)
CREASE_REACH = 3  # pixels either side of a pixel whose normals and positions tell a crease


def _shift(array: np.ndarray, dv: int, du: int, fill=np.nan) -> np.ndarray:
    """``array`` moved so that pixel (v, u) holds the value at (v + dv, u + du); ``fill`` beyond the edge."""
    out = np.full_like(array, fill)
    h, w = array.shape[:2]
    src_v = slice(max(dv, 0), h + min(dv, 0))
    src_u = slice(max(du, 0), w + min(du, 0))
    dst_v = slice(max(-dv, 0), h + min(-dv, 0))
    dst_u = slice(max(-du, 0), w + min(-du, 0))
    out[dst_v, dst_u] = array[src_v, src_u]
    return out


def continuous(z: np.ndarray, z_other: np.ndarray, max_jump: float, steps: int = 1) -> np.ndarray:
    """Whether two depths ``steps`` pixels apart lie on one surface (relative step below ``max_jump`` a pixel)."""
    with np.errstate(invalid="ignore"):
        return np.abs(z - z_other) <= max_jump * steps * 0.5 * (z + z_other)


def grid_normals(
    points: np.ndarray, max_jump: float, reach: int = NORMAL_REACH, smooth: int = NORMAL_WINDOW
) -> np.ndarray:
    """(h, w, 3) unit normals of an organized grid, towards the camera, NaN where unknown.

    Central differences ``reach`` pixels either side (where the surface is continuous), averaged over a
    ``smooth`` x ``smooth`` window of the pixels that have one.
    """
    z = points[..., 2]
    tangents = []
    for dv, du in ((0, reach), (reach, 0)):
        ahead, behind = _shift(points, dv, du), _shift(points, -dv, -du)
        ok = continuous(ahead[..., 2], z, max_jump, reach) & continuous(behind[..., 2], z, max_jump, reach)
        tangents.append(np.where(ok[..., None], ahead - behind, np.nan))
    normals = np.cross(tangents[0], tangents[1])
    known = np.isfinite(normals).all(axis=2)
    normals[~known] = 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        normals /= np.linalg.norm(normals, axis=2, keepdims=True)
    normals[~known] = 0.0
    summed = np.stack([ndimage.uniform_filter(normals[..., i], smooth, mode="constant") for i in range(3)], axis=2)
    with np.errstate(invalid="ignore", divide="ignore"):
        summed /= np.linalg.norm(summed, axis=2, keepdims=True)
    summed[~known] = np.nan
    facing = np.einsum("ijk,ijk->ij", summed, points) > 0
    summed[facing] *= -1.0
    return summed


def creases(
    points: np.ndarray,
    normals: np.ndarray,
    region: np.ndarray,
    max_jump: float,
    angle: float,
    reach: int = CREASE_REACH,
) -> np.ndarray:
    """(h, w) bool: pixels on a concave crease sharper than ``angle`` degrees (LCCP's convexity criterion, Stein
    et al. 2014: two surface points are concave when their normals turn towards each other,
    ``(n_a - n_b) . (p_a - p_b) < 0``), tested between pixels ``reach`` apart on either side of each pixel."""
    limit = 2.0 * np.sin(np.radians(angle) / 2.0)
    found = np.zeros(region.shape, bool)
    for dv, du in ((0, reach), (reach, 0), (reach, reach), (reach, -reach)):
        pa, pb = _shift(points, dv, du), _shift(points, -dv, -du)
        na, nb = _shift(normals, dv, du), _shift(normals, -dv, -du)
        ok = continuous(pa[..., 2], pb[..., 2], max_jump, 2 * reach)
        d = pa - pb
        with np.errstate(invalid="ignore", divide="ignore"):
            d /= np.linalg.norm(d, axis=2, keepdims=True)
            concave = np.einsum("ijk,ijk->ij", na - nb, d) < -limit
        found |= ok & concave
    return found & region


def steps(points: np.ndarray, region: np.ndarray, max_jump: float) -> np.ndarray:
    """(h, w) bool: region pixels beside a depth step (a neighbour in the region off their surface)."""
    z = np.where(region, points[..., 2], np.nan)
    found = np.zeros(region.shape, bool)
    for dv, du in ((0, 1), (1, 0), (0, -1), (-1, 0)):
        other = _shift(z, dv, du)
        with np.errstate(invalid="ignore"):
            found |= np.isfinite(other) & ~continuous(z, other, max_jump)
    return found & region


def reaching(points: np.ndarray, candidates: np.ndarray, inside: np.ndarray, max_jump: float) -> np.ndarray:
    """(h, w) bool: the ``candidates`` pixels on a surface (connected without a depth step) that has a pixel
    ``inside``, and the pixels beside its steps (the step's own pixels, on either side of it)."""
    pieces, _ = ndimage.label(candidates & ~steps(points, candidates, max_jump))
    keep = np.zeros(pieces.max() + 1, bool)
    keep[pieces[inside]] = True
    keep[0] = False
    kept = keep[pieces]
    _, (rows, cols) = ndimage.distance_transform_edt(~kept, return_indices=True)
    near = ndimage.binary_dilation(kept, iterations=STEP_BAND)
    return candidates & (kept | (near & kept[rows, cols]))


def split_surfaces(
    points: np.ndarray, region: np.ndarray, seeds: np.ndarray, settings, *, concave: bool = True
) -> np.ndarray:
    """(h, w) int: the ``region``'s pixels labelled by object (0: none), split where objects meet.

    Like LCCP (Stein et al., CVPR 2014), which cuts a scene's surface where two patches meet at a concave
    angle, but on the frame's pixel grid rather than supervoxels: the pixels on a concave crease sharper than
    ``settings.concavity`` degrees (:func:`creases`) or beside a depth step (:func:`steps`), and a band of
    :data:`CUT_BAND` pixels around them, are taken out; the rest's connected pieces of at least
    :data:`CORE_PIXELS` are the objects' cores, each holding a pixel of ``seeds`` (the workspace, not only an
    object's foot); then every pixel of the region joins its nearest core when it lies within
    ``settings.cluster_distance`` of that core's nearest pixel.

    Parameters
    ----------
    points : (h, w, 3) float64
        Camera-frame points, NaN where there is no reading.
    region : (h, w) bool
        The pixels to label (the workspace and the objects' feet).
    seeds : (h, w) bool
        The pixels a core must reach (the workspace above the feet).
    settings : SegmentSettings
        ``concavity``, ``cluster_distance`` and ``max_depth_jump``.
    concave : bool
        Whether to cut at concave creases too (on a support plane), or at depth steps only (a frame of one object
        has no neighbour to meet: its handle's or its inside's crease is its own).

    Returns
    -------
    (h, w) int64
    """
    labels = np.zeros(region.shape, np.int64)
    rows, cols = np.nonzero(region)
    if len(rows) == 0:
        return labels
    pad = 2 * CREASE_REACH + NORMAL_WINDOW  # the window the normals and creases look through
    window = (
        slice(max(rows.min() - pad, 0), rows.max() + pad + 1),
        slice(max(cols.min() - pad, 0), cols.max() + pad + 1),
    )
    labels[window] = _split(points[window], region[window], seeds[window], settings, concave)
    return labels


def _split(points: np.ndarray, region: np.ndarray, seeds: np.ndarray, settings, concave: bool) -> np.ndarray:
    """:func:`split_surfaces` in the window around the region."""
    jump = settings.max_depth_jump
    cut = steps(points, region, jump)
    if concave:  # in single precision: a millimetre at a metre is far above its rounding, and half the memory to move
        single = points.astype(np.float32)
        normals = grid_normals(np.where(region[..., None], single, np.float32(np.nan)), jump)
        cut |= creases(single, normals, region, jump, settings.concavity)
        # and the region's own edge, where no normal is known: two objects' outlines would join them there
        cut |= region & ~ndimage.binary_erosion(region)
    cut = ndimage.binary_dilation(cut, iterations=CUT_BAND)
    cores, count = ndimage.label(region & ~cut)
    sizes = np.bincount(cores.ravel(), minlength=count + 1)
    reached = np.zeros(len(sizes), bool)
    reached[cores[seeds]] = True
    keep = (sizes >= CORE_PIXELS) & reached
    keep[0] = False
    number = np.where(keep, np.cumsum(keep), 0)  # the kept cores numbered 1..K
    cores = number[cores]
    if not cores.any():
        return cores
    _, (rows, cols) = ndimage.distance_transform_edt(cores == 0, return_indices=True)
    with np.errstate(invalid="ignore"):
        gap = np.linalg.norm(points - points[rows, cols], axis=2)
    labels = np.where(region & (gap <= settings.cluster_distance), cores[rows, cols], 0)
    labels = _grow(labels, points, region, jump)  # the rest (whose nearest core lies across a step) by their surface
    if not concave:
        labels = _join_near(labels, points, settings.cluster_distance)
    used = np.bincount(labels.ravel(), minlength=int(keep.sum()) + 1) > 0
    used[0] = False
    return np.where(used, np.cumsum(used), 0)[labels]  # a core that kept no pixel leaves no gap in the numbers


def _join_near(labels: np.ndarray, points: np.ndarray, distance: float) -> np.ndarray:
    """``labels`` with pieces joined that come within ``distance`` of each other (pixels up to :data:`NEAR_PIXELS`
    apart): one object's pieces parted by a depth step (a cup's inside seen over its rim), as a Euclidean clustering
    joins them, where no support plane says that two objects may meet."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    count = int(labels.max()) + 1
    if count <= 2:
        return labels
    pairs = [np.column_stack(pair) for pair in _near_pairs(labels, points, distance)]
    joined = np.concatenate(pairs)
    graph = sp.coo_matrix((np.ones(len(joined)), (joined[:, 0], joined[:, 1])), shape=(count, count))
    _, component = connected_components(graph, directed=False)
    return np.where(labels > 0, component[labels] + 1, 0)  # renumbered by the caller


def _grow(labels: np.ndarray, points: np.ndarray, region: np.ndarray, max_jump: float) -> np.ndarray:
    """``labels`` grown over the region's unlabelled pixels, a pixel a step for :data:`GROW_STEPS` steps, each taking
    a neighbour's label across no depth step: a pixel whose nearest core in the image lies across a step (the wall
    seen beside a can) joins the surface it lies on."""
    labels = labels.copy()
    z = np.where(region, points[..., 2], np.nan)
    for _ in range(GROW_STEPS):
        open_ = region & (labels == 0)
        if not open_.any():
            break
        for dv, du in ((0, 1), (1, 0), (0, -1), (-1, 0)):
            other = _shift(labels.astype(np.float64), dv, du, fill=0).astype(np.int64)
            take = open_ & (labels == 0) & (other > 0) & continuous(z, _shift(z, dv, du), max_jump)
            labels[take] = other[take]
    return labels


def join_small(labels: np.ndarray, points: np.ndarray, distance: float, area: float) -> np.ndarray:
    """``labels`` with each piece smaller than ``area`` joined to the neighbour it lies nearest to along the longest
    stretch (pixels up to :data:`NEAR_PIXELS` apart and within ``distance`` in space), smallest first: LCCP's
    minimum segment size (Stein et al. 2014), which gives a mug its handle back and a loaf its slices.

    Parameters
    ----------
    labels : (h, w) int
        Pieces 1..N, 0 for none.
    points : (h, w, 3) float64
        Camera-frame points.
    distance : float
        Metres: pieces farther apart than this are not neighbours (a depth step wider than a cluster's gap).
    area : float
        In pixels at 1 m: a piece's area is the sum of its pixels' squared depths (each pixel's footprint, facing
        the camera, is ``z^2 / (fx fy)``), so ``area`` is square metres times ``fx fy``.

    Returns
    -------
    (h, w) int64
    """
    count = int(labels.max()) + 1
    if count <= 2:
        return labels
    rows, cols = np.nonzero(labels)
    window = (slice(rows.min(), rows.max() + 1), slice(cols.min(), cols.max() + 1))  # the pieces' box
    border = np.zeros((count, count), np.int64)
    for near, other in _near_pairs(labels[window], points[window], distance):
        np.add.at(border, (near, other), 1)
    border += border.T
    depth = np.nan_to_num(points[window][..., 2])
    footprint = np.bincount(labels[window].ravel(), weights=depth.ravel() ** 2, minlength=count)
    into = np.arange(count)
    for piece in np.argsort(footprint):
        if piece == 0 or footprint[piece] >= area or not border[piece].any():
            continue
        target = int(np.argmax(border[piece]))
        into[into == piece] = target
        border[target] += border[piece]
        border[:, target] += border[:, piece]
        border[target, target] = 0
        border[piece] = 0
        border[:, piece] = 0
        footprint[target] += footprint[piece]
    return into[labels]


def _near_pairs(labels: np.ndarray, points: np.ndarray, distance: float) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """The labels of pixel pairs of different pieces up to :data:`NEAR_PIXELS` apart in the image (across, down and
    diagonally) and within ``distance`` of each other in space, one pair of (k,) arrays per offset."""
    for reach in range(1, NEAR_PIXELS + 1):
        for dv, du in ((0, reach), (reach, 0), (reach, reach), (reach, -reach)):
            other = _shift(labels.astype(np.float64), dv, du, fill=0).astype(np.int64)
            apart = (labels > 0) & (other > 0) & (labels != other)
            with np.errstate(invalid="ignore"):
                apart &= np.linalg.norm(points - _shift(points, dv, du), axis=2) <= distance
            yield labels[apart], other[apart]
