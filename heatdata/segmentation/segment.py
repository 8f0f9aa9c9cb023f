"""Scenes: the support plane of a depth frame and the objects standing on it, one view each (the step thesis 2.1
leaves outside its scope, as PCL's ``3d_rec_framework`` global pipeline does it).

:func:`segment_frame` reads a depth frame (and its colour) the way a tabletop pipeline does:

1. **planes** (:func:`heatdata.segmentation.plane.support_plane`): up to three planes by RANSAC (open3d's
   ``segment_plane``, seeded, every sample drawn, then refit by least squares to its inliers, so that a frame is
   segmented the same every time), each holding at least ``plane_share`` of the readings; a **support plane** spans
   at least ``plane_size`` metres and has (almost) nothing hanging below its edges (an object's own face has: a
   box's top its sides, a chair's seat its legs). Of these, those facing up in the image come first (a table before
   the wall behind it), a plane standing a little above a wider one is an object's top (a book, a tray) and not the
   support, and of the rest the highest that anything stands on is the support (a table before the floor beneath
   it), else the largest (a bare table);
2. **the workspace**: the readings between ``min_height`` and ``max_height`` above the support plane on surfaces
   that reach inside the plane's outline (the convex hull of its facing pieces): not the wall behind the table, not
   the floor beyond it. Without a support plane (a frame of one isolated object, as the library's views are) every
   reading is in the workspace; and when nothing stands on the support plane of a frame whose readings cover less
   than half the image, the plane was an object's own face (a chair's seat) and the frame is segmented without it;
3. **surfaces cut where objects meet** (:func:`heatdata.segmentation.surfaces.split_surfaces`): at depth steps and,
   on a support plane, at concave creases sharper than ``concavity`` (LCCP's criterion on the pixel grid), pieces
   smaller than ``piece_area`` joined back to their neighbour (a mug's handle); without a support plane, pieces
   within ``cluster_distance`` of each other are one object. Segments under ``min_pixels`` are dropped and said so,
   and so is a segment that is one flat surface wider than ``plane_size`` (a wall seen without a table), but in a
   frame of one isolated object (readings on less than half the image), where it is the object's face;
4. each segment becomes a :class:`heatdata.View`, triangulated from its own pixels as a depth frame is
   (:func:`heatdata.views.depth.grid_view`), with every connected piece kept but specks below
   :data:`heatdata.views.view.MIN_VERTICES` vertices.

What a user should know about a segment is in its ``notes``: cut by the image border, in several pieces, and (the
library adds this) larger than any object it holds, which is what objects touching without a concave seam look like:
they form one segment. What the frame as a whole showed (no support plane, a plane seen edge-on, segments dropped
and why) is in the :class:`Segmentation`'s ``notes``.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from heatdata.errors import ViewError
from heatdata.segmentation.plane import PLANE_POINTS, depth_scale, diameter, refined_plane, support_plane
from heatdata.segmentation.settings import SegmentSettings
from heatdata.segmentation.surfaces import join_small, reaching, split_surfaces
from heatdata.views.depth import back_project, checked_depth, checked_rgb, cut_depth, grid_view
from heatdata.views.view import MIN_VERTICES, View, check_intrinsics, has_colour

log = logging.getLogger(__name__)

ISOLATED = 0.5  # a frame whose readings cover less of the image than this is of one object, when nothing stands on
# its support plane (the void around an object cut out of its frame, as a library's view is)
FOOTING = 0.5  # readings this share of the plane's distance above it may be an object's foot, where one touches
FLAT_SHARE = 0.95  # a cluster with this share of its points on one plane wider than plane_size is background

FIELD_OF_VIEW = (30.0, 130.0)  # degrees: the horizontal fields of view of depth sensors, narrowest and widest


@dataclass
class Segment:
    """One object's part of a frame.

    Attributes
    ----------
    view : View
        Its partial view (camera frame), every connected piece kept.
    mask : (h, w) bool or None
        Its pixels (None for a view given whole, :func:`segment_view`).
    pixels : int
        How many readings it holds.
    bbox : (4,) int
        ``u0, v0, u1, v1``: its pixels' bounding box, inclusive.
    centroid : (3,) float64
        The mean of its points in the camera frame, metres (x right, y down, z forward).
    extent : float
        Its largest size, metres: the diameter of its footprint on the support plane when there is one, else of its
        points (:data:`TRIM` of the outermost left out).
    notes : list of str
        What a user should know about it (cut by the image border, several pieces).
    """

    view: View
    mask: np.ndarray | None
    pixels: int
    bbox: tuple[int, int, int, int]
    centroid: np.ndarray
    extent: float
    notes: list[str] = field(default_factory=list)


@dataclass
class Segmentation:
    """What :func:`segment_frame` found in a frame.

    Attributes
    ----------
    plane : (4,) float64 or None
        The support plane ``a, b, c, d`` (``a x + b y + c z + d = 0`` in the camera frame, unit normal towards the
        camera: ``d > 0`` and a point's height above the plane is ``n . x + d``), or None.
    segments : list of Segment
        The objects, largest first.
    notes : list of str
        What the frame showed: the plane, or why there is none; clusters dropped.
    coloured : bool
        Whether the frame came with a colour image.
    depth : (h, w) float64 or None
        The frame's depth, metres, NaN where it has no reading (all of it, also outside a mask or depth range);
        None for a view given whole. A pose is checked against it (:mod:`heatdata.recognition.pose`).
    """

    plane: np.ndarray | None
    segments: list[Segment]
    notes: list[str] = field(default_factory=list)
    coloured: bool = False
    depth: np.ndarray | None = field(default=None, repr=False)


def segment_frame(
    depth: np.ndarray,
    intrinsics: dict,
    rgb: np.ndarray | None = None,
    settings: SegmentSettings | None = None,
    *,
    mask: np.ndarray | None = None,
    depth_range: tuple[float, float] | None = None,
    name: str = "frame",
) -> Segmentation:
    """The support plane of a depth frame and a view of each object on it (see the module docstring).

    Parameters
    ----------
    depth : (h, w) float
        z-depth in metres; NaN, infinite or <= 0 where there is no reading.
    intrinsics : dict
        ``fx, fy, cx, cy, width, height`` matching the image.
    rgb : (h, w, 3) uint8 or float in [0, 1], optional
        Colour registered to the depth image (default grey).
    settings : SegmentSettings, optional
        The plane, workspace and clustering settings.
    mask : (h, w) bool, optional
        The pixels to segment (an object cut out by the user: two objects in one mask are two segments).
    depth_range : (near, far) metres, optional
        The depths to segment (with a mask too: the pixels both keep).
    name : str
        The frame's name, for messages and the views' ids (``name/0``, ``name/1``...).

    Returns
    -------
    Segmentation
        The plane (or None), the segments, largest first (possibly none), and notes.

    Raises
    ------
    ViewError
        Intrinsics that do not match the image, an RGB image of another size, or no reading at all.
    """
    depth, k = checked_depth(depth, intrinsics, name)
    if mask is None and depth_range is None:
        return segment_points(back_project(depth, k), k, rgb, settings, name=name)
    cut, note = cut_depth(depth, mask, depth_range, name)
    found = segment_points(back_project(cut, k), k, rgb, settings, name=name)
    whole = np.where(np.isfinite(depth) & (depth > 0), depth, np.nan)
    return Segmentation(found.plane, found.segments, [note, *found.notes], found.coloured, whole)


def field_of_view(intrinsics: dict) -> float:
    """The horizontal field of view of ``intrinsics``, degrees: ``2 atan(width / 2 fx)``."""
    return float(np.degrees(2 * np.arctan(intrinsics["width"] / (2 * intrinsics["fx"]))))


def field_of_view_notes(intrinsics: dict) -> list[str]:
    """A note when the intrinsics' field of view is outside :data:`FIELD_OF_VIEW`, the depth sensors' (Kinect 57
    deg, RealSense D435 87 deg, Azure Kinect's wide mode 120 deg): a focal length for another image size, or in
    other units, makes every object the wrong size."""
    degrees = field_of_view(intrinsics)
    low, high = FIELD_OF_VIEW
    if low <= degrees <= high:
        return []
    return [
        f"the intrinsics give a horizontal field of view of {degrees:.0f} deg (fx {intrinsics['fx']:g} px over "
        f"{intrinsics['width']} px), outside the {low:g}-{high:g} deg of depth sensors: is fx in pixels of this "
        "image's size?"
    ]


def segment_points(
    points: np.ndarray,
    intrinsics: dict,
    colors: np.ndarray | None = None,
    settings: SegmentSettings | None = None,
    *,
    name: str = "frame",
) -> Segmentation:
    """:func:`segment_frame` of an organized grid of camera-frame points (an organized cloud's).

    Parameters
    ----------
    points : (h, w, 3) float
        Camera-frame points, metres (x right, y down, z forward); NaN where there is no reading.
    intrinsics : dict
        The camera's ``fx, fy, cx, cy, width, height`` (:func:`heatdata.frames.clouds.fit_intrinsics` for a cloud).
    colors : (h, w, 3) uint8 or float in [0, 1], optional
        Their colours.
    settings : SegmentSettings, optional
        The plane, workspace and clustering settings.
    name : str
        The frame's name.

    Returns
    -------
    Segmentation
    """
    settings = settings or SegmentSettings()
    points = np.asarray(points, dtype=np.float64)
    if points.ndim != 3 or points.shape[2] != 3:
        raise ViewError(f"{name}: an organized grid of points is (h, w, 3), got shape {points.shape}")
    k = check_intrinsics(intrinsics, points.shape[:2], name)
    valid = np.isfinite(points).all(axis=2) & (points[..., 2] > 0)
    if not valid.any():
        raise ViewError(f"{name}: the frame has no valid reading (all zero, NaN or negative): an empty frame")
    points = np.where(valid[..., None], points, np.nan)
    colors = None if colors is None else checked_rgb(colors, valid.shape, name)
    notes: list[str] = field_of_view_notes(k)
    plane, inliers, outline = support_plane(points, valid, settings, notes)
    footing = np.zeros(valid.shape, bool)
    if plane is None or outline is None:
        workspace = valid.copy()
    else:
        height = points @ plane[:3] + plane[3]
        with np.errstate(invalid="ignore"):
            scale = depth_scale(points)
            workspace = valid & ~inliers & (height > settings.min_height * scale) & (height <= settings.max_height)
            # the band an object's foot stands in, above the plane's noise: a segment grows into it where it touches
            footing = valid & (height > FOOTING * settings.plane_distance * scale) & ~workspace
        stride = max(1, int(np.sqrt(workspace.sum() / PLANE_POINTS)))
        # the surfaces that reach inside the outline: not the wall rising at its edge (nor its base, in the foot's
        # band, along which an object standing by the wall would grow); an object standing at the table's far edge,
        # or on others, has its foot outside the outline of the table seen between the objects, but is kept
        inside = outline.contains_grid(points, workspace, settings.plane_distance, stride)
        workspace = reaching(points, workspace, inside, settings.max_depth_jump)
        footing &= (height <= settings.min_height * scale) & outline.contains_grid(
            points, footing, settings.plane_distance, stride
        )
    isolated = valid.sum() < ISOLATED * valid.size
    segments = _clusters(points, colors, workspace, footing, plane, settings, notes, name, k, isolated)
    if not segments and plane is not None and isolated:
        notes.append(
            f"nothing stands on that plane, and the readings cover {valid.sum() / valid.size:.0%} of the image: a "
            "frame of one object seen over a face of its own (a chair's seat); segmented without a support"
        )
        plane = None
        segments = _clusters(points, colors, valid, np.zeros(valid.shape, bool), None, settings, notes, name, k, True)
    if not segments:
        notes.append(
            "no object on the support plane" if plane is not None else "no object in the frame (only flat background)"
        )
    for note in notes:
        log.debug("%s: %s", name, note)
    return Segmentation(
        plane, segments, notes, coloured=colors is not None, depth=np.where(valid, points[..., 2], np.nan)
    )


def segment_view(view: View, note: str) -> Segmentation:
    """A view already cut from its frame (a saved view, a frame segmented by a mask or a depth range) as the one
    segment of a frame with no support plane, so that it is answered as a scene's objects are.

    Parameters
    ----------
    view : View
        The object's view.
    note : str
        How it was segmented, for the answer's notes.

    Returns
    -------
    Segmentation
    """
    pixels = view.pixels
    low, high = np.floor(pixels.min(axis=0)).astype(int), np.ceil(pixels.max(axis=0)).astype(int)
    segment = Segment(
        view=view,
        mask=None,
        pixels=view.n_vertices,
        bbox=(int(low[0]), int(low[1]), int(high[0]), int(high[1])),
        centroid=view.vertices.mean(axis=0),
        extent=diameter(view.vertices),
    )
    return Segmentation(None, [segment], [note], coloured=has_colour(view.colors))


def _clusters(
    points: np.ndarray,
    colors: np.ndarray | None,
    workspace: np.ndarray,
    footing: np.ndarray,
    plane: np.ndarray | None,
    settings: SegmentSettings,
    notes: list[str],
    name: str,
    intrinsics: dict,
    isolated: bool,
) -> list[Segment]:
    """The workspace's surfaces split where objects meet (:func:`heatdata.segmentation.surfaces.split_surfaces`),
    each grown into the ``footing`` pixels it touches (an object's foot, near the plane), one :class:`Segment` each."""
    count = int(workspace.sum())
    if count < settings.min_pixels:
        if count:
            notes.append(f"dropped {count} readings in the workspace: fewer than {settings.min_pixels}")
        return []
    labels = split_surfaces(points, workspace | footing, workspace, settings, concave=plane is not None)
    if plane is not None:  # a piece smaller than an object's least area is part of its neighbour
        labels = join_small(
            labels, points, settings.cluster_distance, settings.piece_area * intrinsics["fx"] * intrinsics["fy"]
        )
    sizes = np.bincount(labels.ravel())
    windows = ndimage.find_objects(labels)  # each label's box: its mask is made there, not over the whole frame
    segments: list[Segment] = []
    flat = 0
    small = []
    for label in np.argsort(-sizes[1:], kind="stable") + 1:
        if sizes[label] < settings.min_pixels:
            if sizes[label]:
                small.append(int(sizes[label]))
            continue
        window = windows[label - 1]
        pixels = (labels[window] == label, window)
        segment = _segment(points, colors, pixels, plane, settings, f"{name}/{len(segments)}", intrinsics, isolated)
        if segment is None:
            flat += 1
            continue
        segments.append(segment)
    alone = int((workspace & (labels == 0)).sum())
    if small:
        notes.append(
            f"dropped {len(small)} cluster(s) under {settings.min_pixels} pixels (the largest {max(small)}, "
            f"{sum(small)} readings in all)"
        )
    if alone:
        notes.append(f"dropped {alone} readings joined to no surface (flying pixels, specks)")
    if flat:
        notes.append(f"dropped {flat} flat cluster(s) wider than {settings.plane_size:g} m: background, not objects")
    return segments


def _segment(
    points: np.ndarray,
    colors: np.ndarray | None,
    pixels: tuple[np.ndarray, tuple[slice, slice]],
    plane: np.ndarray | None,
    settings: SegmentSettings,
    view_id: str,
    intrinsics: dict,
    isolated: bool,
) -> Segment | None:
    """The :class:`Segment` of the ``pixels`` (a mask of a window of the frame, and the window); None for a flat
    background surface (not in a frame of one isolated object, where a flat cluster is the object's face)."""
    import open3d as o3d

    inside, box = pixels
    cloud = points[box][inside]
    # its box's diagonal bounds its diameter: most segments are too small to be a wall without the hull
    wide = float(np.linalg.norm(np.ptp(cloud, axis=0))) > settings.plane_size
    if wide and not isolated and diameter(cloud, plane) > settings.plane_size:
        o3d.utility.random.seed(settings.seed)
        tolerance = settings.plane_distance * float(np.median(depth_scale(cloud)))
        flat = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(cloud))
        model, _ = flat.segment_plane(tolerance, 3, 200, probability=1.0)
        if len(refined_plane(cloud, model, tolerance)[1]) >= FLAT_SHARE * len(cloud):
            return None
    notes = []
    height, width = points.shape[:2]
    v0, v1, u0, u1 = box[0].start, box[0].stop - 1, box[1].start, box[1].stop - 1  # find_objects' tight box
    if u0 == 0 or v0 == 0 or u1 == width - 1 or v1 == height - 1:
        notes.append("cut by the image border: part of the object is outside the frame")
    mask = np.zeros((height, width), bool)
    mask[box] = inside
    grid = np.where(inside[..., None], points[box], np.nan)  # the view's vertices are camera coordinates: crop freely
    try:
        view = grid_view(
            grid, None if colors is None else colors[box], max_depth_jump=settings.max_depth_jump,
            components="all", intrinsics=intrinsics, view_id=view_id,
        )  # fmt: skip
    except ViewError as exc:
        log.info("%s: no view (%s)", view_id, exc)
        return None
    sizes = np.bincount(view.component_labels)
    if (sizes < MIN_VERTICES).any():
        keep = sizes[view.component_labels] >= MIN_VERTICES
        if not keep.any():
            return None
        dropped = int((sizes < MIN_VERTICES).sum())
        view = view.submesh(keep, f"dropped {dropped} speck(s) under {MIN_VERTICES} vertices")
    if view.n_components > 1:
        notes.append(f"in {view.n_components} pieces (the surface breaks at depth steps); all are kept")
    return Segment(
        view=view,
        mask=mask,
        pixels=int(inside.sum()),
        bbox=(u0, v0, u1, v1),
        centroid=cloud.mean(axis=0),
        extent=diameter(view.vertices, plane),
        notes=notes,
    )


def label_image(segmentation: Segmentation, shape: tuple[int, int]) -> np.ndarray:
    """(h, w) uint16: 0 for no object (the support plane, the background, no reading), 1..N for the segments in
    their order (largest first).

    Parameters
    ----------
    segmentation : Segmentation
        A frame's segments (each with its mask).
    shape : (h, w)
        The frame's size.

    Returns
    -------
    (h, w) uint16
    """
    labels = np.zeros(shape, np.uint16)
    for number, segment in enumerate(segmentation.segments, start=1):
        if segment.mask is None:
            raise ViewError(f"{segment.view.name}: a view given whole has no pixels in a frame to label")
        labels[segment.mask & (labels == 0)] = number
    return labels
