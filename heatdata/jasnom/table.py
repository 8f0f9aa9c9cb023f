"""The support-plane term of JASNOM for two scans of an object on a table (thesis 7.5's acquisition, beyond 7.2).

The thesis scans an object standing on a table, flips it upside down and scans it again (7.5, Fig. 7.1). Two
silhouettes cut where both surfaces graze leave a band of unseen surface between the boundaries, along the
viewing ray; no boundary term sees its width to first order, so the boundary cost alone prefers to close it. The
table the object stands on carries what the boundaries lack. With ``x1 = R x2 + t`` moving scan 2 into scan 1's
frame, and each scan's table plane ``P = (n, d)`` (unit normal towards the object, height ``n . x + d``):

- **scan 1 (standing)**: the object's bottom rests on P1. Scan 1 does not see it; scan 2 (flipped, the bottom
  now facing up) does. So the moved scan 2 lies on P1's object side and touches it:
  ``h_a = n1 . (R y + t) + d1 >= 0`` for every point ``y`` of scan 2, with its lowest points at 0;
- **scan 2 (flipped)**: the object's top rests on P2, seen by scan 1. So scan 1 lies on the moved P2's object
  side and touches it: ``h_b = (R n2) . (x - t) + d2 >= 0`` for every point ``x`` of scan 1, lowest at 0.

Both fix the translation along the table normal. They do not fix the rest of the band: the design assumed that
the band's ambiguity lies along the viewing ray, one direction, so that fixing its component along the normal
fixes it whole. Measured, the search is free to slide the flipped scan *along the table*, and the
boundary cost closes the band by the ray's horizontal part (``scripts/jasnom_scans.py --table-out``: the error left
lies along the ray's horizontal part, not the normal). Nor does the contact fix the tilt of a flat bottom: a tilt
that keeps the lowest :data:`CONTACT_SHARE` of the points on the plane costs nothing (a cylinder with a known band:
its centroid 0.26% of the size off along the normal, against 0.70% without the table).

What holds the slide and the turn is **free space**: with the frames, each camera measured where the object is not.
A point of the moved scan 2 that stands in front of what camera 1 read (the table beside the object, the wall
behind it) cannot be there, and the same for scan 1 in camera 2.

**The term** (added to J, eq. 7.4, with weight ``table``), in units of the boundary's RMS radius ``s`` as J's
terms are:

``T = table * [ (c_a / s)^2 + (c_b / s)^2 + mean_y p(h_a)^2 + mean_x p(h_b)^2 + mean_y f_1(y)^2 + mean_x f_2(x)^2 ]``

- ``c_a``, ``c_b``: the *contact*, the :data:`CONTACT_SHARE` quantile of the heights (not their minimum, which a
  sensor's noise and a flying pixel set);
- ``p(h) = min(h, 0) / s``: how far a point lies below the plane. Not J2's logistic, which a boundary sample
  switches on only where it crosses the other mesh: here the whole object stands above the plane, and a logistic's
  tail over thousands of points near it would pull the object down by a share of the sample spacing;
- ``f_k = max(D_k(u) - z - spacing, 0) / s``: how far a moved point stands in front of the nearest reading ``D_k``
  within :data:`NEIGHBOURHOOD` pixels of where camera k sees it (0 outside the image and where it read nothing),
  beyond the mean spacing of the scans' samples.

At the true motion T is 0 up to the sensor's noise; moved by ``delta`` along the normal it grows as
``2 table (delta / s)^2``, whatever the object's size.

**The seeds.** The flip is a half-turn about an axis in the table plane: the object's up, ``n1`` in scan 1, is
``-n2`` in scan 2, so ``R n2 = -n1``. :meth:`TableContact.flip_candidates` gives the motions that satisfy this, at
every :data:`TURNS`-th turn about the normal, each set on the table with its footprint's centroid over scan 1's;
:func:`heatdata.jasnom.align.align` slides each along the table by closest-point steps between the boundaries,
sets its boundary correspondences' candidates on the table too, and refines the best of both families. An object
that rests tilted once flipped (a top that is not parallel to its bottom) departs from ``R n2 = -n1``; the
refinement is free to follow it.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

from heatdata.core.geometry import rotation_between
from heatdata.errors import StitchError
from heatdata.io.models import Model
from heatdata.jasnom.cost import ScanSurface
from heatdata.segmentation.segment import SegmentSettings, segment_frame
from heatdata.typing import StrPath
from heatdata.views.depth import nearest_readings, pixels_of

log = logging.getLogger(__name__)

#: the contact is this quantile of the heights above a plane, not the minimum that noise and flying pixels set
CONTACT_SHARE = 0.02
#: surface samples per scan that the term measures (a seeded sample by area where a scan has more faces)
CONTACT_POINTS = 2000
#: turns about the table normal the flip candidates try (every 360 / TURNS degrees)
TURNS = 72
#: a point hides behind a frame's reading when it lies behind the nearest reading within this many pixels: the
#: outline of an object rounds onto the background beside it, where a sensor's edge reads flying pixels
NEIGHBOURHOOD = 5
#: the most the two scans' object heights above their tables may differ by, as a ratio (the same object, flipped)
HEIGHT_RATIO = 1.3
#: the share of a scan's points above its table that sets its height (not the highest, a flying pixel's)
TOP_SHARE = 0.99
#: an object whose pixels come this near the image border is cut by it: a sensor reads nothing in a band along its
#: edges (the Kinect's projector does not light the last columns)
BORDER_PIXELS = 12


@dataclass(frozen=True)
class TableScan:
    """An object scanned standing on a table (or flipped): its segmented view as a mesh, the table plane and the
    frame it was cut from, all in the camera's frame.

    Attributes
    ----------
    model : Model
        The object's view (:func:`heatdata.segmentation.segment.segment_frame`'s largest segment).
    plane : (4,) float64
        The table ``a, b, c, d``, unit normal towards the camera (and the object).
    depth : (h, w) float64
        The frame's depth, metres, NaN where it has no reading.
    intrinsics : dict
        ``fx, fy, cx, cy, width, height``.
    """

    model: Model
    plane: np.ndarray
    depth: np.ndarray
    intrinsics: dict

    @property
    def height(self) -> float:
        """The object's height above the table, metres (the :data:`TOP_SHARE` quantile of its vertices')."""
        return float(np.quantile(self.model.vertices @ self.plane[:3] + self.plane[3], TOP_SHARE))


def table_scan(
    depth: np.ndarray,
    intrinsics: dict,
    rgb: np.ndarray | None = None,
    *,
    name: str = "scan",
    settings: SegmentSettings | None = None,
) -> TableScan:
    """A depth frame of an object on a table, segmented: the table plane and the object standing on it.

    Parameters
    ----------
    depth : (h, w) float
        z-depth, metres (NaN, 0 or negative: no reading).
    intrinsics : dict
        ``fx, fy, cx, cy, width, height``.
    rgb : (h, w, 3) uint8 or float in [0, 1], optional
        Its colour, for the stitched model's.
    name : str
        The scan's name, for messages and the model.
    settings : SegmentSettings, optional
        How the frame is segmented (the scenes' defaults).

    Returns
    -------
    TableScan

    Raises
    ------
    StitchError
        A frame without a table plane, with nothing on it, or whose object the image border cuts.
    """
    found = segment_frame(depth, intrinsics, rgb, settings, name=name)
    if found.plane is None or found.depth is None:
        raise StitchError(
            f"{name}: no table plane in the frame ({'; '.join(found.notes)}): scans to stitch with their tables are "
            "of an object standing on one"
        )
    if not found.segments:
        raise StitchError(f"{name}: nothing stands on the table ({'; '.join(found.notes)})")
    if len(found.segments) > 1:
        log.warning("%s: %d objects stand on the table: the largest is stitched", name, len(found.segments))
    segment = found.segments[0]
    u0, v0, u1, v1 = segment.bbox
    width, height = int(intrinsics["width"]), int(intrinsics["height"])
    if min(u0, v0, width - 1 - u1, height - 1 - v1) < BORDER_PIXELS:
        raise StitchError(
            f"{name}: the object touches the image border: its boundary there is the image's, not the object's "
            "(step back, or turn the camera, so that the whole object is in the frame)"
        )
    view = segment.view
    model = Model.untextured(name, view.vertices, view.faces, view.colors[view.faces], source=name)
    return TableScan(model, found.plane, found.depth, dict(view.intrinsics or intrinsics))


def read_table_scan(depth_path: StrPath, intrinsics_path: StrPath, rgb_path: StrPath | None = None) -> TableScan:
    """:func:`table_scan` of a depth frame's files (a 16-bit PNG in millimetres or a ``.npy`` in metres, its
    intrinsics' JSON or YAML, and optionally its colour image)."""
    from pathlib import Path

    from heatdata.views.depth import read_depth_frame

    depth, rgb, intrinsics = read_depth_frame(depth_path, intrinsics_path, rgb_path)
    return table_scan(depth, intrinsics, rgb, name=Path(depth_path).stem)


@dataclass(frozen=True)
class TableContact:
    """Two scans' table planes and surface samples, each in its own scan's frame.

    Attributes
    ----------
    planes : (2, 4) float64
        ``a, b, c, d`` of each scan's table plane, unit normal towards the object (a point's
        height above it is ``n . x + d``), as :class:`heatdata.segmentation.segment.Segmentation`
        gives it.
    points : tuple of two (m, 3) float64
        Samples of each scan's surface (face centroids).
    spacing : float
        The mean distance from a sample to its nearest neighbour, over both scans.
    """

    planes: np.ndarray
    points: tuple[np.ndarray, np.ndarray]
    spacing: float
    depths: tuple[np.ndarray, np.ndarray] | None = None
    intrinsics: tuple[dict, dict] | None = None

    @classmethod
    def of_scans(cls, first: TableScan, second: TableScan, count: int = CONTACT_POINTS) -> TableContact:
        """The contact of two scans on their tables, with their frames: a moved scan that stands in front of what
        the other's camera measured costs too (the free-space residuals of :meth:`residuals`).

        Raises
        ------
        StitchError
            Objects whose heights above their tables differ by more than :data:`HEIGHT_RATIO` (not one object).
        """
        heights = first.height, second.height
        if max(heights) > HEIGHT_RATIO * min(heights):
            raise StitchError(
                f"the object on {first.model.name}'s table is {heights[0]:.3f} m tall and the one on "
                f"{second.model.name}'s {heights[1]:.3f} m: not one object scanned standing and flipped"
            )
        contact = cls.of(first.model, second.model, first.plane, second.plane, count)
        depths = tuple(nearest_readings(scan.depth, NEIGHBOURHOOD) for scan in (first, second))
        return cls(contact.planes, contact.points, contact.spacing, depths, (first.intrinsics, second.intrinsics))  # type: ignore[arg-type]

    @classmethod
    def of(cls, first: Model, second: Model, plane1, plane2, count: int = CONTACT_POINTS) -> TableContact:
        """The contact of two scans on their planes.

        Raises
        ------
        StitchError
            A plane that is not four finite numbers with a nonzero normal, or a scan that lies mostly below its
            plane (a normal pointing away from the object).
        """
        planes = np.array([_checked_plane(p, k) for k, p in enumerate((plane1, plane2), start=1)])
        points = tuple(ScanSurface.of(model, count).centroids for model in (first, second))
        for k, (model, plane, sample) in enumerate(zip((first, second), planes, points, strict=True), start=1):
            if np.median(sample @ plane[:3] + plane[3]) < 0:
                raise StitchError(
                    f"{model.name}: most of the scan lies below plane {k}: its normal must point towards the object "
                    "(a table's normal points up, towards the camera)"
                )
        spacing = float(np.mean([cKDTree(p).query(p, k=2)[0][:, 1].mean() for p in points]))
        return cls(planes, points, spacing)  # type: ignore[arg-type]

    def heights(self, rotation: np.ndarray, translation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """At ``x1 = rotation @ x2 + translation``: scan 2's heights above plane 1 and scan 1's above the moved
        plane 2 (``h_a``, ``h_b`` of the module docstring)."""
        (n1, d1), (n2, d2) = (self.planes[0, :3], self.planes[0, 3]), (self.planes[1, :3], self.planes[1, 3])
        moved_normal = rotation @ n2
        h_a = (self.points[1] @ rotation.T + translation) @ n1 + d1
        h_b = (self.points[0] - translation) @ moved_normal + d2
        return h_a, h_b

    def residuals(self, rotation: np.ndarray, translation: np.ndarray, scale: float) -> np.ndarray:
        """The term's residuals at a motion, unweighted: their squares sum to ``T / table``.

        Returns
        -------
        (4,) or (6,) float64
            ``c_a / s``, ``c_b / s``, the RMS of ``p(h_a)`` and of ``p(h_b)``, and with the
            frames the RMS of ``f`` for scan 2 in camera 1 and for scan 1 in camera 2 (one
            residual per sum: the least squares' Jacobian stays small).
        """
        h_a, h_b = self.heights(rotation, translation)
        contacts = [np.quantile(h_a, CONTACT_SHARE), np.quantile(h_b, CONTACT_SHARE)]
        below = [_rms(np.minimum(h, 0.0)) for h in (h_a, h_b)]
        if self.depths is None or self.intrinsics is None:
            return np.array([*contacts, *below]) / scale
        front = [
            _rms(self._in_front(self.points[1] @ rotation.T + translation, 0)),
            _rms(self._in_front((self.points[0] - translation) @ rotation, 1)),
        ]
        return np.array([*contacts, *below, *front]) / scale

    def _in_front(self, points: np.ndarray, k: int) -> np.ndarray:
        """How far each of ``points`` (in scan ``k``'s camera frame) stands in front of the nearest reading of that
        camera, beyond the sample spacing (0 behind it, outside the image and where it read nothing)."""
        depth = self.depths[k]  # type: ignore[index]
        pixel, inside = pixels_of(points, self.intrinsics[k])  # type: ignore[index]
        measured = np.full(len(points), np.nan)
        measured[inside] = depth[pixel[inside, 1], pixel[inside, 0]]
        gap = np.where(np.isfinite(measured), measured - points[:, 2] - self.spacing, 0.0)
        return np.maximum(gap, 0.0)

    def on_table(self, rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
        """``translation`` moved along plane 1's normal so that scan 2's contact with plane 1 is 0."""
        normal = self.planes[0, :3]
        return translation - np.quantile(self.heights(rotation, translation)[0], CONTACT_SHARE) * normal

    def flip_candidates(self, turns: int = TURNS) -> tuple[np.ndarray, np.ndarray]:
        """Motions of scan 2 that turn it upside down onto plane 1 (``R n2 = -n1``), one per turn about ``n1``.

        Each is placed so that scan 2's footprint (its samples' foot on plane 1) has its centroid over scan 1's,
        and its :data:`CONTACT_SHARE` quantile of heights is 0.

        Returns
        -------
        rotations : (turns, 3, 3) float64
        translations : (turns, 3) float64
        """
        n1, d1 = self.planes[0, :3], self.planes[0, 3]
        n2 = self.planes[1, :3]
        upright = rotation_between(n2, -n1)
        angles = 2 * np.pi * np.arange(turns) / turns
        rotations = Rotation.from_rotvec(angles[:, None] * n1).as_matrix() @ upright
        foot1 = _foot(self.points[0], n1, d1).mean(axis=0)
        translations = [
            self.on_table(rotation, foot1 - _foot(self.points[1] @ rotation.T, n1, d1).mean(axis=0))
            for rotation in rotations
        ]
        return rotations, np.array(translations)


def _rms(values: np.ndarray) -> float:
    return float(np.sqrt(np.mean(values**2)))


def _checked_plane(plane, k: int) -> np.ndarray:
    try:
        p = np.asarray(plane, dtype=np.float64).reshape(4)
    except (TypeError, ValueError):
        raise StitchError(f"plane {k} must be four numbers a, b, c, d, got {plane!r}") from None
    length = float(np.linalg.norm(p[:3]))
    if not (np.all(np.isfinite(p)) and length > 0):
        raise StitchError(f"plane {k} must be four finite numbers with a nonzero normal, got {p.tolist()}")
    return p / length


def _foot(points: np.ndarray, normal: np.ndarray, offset: float) -> np.ndarray:
    """The feet of ``points`` on the plane ``normal . x + offset = 0`` (unit normal)."""
    return points - np.outer(points @ normal + offset, normal)
