"""Partial views: the triangle mesh of the surface a depth sensor sees (thesis 2.1).

A :class:`View` holds the mesh in camera coordinates (OpenCV frame: x right, y down,
z forward, camera at the origin), per-vertex RGB, the camera intrinsics and, when it
was rendered, the view angle and pose. It does not care whether it came from the
renderer or a real sensor: :meth:`View.from_arrays` builds one from any mesh and
cleans it (NaN check, duplicate vertices merged, degenerate faces dropped), logging
and recording every repair in ``view.repairs``.

The boundary (2.3.3) is the outer boundary loop ordered counter-clockwise as a person
sees the image (x right, y up), starting where the +x axis of the image-centred frame
leaves the shape.
"""

from __future__ import annotations

import json
import logging
import zipfile
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from heatdata.core.geometry import rotation_between
from heatdata.core.mesh import (
    boundary_loops,
    component_labels,
    consistent_winding,
    mesh_edges,
)
from heatdata.errors import OutputError, ViewError
from heatdata.io.bounded_yaml import brief
from heatdata.io.files import atomic, atomic_group, require_file
from heatdata.typing import StrPath

log = logging.getLogger(__name__)

MIN_VERTICES = 30
ZERO_AREA = 1e-10  # faces below this fraction of the median face area (twice the area) are degenerate
INTRINSIC_KEYS = ("fx", "fy", "cx", "cy", "width", "height")
#: the grey a view's vertices get when no colour was given (a depth frame without its colour image)
NO_COLOUR = 0.5


def has_colour(colors: np.ndarray) -> bool:
    """Whether a view's ``colors`` (n, 3) were given: not every vertex the grey :data:`NO_COLOUR` a view without
    colour gets. A uniformly coloured object has colour; only an exact grey everywhere reads as none."""
    return bool(np.any(np.asarray(colors) != NO_COLOUR))


VIEW_ARRAYS = ("vertices", "faces", "colors", "pose", "angle", "intrinsics", "ids", "repairs")  # of a saved view
#: larger depth, colour and mask images and organized clouds are refused unread: a 1920 x 1080 depth PNG made into a
#: view and written as .npz and .ply peaks at 1.73 GB (a flat frame, every pixel a vertex; docs/guide/cli.md)
MAX_IMAGE_PIXELS = 2**21
#: a saved view of more vertices is refused before its arrays are read
MAX_VIEW_VERTICES = MAX_IMAGE_PIXELS
CANONICAL_STEPS = 8  # fixed-point steps of the canonical rotation (2-3 reach CANONICAL_PIXELS)
CANONICAL_PIXELS = 1e-3  # how near the optical axis the canonical frame centres the image's bounding box
#: the longest focal length and the farthest principal point, pixels: 10^6 px over a 2,000-pixel-wide image is a
#: 0.1 deg field of view, beyond any depth sensor; far beyond it, back-projection overflows
MAX_FOCAL = 1e6
KINECT_INTRINSICS = {"fx": 580.0, "fy": 580.0, "cx": 319.5, "cy": 239.5, "width": 640, "height": 480}


def check_intrinsics(intrinsics: dict, shape: tuple[int, int] | None = None, name: str = "intrinsics") -> dict:
    """``fx, fy, cx, cy, width, height`` as numbers, checked (and against an image's ``(h, w)``).

    Parameters
    ----------
    intrinsics : dict
        A pinhole camera: focal lengths and principal point in pixels, the image's size.
    shape : (h, w), optional
        The image they must fit.
    name : str
        The file or view, for the message.

    Returns
    -------
    dict
        The six values as floats, ``width`` and ``height`` as ints.

    Raises
    ------
    ViewError
        A key missing, a value that is not a number (a bool or a string is not), not finite, ``fx`` or ``fy``
        <= 0 or above :data:`MAX_FOCAL`, ``cx`` or ``cy`` beyond it, a size that is not a whole number >= 1, more than
        ``MAX_IMAGE_PIXELS``, or another shape.
    """
    missing = [key for key in INTRINSIC_KEYS if key not in intrinsics]
    if missing:
        raise ViewError(f"{name}: missing {', '.join(missing)} (need {', '.join(INTRINSIC_KEYS)})")
    given = {key: intrinsics[key] for key in INTRINSIC_KEYS}
    odd = [f"{key}={brief(value)}" for key, value in given.items() if isinstance(value, bool) or not _is_number(value)]
    if odd:
        raise ViewError(f"{name}: intrinsics must be numbers, got {', '.join(odd)}")
    k = {key: _as_float(value) for key, value in given.items()}
    bad = [f"{key}={k[key]:g}" for key in INTRINSIC_KEYS if not np.isfinite(k[key])]
    bad += [f"{key}={k[key]:g} (a focal length in pixels is > 0)" for key in ("fx", "fy") if k[key] <= 0]
    bad += [
        f"{key}={k[key]:g} (a whole number of pixels >= 1)"
        for key in ("width", "height")
        if np.isfinite(k[key]) and not (k[key] >= 1 and k[key] == round(k[key]))
    ]
    bad += [f"{key}={k[key]:g} (a focal length above {MAX_FOCAL:g} px)" for key in ("fx", "fy") if k[key] > MAX_FOCAL]
    if not bad and k["width"] * k["height"] > MAX_IMAGE_PIXELS:
        bad.append(f"{k['width']:g}x{k['height']:g} pixels, above the cap of {MAX_IMAGE_PIXELS / 1e6:.1f} Mpixel")
    bad += [
        f"{key}={k[key]:g} (a principal point beyond {MAX_FOCAL:g} px)"
        for key in ("cx", "cy")
        if abs(k[key]) > MAX_FOCAL
    ]
    if bad:
        raise ViewError(f"{name}: bad intrinsics: {', '.join(bad)}")
    k["width"], k["height"] = int(k["width"]), int(k["height"])
    if shape is not None and (k["height"], k["width"]) != tuple(shape):
        raise ViewError(
            f"{name}: the intrinsics are for {k['width']}x{k['height']} but the depth image is {shape[1]}x{shape[0]}"
        )
    return k


def _as_float(value) -> float:
    """``float(value)``; an integer of 400 digits is infinite, not an OverflowError."""
    try:
        return float(value)
    except OverflowError:
        return float("inf") if value > 0 else float("-inf")


def _is_number(value: object) -> bool:
    try:
        float(value)  # type: ignore[arg-type]
    except OverflowError:  # an integer of 400 digits is a number, an infinite one
        return True
    except (TypeError, ValueError):
        return False
    return not isinstance(value, str)


def kinect_intrinsics(image_scale: float = 1.0) -> dict:
    """The Kinect's intrinsics for an image scaled by ``image_scale`` (0.5: its 320x240 mode).

    Parameters
    ----------
    image_scale : float
        The image's size relative to 640 x 480.

    Returns
    -------
    dict
        ``fx, fy, cx, cy, width, height`` in pixels.
    """
    if not image_scale > 0:
        raise ViewError(f"image_scale must be positive, got {image_scale}")
    k = KINECT_INTRINSICS
    width, height = round(k["width"] * image_scale), round(k["height"] * image_scale)
    return {
        "fx": k["fx"] * image_scale,
        "fy": k["fy"] * image_scale,
        "cx": (width - 1) / 2.0,
        "cy": (height - 1) / 2.0,
        "width": width,
        "height": height,
    }


NPY_HEADERS = {(1, 0): np.lib.format.read_array_header_1_0, (2, 0): np.lib.format.read_array_header_2_0}


#: the largest array of a saved view, in bytes, by name (another array: :data:`MAX_OTHER_BYTES`)
MAX_ARRAY_BYTES = {"vertices": MAX_VIEW_VERTICES * 3 * 8, "colors": MAX_VIEW_VERTICES * 3 * 8}
MAX_ARRAY_BYTES["faces"] = 2 * MAX_ARRAY_BYTES["vertices"]
MAX_OTHER_BYTES = 2**20  # a pose, the angles, the identifiers, the intrinsics' and repairs' JSON


def _check_array_sizes(path: StrPath) -> None:
    """Refuse a ``.npz`` view whose arrays would not fit: each array's header is read, not its data (a compressed
    archive of 1 MB can hold 50 million vertices)."""
    try:
        with zipfile.ZipFile(path) as archive:
            for member in archive.infolist():
                key = member.filename.removesuffix(".npy")
                with archive.open(member) as file:
                    version = np.lib.format.read_magic(file)
                    if version not in NPY_HEADERS:
                        raise ValueError(f"npy format {version}")
                    shape, _, dtype = NPY_HEADERS[version](file)
                size = int(np.prod(shape, dtype=object)) * dtype.itemsize
                if size > MAX_ARRAY_BYTES.get(key, MAX_OTHER_BYTES):
                    raise ViewError(
                        f"{path}: its {key} hold {shape[0] if shape else 1:,} rows ({size / 2**20:,.0f} MB); a view "
                        f"holds at most {MAX_VIEW_VERTICES:,} vertices (one per pixel of a "
                        f"{MAX_IMAGE_PIXELS / 1e6:.1f} Mpixel image)"
                    )
    except ViewError:
        raise
    except Exception as exc:  # a damaged archive or header: zipfile, zlib and numpy raise many kinds
        raise ViewError(f"{path}: not a readable heatdata view ({type(exc).__name__}: {exc})") from None


@dataclass
class View:
    """A partial view.

    Attributes
    ----------
    vertices : (n, 3) float64
        Camera-frame coordinates in metres.
    faces : (m, 3) int64
        Triangles.
    colors : (n, 3) float64
        RGB in [0, 1].
    intrinsics : dict
        ``fx, fy, cx, cy, width, height`` of the pinhole camera.
    view_id, object_id, label : str
        Stable identifiers and class.
    azimuth, elevation, distance : float
        View angle in degrees and camera distance in metres (NaN for sensor data).
    pose : (4, 4) float64
        Camera-to-model transform (identity when unknown).
    repairs : list of str
        Every repair made to the input, in order.
    """

    vertices: np.ndarray
    faces: np.ndarray
    colors: np.ndarray
    intrinsics: dict = field(default_factory=lambda: dict(KINECT_INTRINSICS))
    view_id: str = ""
    object_id: str = ""
    label: str = ""
    azimuth: float = float("nan")
    elevation: float = float("nan")
    distance: float = float("nan")
    pose: np.ndarray = field(default_factory=lambda: np.eye(4))
    repairs: list = field(default_factory=list)

    @classmethod
    def from_arrays(
        cls, vertices: np.ndarray, faces: np.ndarray, colors: np.ndarray | None = None, **kwargs: Any
    ) -> View:
        """Build a view from raw arrays, checking and cleaning them.

        NaN or infinite coordinates raise :class:`ViewError`; duplicate vertices are
        merged, and faces that repeat a vertex or another face are dropped, each logged and recorded.

        Parameters
        ----------
        vertices : (n, 3) float
            Metres, in the camera's frame (x right, y down, z forward).
        faces : (m, 3) int
            Triangles (whole numbers; floats that are whole are accepted).
        colors : (n, 3) float in [0, 1], optional
            Per-vertex RGB (default grey).
        **kwargs
            The other fields of :class:`View` (``view_id``, ``pixels``, ...).

        Returns
        -------
        View
            The cleaned view; ``repairs`` lists what was changed.
        """
        name = kwargs.get("view_id") or "view"
        vertices = np.asarray(vertices, dtype=np.float64)
        raw_faces = np.asarray(faces)
        if raw_faces.dtype.kind == "f" and not np.all(raw_faces == np.round(raw_faces)):
            raise ViewError(
                f"{name}: faces must be whole vertex indices, got e.g. {raw_faces[raw_faces != np.round(raw_faces)][0]}"
            )
        if raw_faces.dtype.kind not in "iuf":
            raise ViewError(f"{name}: faces must be integer vertex indices, got {raw_faces.dtype}")
        faces = raw_faces.astype(np.int64)
        if vertices.ndim != 2 or vertices.shape[1] != 3:
            raise ViewError(f"{name}: vertices must be (n, 3), got {vertices.shape}")
        if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0:
            raise ViewError(f"{name}: faces must be a non-empty (m, 3) array, got {faces.shape}")
        if faces.min() < 0 or faces.max() >= len(vertices):
            raise ViewError(f"{name}: faces index vertices outside 0..{len(vertices) - 1}")
        if not np.all(np.isfinite(vertices)):
            bad = int((~np.isfinite(vertices)).any(axis=1).sum())
            raise ViewError(f"{name}: {bad} vertices have NaN or infinite coordinates")
        colors = np.full((len(vertices), 3), NO_COLOUR) if colors is None else np.asarray(colors, dtype=np.float64)
        if colors.shape != vertices.shape:
            raise ViewError(f"{name}: colors must be (n, 3) RGB for the {len(vertices)} vertices, got {colors.shape}")
        if not np.all(np.isfinite(colors)):
            bad = int((~np.isfinite(colors)).any(axis=1).sum())
            raise ViewError(f"{name}: {bad} vertices have NaN or infinite colours")
        if len(colors) and (colors.min() < 0 or colors.max() > 1):
            raise ViewError(
                f"{name}: colours are RGB in [0, 1], got {colors.min():g}..{colors.max():g}"
                + (" (8-bit colours: divide by 255)" if colors.max() <= 255 and colors.min() >= 0 else "")
            )
        if "intrinsics" in kwargs:  # a saved view's are untrusted too: fx < 0 mirrors its pixels
            kwargs["intrinsics"] = check_intrinsics(kwargs["intrinsics"], name=name)
        if "pose" in kwargs:
            pose = np.asarray(kwargs["pose"], dtype=np.float64)
            if pose.shape != (4, 4) or not np.all(np.isfinite(pose)):
                raise ViewError(f"{name}: pose must be a finite 4x4 camera-to-model transform, got shape {pose.shape}")
            kwargs["pose"] = pose
        repairs = list(kwargs.pop("repairs", []))
        unique, first, inverse = np.unique(vertices, axis=0, return_index=True, return_inverse=True)
        if len(unique) < len(vertices):
            message = f"merged {len(vertices) - len(unique)} duplicate vertices"
            log.warning("%s: %s", name, message)
            repairs.append(message)
            order = np.argsort(first)  # keep the original vertex order
            rank = np.empty_like(order)
            rank[order] = np.arange(len(order))
            faces = rank[inverse.ravel()][faces]
            vertices, colors = vertices[first[order]], colors[first[order]]
        degenerate = (faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 0] == faces[:, 2])
        if degenerate.any():
            message = f"dropped {int(degenerate.sum())} degenerate faces"
            log.warning("%s: %s", name, message)
            repairs.append(message)
            faces = faces[~degenerate]
        repeated = _repeated_faces(faces)
        if repeated.any():
            message = f"dropped {int(repeated.sum())} repeated faces"
            log.warning("%s: %s", name, message)
            repairs.append(message)
            faces = faces[~repeated]
        p = vertices[faces]
        area2 = np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
        flat = area2 <= ZERO_AREA * max(float(np.median(area2)), np.finfo(float).tiny)
        if flat.any():
            message = f"dropped {int(flat.sum())} zero-area faces (collinear vertices)"
            log.warning("%s: %s", name, message)
            repairs.append(message)
            faces = faces[~flat]
        if len(faces) == 0:
            raise ViewError(f"{name}: no face with a non-zero area")
        faces, flipped = consistent_winding(faces)
        if flipped:
            message = f"reversed {flipped} faces whose winding disagreed with their neighbours'"
            log.warning("%s: %s", name, message)
            repairs.append(message)
        used = np.zeros(len(vertices), bool)
        used[faces.ravel()] = True
        if not used.all():
            message = f"dropped {int((~used).sum())} vertices in no face"
            log.debug("%s: %s", name, message)
            repairs.append(message)
            vertices, colors, faces = _compact(vertices, colors, faces, used)
        view = cls(vertices=vertices, faces=faces, colors=colors, repairs=repairs, **kwargs)
        view.check_size()
        return view

    def to_ply(self, path: StrPath) -> None:
        """Write the view as a binary PLY with vertex colours (MeshLab, Open3D and PCL open it), camera frame.

        Parameters
        ----------
        path : str or Path
            The ``.ply`` to write.
        """
        with atomic(path) as temporary:
            self._write_ply(temporary)

    def _write_ply(self, path: Path) -> None:
        import trimesh

        colors = np.round(np.clip(self.colors, 0.0, 1.0) * 255).astype(np.uint8)
        trimesh.Trimesh(self.vertices, self.faces, vertex_colors=colors, process=False).export(path, file_type="ply")

    def write(self, paths: Sequence[StrPath]) -> None:
        """Write the view to several files at once, each a ``.npz`` (:meth:`save`) or a ``.ply`` (:meth:`to_ply`).

        They are written as one unit (:func:`heatdata.io.files.atomic_group`): another command writing the same
        files leaves its whole set or this one's, and an interrupted write leaves none.

        Parameters
        ----------
        paths : sequence of str or Path
            Files ending in ``.npz`` or ``.ply``.
        """
        writers = {".npz": self._write_npz, ".ply": self._write_ply}
        for path in paths:
            if Path(path).suffix.lower() not in writers:
                raise OutputError(f"{path}: a view is written to a .npz or .ply file")
        with atomic_group(paths) as temporaries:
            for path, temporary in zip(paths, temporaries):
                writers[Path(path).suffix.lower()](temporary)

    def save(self, path: StrPath) -> None:
        """Write the view to a ``.npz`` file (arrays plus identifiers and intrinsics).

        Parameters
        ----------
        path : str or Path
            The ``.npz`` to write.
        """
        if Path(path).suffix != ".npz":
            raise OutputError(f"{path}: a view is saved to a .npz file")
        with atomic(path) as temporary:
            self._write_npz(temporary)

    def _write_npz(self, path: Path) -> None:
        np.savez_compressed(
            path,
            vertices=self.vertices,
            faces=self.faces,
            colors=self.colors,
            pose=self.pose,
            angle=np.array([self.azimuth, self.elevation, self.distance]),
            intrinsics=np.array(json.dumps(self.intrinsics)),
            ids=np.array([self.view_id, self.object_id, self.label]),
            repairs=np.array(json.dumps(self.repairs)),
        )

    @classmethod
    def load(cls, path: StrPath) -> View:
        """Read a view written by :meth:`save`.

        Parameters
        ----------
        path : str or Path
            An ``.npz`` of :meth:`save`.

        Returns
        -------
        View
        """
        require_file(path, "view file", ViewError)
        if not zipfile.is_zipfile(path):
            raise ViewError(
                f"{path}: not a readable .npz view file (not a zip archive: truncated, or not written by "
                "heatdata render)"
            )
        _check_array_sizes(path)
        try:
            with np.load(path, allow_pickle=False) as data:
                arrays = {key: np.array(data[key]) for key in VIEW_ARRAYS}
            view_id, object_id, label = (str(x) for x in arrays["ids"])
            azimuth, elevation, distance = (float(x) for x in arrays["angle"])
            intrinsics, repairs = json.loads(str(arrays["intrinsics"])), json.loads(str(arrays["repairs"]))
            if not isinstance(intrinsics, dict) or not isinstance(repairs, list):
                raise ValueError("its intrinsics are not a mapping or its repairs not a list")
        except Exception as exc:  # numpy and zipfile raise many kinds on a damaged archive (zlib.error, ...)
            raise ViewError(f"{path}: not a readable heatdata view ({type(exc).__name__}: {exc})") from None
        return cls.from_arrays(
            arrays["vertices"],
            arrays["faces"],
            arrays["colors"],
            intrinsics=intrinsics,
            view_id=view_id,
            object_id=object_id,
            label=label,
            azimuth=azimuth,
            elevation=elevation,
            distance=distance,
            pose=arrays["pose"],
            repairs=[str(r) for r in repairs],
        )

    # -- structure ---------------------------------------------------------------

    @property
    def n_vertices(self) -> int:
        return len(self.vertices)

    def check_size(self) -> None:
        """Raise :class:`ViewError` if the view has fewer than ``MIN_VERTICES`` vertices."""
        if self.n_vertices < MIN_VERTICES:
            raise ViewError(f"{self.name}: only {self.n_vertices} vertices (at least {MIN_VERTICES} needed)")

    @property
    def name(self) -> str:
        return self.view_id or self.object_id or "view"

    @cached_property
    def edges(self) -> np.ndarray:
        """(e, 2) int64: unique undirected mesh edges, ``i < j``."""
        return mesh_edges(self.faces, self.n_vertices)

    @cached_property
    def component_labels(self) -> np.ndarray:
        """(n,) int: connected-component index of each vertex."""
        return component_labels(self.edges, self.n_vertices)

    @property
    def n_components(self) -> int:
        return int(self.component_labels.max()) + 1

    def submesh(self, keep: np.ndarray, reason: str) -> View:
        """A copy keeping the vertices where ``keep`` is true (and faces among them).

        The repair ``reason`` is logged and recorded in the copy's ``repairs``.

        Parameters
        ----------
        keep : (n,) bool
            The vertices to keep; faces with every corner kept stay.
        reason : str
            A note for ``repairs`` (why vertices were dropped).

        Returns
        -------
        View
            The kept part, its pixels and colours with it.
        """
        keep = np.asarray(keep, bool)
        face_keep = keep[self.faces].all(axis=1)
        vertices, colors, faces = _compact(self.vertices, self.colors, self.faces[face_keep], keep)
        log.info("%s: %s", self.name, reason)
        view = View(
            vertices=vertices,
            faces=faces,
            colors=colors,
            intrinsics=self.intrinsics,
            view_id=self.view_id,
            object_id=self.object_id,
            label=self.label,
            azimuth=self.azimuth,
            elevation=self.elevation,
            distance=self.distance,
            pose=self.pose,
            repairs=[*self.repairs, reason],
        )
        view.check_size()
        return view

    def largest_component(self) -> View:
        """The view itself if connected, else its largest connected component (a repair).

        Returns
        -------
        View
            The connected component with the most vertices (the view itself if it has one).
        """
        if self.n_components == 1:
            return self
        sizes = np.bincount(self.component_labels)
        keep = self.component_labels == np.argmax(sizes)
        return self.submesh(
            keep, f"kept the largest of {len(sizes)} components ({int(keep.sum())} of {self.n_vertices} vertices)"
        )

    def component_of(self, vertex: int) -> tuple[View, int]:
        """The connected component containing ``vertex``, and that vertex's new index.

        Parameters
        ----------
        vertex : int
            A vertex of the view.

        Returns
        -------
        component : View
            The connected component that holds it.
        index : int
            ``vertex``'s index in it.
        """
        if self.n_components == 1:
            return self, vertex
        keep = self.component_labels == self.component_labels[vertex]
        sub = self.submesh(
            keep,
            f"kept the component of vertex {vertex} "
            f"({int(keep.sum())} of {self.n_vertices} vertices, "
            f"{self.n_components} components)",
        )
        return sub, int(np.cumsum(keep)[vertex] - 1)

    # -- image-plane geometry ------------------------------------------------------

    @cached_property
    def pixels(self) -> np.ndarray:
        """(n, 2) float64: image coordinates (u right, v down) of the vertices."""
        k = self.intrinsics
        z = self.vertices[:, 2]
        if np.any(z <= 0):
            raise ViewError(f"{self.name}: vertices behind the camera (z <= 0)")
        return np.column_stack(
            [k["fx"] * self.vertices[:, 0] / z + k["cx"], k["fy"] * self.vertices[:, 1] / z + k["cy"]]
        )

    @cached_property
    def canonical_rotation(self) -> np.ndarray:
        """(3, 3) float64: the rotation about the optical centre that turns the camera to face the segment.

        Eq. 2.8 and 2.3.3 take the source and the boundary's frame at "the centre of the segmented depth image"; a
        view is described as if the camera looked straight at it. ``R`` is the smallest rotation taking a direction
        ``d`` onto the optical axis (+z) such that, in the turned frame (``canonical_vertices = vertices @ R.T``),
        the bounding box of the segment's image is centred on the axis: a fixed point, found from the ray through
        the image bounding box's centre in a few steps. An object anywhere in the frame is then described as it
        is at the image centre: panning or tilting the camera turns ``R`` with it (to within the sliver of roll two
        smallest rotations leave; rolling the camera about its axis turns the image box, as it turns the boundary's
        origin of 2.3.3). Of the segment centres measured (the points' centroid, the mean pixel, the 3D box of the
        points, the image box), the image box gave the most stable ``"center"`` source (the recognition chapter's
        page).
        """
        x = self.vertices
        if np.any(x[:, 2] <= 0):
            raise ViewError(f"{self.name}: vertices behind the camera (z <= 0)")
        x = x[_image_hull(x)]  # the box's sides lie on these in any turned frame: the same box, ~100 points
        k = self.intrinsics
        scale = np.array([k["fx"], k["fy"]])
        axis = np.array([0.0, 0.0, 1.0])
        direction, rotation = axis, np.eye(3)
        for _ in range(CANONICAL_STEPS):
            turned = x @ rotation.T
            image = scale * turned[:, :2] / turned[:, 2:]
            centre = (image.min(axis=0) + image.max(axis=0)) / 2
            if np.hypot(*centre) < CANONICAL_PIXELS:
                break
            direction = rotation.T @ np.append(centre / scale, 1.0)
            rotation = rotation_between(direction, axis)
        return rotation

    @cached_property
    def canonical_vertices(self) -> np.ndarray:
        """(n, 3) float64: the vertices in the camera frame turned to face the segment (:attr:`canonical_rotation`)."""
        return self.vertices @ self.canonical_rotation.T

    @cached_property
    def planar(self) -> np.ndarray:
        """(n, 2) float64: the image-centred frame of 2.3.3 (Fig. 2.6), x right and y up, in pixels.

        The vertices are projected by the view's focal lengths in the canonical frame
        (:attr:`canonical_rotation`) and centred on their mean, so the frame does not depend on where the
        object stands in the image.
        """
        x = self.canonical_vertices
        if np.any(x[:, 2] <= 0):
            raise ViewError(f"{self.name}: vertices behind the camera (z <= 0)")
        k = self.intrinsics
        d = np.column_stack([k["fx"] * x[:, 0] / x[:, 2], k["fy"] * x[:, 1] / x[:, 2]])
        d -= d.mean(axis=0)
        return np.column_stack([d[:, 0], -d[:, 1]])

    @cached_property
    def boundary(self) -> np.ndarray:
        """(b,) int64: the outer boundary loop, counter-clockwise, origin on the +x axis."""
        return _outer_boundary(self)


def _repeated_faces(faces: np.ndarray) -> np.ndarray:
    """(m,) bool: faces on the same three vertices as an earlier face (in either winding)."""
    corners = np.sort(faces, axis=1)
    order = np.lexsort(corners.T[::-1])  # stable: the first of equal faces comes first
    ranked = corners[order]
    repeated = np.zeros(len(faces), bool)
    repeated[order[1:]] = (ranked[1:] == ranked[:-1]).all(axis=1)
    return repeated


def _compact(vertices, colors, faces, keep):
    index = np.full(len(vertices), -1, np.int64)
    index[keep] = np.arange(int(keep.sum()))
    return vertices[keep], colors[keep], index[faces]


def _signed_area(points: np.ndarray) -> float:
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _image_hull(points: np.ndarray) -> np.ndarray:
    """Indices of the points whose rays span the convex hull of the image (all of them when it is flat).

    Turning the camera about its centre maps the image by a homography; for points in front of the camera before
    and after the turn it maps the hull of their image to the hull of the turned image, so the turned image's
    bounding box is that of these points (:attr:`View.canonical_rotation`).
    """
    from scipy.spatial import ConvexHull, QhullError

    try:
        return ConvexHull(points[:, :2] / points[:, 2:]).vertices
    except (QhullError, ValueError):  # fewer than three points, or all on one line
        return np.arange(len(points))


def _outer_boundary(view: View) -> np.ndarray:
    planar = view.planar
    loops = [loop for loop in boundary_loops(view.faces, planar) if len(loop) >= 3]
    if not loops:
        raise ViewError(f"{view.name}: the mesh has no boundary (a closed surface is not a partial view)")
    areas = [_signed_area(planar[loop]) for loop in loops]
    best = int(np.argmax(np.abs(areas)))
    loop = loops[best]
    if areas[best] < 0:
        loop = loop[::-1]
    # origin: the outermost crossing of the +x axis, going counter-clockwise (angle 0)
    p = planar[loop]
    q = np.roll(p, -1, axis=0)
    crosses = (p[:, 1] < 0) & (q[:, 1] >= 0)
    if crosses.any():
        idx = np.flatnonzero(crosses)
        x_at = p[idx, 0] + (q[idx, 0] - p[idx, 0]) * (-p[idx, 1]) / (q[idx, 1] - p[idx, 1])
        start = (idx[np.argmax(x_at)] + 1) % len(loop)
    else:  # the centre is outside the loop: start at the vertex nearest to angle 0
        start = int(np.argmin(np.abs(np.arctan2(p[:, 1], p[:, 0]))))
    return np.roll(loop, -start)


def joined_view(first: View, second: View) -> View:
    """Two views of one camera as one (their meshes side by side, no face across them): two segments of a frame
    that may be one object.

    Parameters
    ----------
    first, second : View
        Camera-frame views with the same intrinsics.

    Returns
    -------
    View
        ``first``'s fields, the vertices, faces and colours of both.
    """
    if first.intrinsics != second.intrinsics:
        raise ViewError(f"{first.view_id} and {second.view_id}: views of two cameras cannot be joined")
    return View.from_arrays(
        np.vstack([first.vertices, second.vertices]),
        np.vstack([first.faces, second.faces + len(first.vertices)]),
        np.vstack([first.colors, second.colors]),
        intrinsics=dict(first.intrinsics),
        view_id=f"{first.view_id}+{second.view_id}",
    )
