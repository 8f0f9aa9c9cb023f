"""3D models: loading OBJ/MTL/textures, PLY, STL, OFF and GLB into one in-memory form.

A :class:`Model` is a triangle mesh in metres with everything the renderer needs to
colour a ray hit: per-face-corner colours for untextured faces and per-face-corner
texture coordinates plus texture images for textured ones. Files are parsed with
trimesh; this module only gathers its scene graph into flat arrays and scales the
result to real size (thesis 2.1: partial views are measured in the sensor's metres).

The model frame is the file's own, with +y up (the OBJ and Sweet Home 3D convention).
"""

from __future__ import annotations

import io
import logging
import re
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
import PIL.Image
import trimesh
from numpy.typing import ArrayLike

from heatdata.core.mesh import merged_vertices
from heatdata.errors import ModelError, StitchError
from heatdata.io.files import atomic, require_file

log = logging.getLogger(__name__)

SUPPORTED_SUFFIXES = (".obj", ".ply", ".stl", ".off", ".glb", ".gltf")
DEFAULT_GREY = (0.7, 0.7, 0.7)
IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".gif", ".tga", ".tif", ".tiff", ".webp")
MAX_FILE_BYTES = 256 * 2**20  # a model file, or a file it names (MTL, texture, glTF buffer)
TEXTURE_PIXELS = 2048 * 2048  # larger textures are downscaled: a view samples them at Kinect resolution
MAX_TEXTURE_PIXELS = 4096 * 4096  # larger ones are refused before they are decoded (the material's colour stands)
MAX_MODEL_TEXTURE_PIXELS = 4 * MAX_TEXTURE_PIXELS  # all of a model's textures together (each material decodes its own)
LARGE_MODEL = 20.0  # metres: a model larger than this, with no size given, is probably not in metres


@dataclass
class Model:
    """A coloured triangle mesh in metres.

    Attributes
    ----------
    name : str
        Object identifier (stable string).
    vertices : (n, 3) float64
        Vertex positions in metres, model frame (+y up).
    faces : (m, 3) int64
        Triangles as vertex indices.
    corner_colors : (m, 3, 3) float32
        RGB in [0, 1] at each corner of each face; used where a face has no texture.
    corner_uv : (m, 3, 2) float32
        Texture coordinates at each face corner (meaningful where ``face_texture >= 0``).
    face_texture : (m,) int32
        Index into ``textures`` per face, -1 for untextured faces.
    textures : list of (h, w, 3) float32
        Texture images, RGB in [0, 1], row 0 at the top of the image.
    label : str
        Object class (e.g. ``"mug"``).
    source : str
        The file the model was read from.
    repairs : list of str
        What loading could not use, e.g. a texture that is missing or outside the model's
        folder (the Kd colour stands in); every view rendered from the model carries them.
    """

    name: str
    vertices: np.ndarray
    faces: np.ndarray
    corner_colors: np.ndarray
    corner_uv: np.ndarray
    face_texture: np.ndarray
    textures: list = field(default_factory=list)
    label: str = ""
    source: str = ""
    repairs: list = field(default_factory=list)

    def __post_init__(self) -> None:
        self.faces = checked_faces(self.faces, len(self.vertices), self.name)

    @classmethod
    def untextured(
        cls,
        name: str,
        vertices: np.ndarray,
        faces: np.ndarray,
        colors: ArrayLike = DEFAULT_GREY,
        **fields: Any,
    ) -> Model:
        """A model without textures: ``colors`` one RGB for every face, or (m, 3, 3) per face corner; ``fields``:

        the other attributes (``label``, ``source``, ...).

        Parameters
        ----------
        name : str
            The model's name.
        vertices : (n, 3) float
            Metres.
        faces : (m, 3) int
            Triangles.
        colors : (3,) or (m, 3, 3) float in [0, 1]
            One RGB for every face, or one per face corner.
        **fields
            The other attributes (``label``, ``source``, ...).

        Returns
        -------
        Model
            With no texture and the given corner colours.
        """
        faces = np.asarray(faces, np.int64)
        corner_colors = np.broadcast_to(np.asarray(colors, np.float32), (len(faces), 3, 3)).copy()
        return cls(
            name=name,
            vertices=np.asarray(vertices, np.float64),
            faces=faces,
            corner_colors=corner_colors,
            corner_uv=np.zeros((len(faces), 3, 2), np.float32),
            face_texture=np.full(len(faces), -1, np.int32),
            **fields,
        )

    @property
    def coloured(self) -> bool:
        """Whether the file gave the model colour: a texture, or a colour other than the :data:`DEFAULT_GREY` a
        geometry-only file (a scanned mesh, most CAD exports) gets. Its views are then all that grey, and a library
        compares no frame's colour with them."""
        return bool(self.textures) or bool(np.any(self.corner_colors != np.float32(DEFAULT_GREY[0])))

    @property
    def extents(self) -> np.ndarray:
        """(3,) float64: bounding-box size along x, y, z in metres."""
        return self.vertices.max(axis=0) - self.vertices.min(axis=0)

    @property
    def center(self) -> np.ndarray:
        """(3,) float64: bounding-box centre."""
        return 0.5 * (self.vertices.max(axis=0) + self.vertices.min(axis=0))


def _texture_size_note(name: str, size: tuple[int, int]) -> str | None:
    """Why a texture of ``size`` (w, h) pixels is refused before it is decoded, or None."""
    if size[0] * size[1] > MAX_TEXTURE_PIXELS:
        return (
            f"refused texture {name!r}: {size[0]}x{size[1]} pixels, above the cap of "
            f"{MAX_TEXTURE_PIXELS / 1e6:.0f} Mpixel"
        )
    return None


def _image_to_array(image, notes: list[str]) -> np.ndarray | None:
    """A texture as (h, w, 3) float32 in [0, 1], downscaled to at most ``TEXTURE_PIXELS``; None (with a note in
    ``notes``) when it is refused or cannot be decoded."""
    if image is None:
        return None
    name = getattr(image, "filename", "") or "embedded image"
    refused = _texture_size_note(name, image.size)
    if refused:
        notes.append(f"{refused}; the material's colour is used instead")
        return None
    try:
        if image.size[0] * image.size[1] > TEXTURE_PIXELS:
            factor = int(np.ceil(np.sqrt(image.size[0] * image.size[1] / TEXTURE_PIXELS)))
            notes.append(f"texture {name!r} of {image.size[0]}x{image.size[1]} pixels downscaled {factor}x")
            image = image.convert("RGB").reduce(factor)
        array = np.asarray(image.convert("RGB"), dtype=np.float32) / 255.0
    except (OSError, ValueError, SyntaxError) as error:  # Pillow's errors on a corrupt image
        notes.append(f"cannot decode texture {name!r} ({error}); the material's colour is used instead")
        return None
    return array if array.size else None


def _material_color_and_texture(visual, notes: list[str]) -> tuple[np.ndarray, np.ndarray | None]:
    """Base RGB colour and texture image of a trimesh TextureVisuals material (what is refused goes to ``notes``)."""
    material = getattr(visual, "material", None)
    if material is None:
        return np.array(DEFAULT_GREY), None
    if isinstance(material, trimesh.visual.material.PBRMaterial):
        factor = material.baseColorFactor
        color = np.asarray(factor[:3], float) / 255.0 if factor is not None else np.array(DEFAULT_GREY)
        return color, _image_to_array(material.baseColorTexture, notes)
    diffuse = getattr(material, "diffuse", None)
    color = np.asarray(diffuse[:3], float) / 255.0 if diffuse is not None else np.array(DEFAULT_GREY)
    return color, _image_to_array(getattr(material, "image", None), notes)


class _FolderResolver(trimesh.resolvers.FilePathResolver):
    """trimesh's file resolver, confined to the model's folder: a model file, its MTL and texture names
    are untrusted input, so a name that leads outside the folder (``../``, an absolute path, a link)
    is refused, and every refused or missing file is noted for the model's repairs."""

    def __init__(self, path: Path):
        super().__init__(str(path))
        self.root = Path(self.parent).resolve()
        self.notes: list[str] = []
        self.pixels = 0  # of the textures served so far

    def get(self, name: str):
        clean = name.strip()
        try:
            target = (self.root / clean).resolve()
        except (ValueError, OSError) as error:  # a NUL byte, a loop of links
            return self._refuse(f"refused {clean!r}: not a file name ({error})")
        if not target.is_relative_to(self.root):
            return self._refuse(f"refused {clean!r}: it is outside the model's folder")
        if not target.is_file():
            return self._refuse(f"missing {clean!r} in the model's folder")
        if target.stat().st_size > MAX_FILE_BYTES:
            return self._refuse(f"refused {clean!r}: {target.stat().st_size / 2**20:.0f} MB, above the cap")
        data = target.read_bytes()
        if target.suffix.lower() in IMAGE_SUFFIXES:  # checked before trimesh decodes it
            try:
                with PIL.Image.open(io.BytesIO(data)) as image:
                    refused = _texture_size_note(clean, image.size)
                    if not refused and self.pixels + image.size[0] * image.size[1] > MAX_MODEL_TEXTURE_PIXELS:
                        refused = (
                            f"refused texture {clean!r}: the model's textures would exceed "
                            f"{MAX_MODEL_TEXTURE_PIXELS / 1e6:.0f} Mpixel together"
                        )
                    if not refused:
                        image.load()  # decoded once here: trimesh decodes it again, unguarded, when it copies
                        self.pixels += image.size[0] * image.size[1]
            except (OSError, ValueError, SyntaxError, PIL.Image.DecompressionBombError) as error:
                return self._refuse(f"cannot read texture {clean!r} ({error})")
            if refused:
                return self._refuse(refused)
        return data

    def _refuse(self, note: str):
        self.notes.append(note)
        raise OSError(note)


def _drop_oversized_images(scene: trimesh.Scene) -> list[str]:
    """Drop the images embedded in the file (a GLB's) above ``MAX_TEXTURE_PIXELS`` before anything decodes them
    (trimesh decodes every material's images when it flattens the scene); what was dropped, as notes."""
    notes = []
    for geometry in scene.geometry.values():
        material = getattr(getattr(geometry, "visual", None), "material", None)
        if material is None:
            continue
        stores = [vars(material), getattr(material, "_data", None)]  # a PBR material keeps its images in _data
        for store in (s for s in stores if isinstance(s, dict)):
            for key, value in list(store.items()):
                refused = isinstance(value, PIL.Image.Image) and _texture_size_note(f"embedded {key}", value.size)
                if refused:
                    store[key] = None
                    notes.append(refused)
    return notes


#: an OBJ face's index 0 (OBJ counts from 1): a token ``0`` of a face line, alone or between slashes
OBJ_ZERO_INDEX = re.compile(rb"(?m)^[ \t]*f[ \t][^\n]*?(?<![\w.+-])0(?![\w.])")


def _check_obj_indices(path: Path) -> None:
    """Refuse an OBJ with a face index 0, which trimesh would read as the last vertex (OBJ counts from 1)."""
    found = OBJ_ZERO_INDEX.search(path.read_bytes())
    if found:
        line = found.string.count(b"\n", 0, found.start()) + 1
        raise ModelError(f"{path}: line {line}: a face index 0 (OBJ counts vertices from 1)")


def _read_scene(path: Path) -> tuple[trimesh.Scene, list[str]]:
    """The file's scene and what its resolver refused or missed (MTL, textures)."""
    if path.suffix.lower() == ".obj":
        _check_obj_indices(path)
    resolver = _FolderResolver(path)
    try:
        loaded = trimesh.load(str(path), force="scene", process=False, resolver=resolver)
    except Exception as exc:  # trimesh raises many types on corrupt input
        raise ModelError(f"{path}: cannot read the model file ({type(exc).__name__}: {exc})") from exc
    refused = resolver.notes + _drop_oversized_images(loaded)
    notes = [f"{path.name}: {note}; the material's colour is used instead" for note in dict.fromkeys(refused)]
    for note in notes:
        log.warning("%s", note)
    return loaded, notes


def load_model(
    path: str | Path,
    *,
    size: tuple[float, float, float] | None = None,
    scale: float = 1.0,
    rotation: np.ndarray | None = None,
    up_axis: str = "y",
    name: str | None = None,
    label: str = "",
    center: bool = True,
) -> Model:
    """Load a mesh file into a :class:`Model` in metres.

    Parameters
    ----------
    path : str or Path
        An OBJ (with MTL and textures), PLY, STL, OFF, GLB or glTF file.
    size : (3,) float, optional
        Real size (width along x, height along y, depth along z) in metres. The mesh is
        scaled per axis to this bounding box, as Sweet Home 3D does with its catalogue sizes
        (an axis along which the mesh is flat stays flat).
    scale : float
        Uniform factor from file units to metres, used when ``size`` is not given.
    rotation : (3, 3) float, optional
        Rotation applied before scaling (a Sweet Home 3D ``modelRotation``), after the turn to y up.
    up_axis : {"y", "z"}
        The file's up axis. heatdata's models stand on y; a z-up file (YCB, BOP and most CAD and scanner files) is
        turned by :data:`Z_UP_TO_Y_UP` first. A y-up model that looks lying on its side (taller along z than along y
        and x) is warned about.
    name, label : str
        Object identifier (default: the file stem) and class.
    center : bool
        Move the bounding box's centre to the origin (default). False keeps the file's
        frame (scaled), e.g. for scans whose frames are registered to each other.

    Returns
    -------
    Model

    Raises
    ------
    ModelError
        The file does not exist, is of an unsupported type, cannot be parsed, or holds no
        triangle.
    """
    path = Path(path)
    if size is not None and (np.shape(size) != (3,) or not np.all(np.isfinite(size)) or np.any(np.asarray(size) < 0)):
        raise ModelError(
            f"{path}: size must be three finite lengths >= 0 in metres (a negative one mirrors the model), got {size}"
        )
    if not (np.isfinite(scale) and scale > 0):
        raise ModelError(f"{path}: scale must be a positive number, got {scale}")
    if up_axis not in UP_AXES:
        raise ModelError(f"{path}: up_axis must be one of {', '.join(UP_AXES)}, got {up_axis!r}")
    if rotation is not None:
        rotation = _checked_rotation(rotation, path)
    require_file(path, "model file", ModelError)
    if path.suffix.lower() not in SUPPORTED_SUFFIXES:
        raise ModelError(f"{path}: unsupported model type {path.suffix!r} (use one of {', '.join(SUPPORTED_SUFFIXES)})")
    if path.stat().st_size == 0:
        raise ModelError(f"{path}: the model file is empty")
    if path.stat().st_size > MAX_FILE_BYTES:
        raise ModelError(f"{path}: {path.stat().st_size / 2**20:.0f} MB, above the cap of {MAX_FILE_BYTES >> 20} MB")
    scene, repairs = _read_scene(path)
    try:
        parts_of_scene = scene.dump(concatenate=False)
    except Exception as exc:  # trimesh decodes embedded images and applies transforms here
        raise ModelError(f"{path}: cannot read the model file ({type(exc).__name__}: {exc})") from exc
    meshes = [g for g in parts_of_scene if isinstance(g, trimesh.Trimesh) and len(g.faces)]
    if not meshes:
        raise ModelError(f"{path}: the model has no triangle faces")

    parts: list[np.ndarray] = []
    faces, colors, uvs, face_tex, textures = [], [], [], [], []
    offset = 0
    texture_notes: list[str] = []
    for mesh in meshes:
        v = np.asarray(mesh.vertices, dtype=np.float64)
        f = checked_faces(mesh.faces, len(v), str(path))
        n_faces = len(f)
        corner_uv = np.zeros((n_faces, 3, 2), np.float32)
        tex_index = -1
        visual = mesh.visual
        if isinstance(visual, trimesh.visual.texture.TextureVisuals):
            color, image = _material_color_and_texture(visual, texture_notes)
            corner = np.broadcast_to(color.astype(np.float32), (n_faces, 3, 3))
            if image is not None and visual.uv is not None and len(visual.uv) == len(v):
                textures.append(image)
                tex_index = len(textures) - 1
                corner_uv = np.asarray(visual.uv, np.float32)[f]
        elif isinstance(visual, trimesh.visual.color.ColorVisuals) and visual.kind == "vertex":
            corner = (np.asarray(visual.vertex_colors, np.float32)[:, :3] / 255.0)[f]
        elif isinstance(visual, trimesh.visual.color.ColorVisuals) and visual.kind == "face":
            rgb = np.asarray(visual.face_colors, np.float32)[:, :3] / 255.0
            corner = np.repeat(rgb[:, None, :], 3, axis=1)
        else:
            corner = np.broadcast_to(np.array(DEFAULT_GREY, np.float32), (n_faces, 3, 3))
        parts.append(v)
        faces.append(f + offset)
        colors.append(np.array(corner, np.float32))
        uvs.append(corner_uv)
        face_tex.append(np.full(n_faces, tex_index, np.int32))
        offset += len(v)

    vertices = np.concatenate(parts)
    if not np.all(np.isfinite(vertices)):
        raise ModelError(f"{path}: the model has NaN or infinite vertex coordinates")
    _check_complete(path, len(vertices), sum(len(f) for f in faces))
    for note in dict.fromkeys(texture_notes):
        repairs.append(f"{path.name}: {note}")
        log.warning("%s", repairs[-1])
    vertices = vertices @ UP_AXES[up_axis].T
    if rotation is not None:
        vertices = vertices @ rotation.T
    if up_axis == "y":
        _warn_if_lying(vertices, path)
    if center:
        vertices = vertices - 0.5 * (vertices.max(axis=0) + vertices.min(axis=0))
    extents = vertices.max(axis=0) - vertices.min(axis=0)
    if size is not None:
        flat = extents <= 0  # a flat model keeps zero thickness; its other axes are scaled
        collapsed = [axis for axis, s, e in zip("xyz", size, extents) if s == 0 and e > 0]
        if collapsed:
            raise ModelError(
                f"{path}: size 0 along {', '.join(collapsed)} would flatten a model that has thickness there "
                f"(extents {np.round(extents, 4).tolist()} in file units)"
            )
        vertices = vertices * np.where(flat, 1.0, np.asarray(size, float) / np.where(flat, 1.0, extents))
    else:
        vertices = vertices * scale
        if extents.max() * scale > LARGE_MODEL:
            log.warning(
                "%s: the model is %.0f m across: if its file is in millimetres or centimetres, give a scale "
                "(0.001 or 0.01; heatdata render --scale) or its real size (--size)",
                path,
                extents.max() * scale,
            )
    model = Model(
        name=name or path.stem,
        vertices=vertices,
        faces=np.concatenate(faces),
        corner_colors=np.concatenate(colors),
        corner_uv=np.concatenate(uvs),
        face_texture=np.concatenate(face_tex),
        textures=textures,
        label=label,
        source=str(path),
        repairs=repairs,
    )
    log.debug(
        "loaded %s: %d vertices, %d faces, %d textures, extents %s m",
        path,
        len(model.vertices),
        len(model.faces),
        len(textures),
        np.round(model.extents, 3),
    )
    return model


def checked_faces(faces: ArrayLike, n_vertices: int, name: str) -> np.ndarray:
    """``faces`` as (m, 3) int64 indices into ``n_vertices`` vertices, or a :class:`ModelError` naming ``name``.

    Every model passes here before native code (open3d's ray caster takes the indices as uint32 and does not
    check them).

    Parameters
    ----------
    faces : (m, 3) int
        Triangles.
    n_vertices : int
        How many vertices they index.
    name : str
        The file or model, for the message.

    Returns
    -------
    (m, 3) int64
        The faces.

    Raises
    ------
    ModelError
        Not (m, 3) whole numbers, or an index that is negative or not below ``n_vertices``.
    """
    array = np.asarray(faces)
    if array.ndim != 2 or array.shape[1] != 3 or (len(array) and array.dtype.kind not in "iu"):
        raise ModelError(f"{name}: faces must be (m, 3) vertex indices, got shape {array.shape} of {array.dtype}")
    array = array.astype(np.int64)
    if len(array) and (array.min() < 0 or array.max() >= n_vertices):
        outside = (array < 0) | (array >= n_vertices)
        raise ModelError(
            f"{name}: {int(outside.any(axis=1).sum())} faces index vertices outside 0..{n_vertices - 1} "
            f"(e.g. {array[outside][0]})"
        )
    return array


#: the turn that stands a z-up file on heatdata's y: (x, y, z) -> (x, z, -y), a rotation (no mirror)
Z_UP_TO_Y_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
UP_AXES = {"y": np.eye(3), "z": Z_UP_TO_Y_UP}
#: a y-up model this many times longer along z than along x and y looks like a z-up file lying down
LYING_RATIO = 1.5


def _warn_if_lying(vertices: np.ndarray, path: Path) -> None:
    """Warn where a model read as y-up is :data:`LYING_RATIO` times longer along z than along x and y: a tall z-up
    file (a bottle, a can) read without ``up_axis: z`` lies on its side in every view."""
    extents = vertices.max(axis=0) - vertices.min(axis=0)
    if extents[2] > LYING_RATIO * max(extents[0], extents[1]):
        log.warning(
            "%s: the model is %.3g along z and %.3g along y (up): if its file is z-up, as YCB, BOP and most CAD "
            "files are, give up_axis z (heatdata render --up-axis z), or it lies on its side in every view",
            path,
            extents[2],
            extents[1],
        )


def _checked_rotation(rotation: ArrayLike, path: Path) -> np.ndarray:
    r = np.asarray(rotation, np.float64)
    if (
        r.shape != (3, 3)
        or not np.all(np.isfinite(r))
        or not np.allclose(r @ r.T, np.eye(3), atol=1e-3)
        or np.linalg.det(r) < 0
    ):
        raise ModelError(
            f"{path}: rotation must be a 3x3 rotation matrix (finite, orthonormal, no reflection), got "
            f"{np.round(r, 4).tolist() if r.size <= 9 else r.shape}"
        )
    return r


def _check_complete(path: Path, n_vertices: int, n_faces: int) -> None:
    """Refuse an ASCII OFF or PLY holding fewer vertices or faces than its header declares (a truncated file)."""
    suffix = path.suffix.lower()
    if suffix not in (".off", ".ply"):
        return  # binary PLY, GLB and STL truncations are refused by trimesh; OBJ declares no counts
    with path.open("rb") as handle:
        head = handle.read(4096).decode("latin-1", "replace")
    declared = None
    if suffix == ".off":
        words = [w for line in head.splitlines() if not line.lstrip().startswith("#") for w in line.split()]
        if words and words[0].upper().endswith("OFF") and len(words) >= 3 and words[1].isdigit() and words[2].isdigit():
            declared = int(words[1]), int(words[2])
    elif "format ascii" in head:
        vertex = re.search(r"^element vertex (\d+)", head, re.M)
        face = re.search(r"^element face (\d+)", head, re.M)
        declared = int(vertex.group(1)) if vertex else 0, int(face.group(1)) if face else 0
    if declared and (n_vertices < declared[0] or n_faces < declared[1]):
        raise ModelError(
            f"{path}: truncated: its header declares {declared[0]:,} vertices and {declared[1]:,} faces, "
            f"the file holds {n_vertices:,} and {n_faces:,}"
        )


def vertex_colors(model: Model) -> np.ndarray:
    """(n, 3) RGB per vertex: the mean colour of its face corners (textured corners sample their texture)."""
    colors = np.array(model.corner_colors, dtype=np.float64)
    for t, image in enumerate(model.textures):
        faces = np.flatnonzero(model.face_texture == t)
        if len(faces):
            uv = model.corner_uv[faces].reshape(-1, 2) % 1.0
            h, w = image.shape[:2]
            px = np.clip((uv[:, 0] * w).astype(int), 0, w - 1)
            py = np.clip(((1.0 - uv[:, 1]) * h).astype(int), 0, h - 1)
            colors[faces] = image[py, px].reshape(len(faces), 3, 3)
    total = np.zeros((len(model.vertices), 3))
    count = np.zeros(len(model.vertices))
    np.add.at(total, model.faces.ravel(), colors.reshape(-1, 3))
    np.add.at(count, model.faces.ravel(), 1.0)
    return total / np.maximum(count, 1.0)[:, None]


def hue_rotated(model: Model, degrees: float, name: str | None = None) -> Model:
    """A colour twin of ``model``: the same mesh, its colours and textures turned by ``degrees`` around the hue

    circle (saturation and value kept: greys stay grey), the twins of thesis 3.4 that only colour tells apart.

    Parameters
    ----------
    model : Model
        Any model.
    degrees : float
        The turn around the hue circle.
    name : str, optional
        The twin's name; default ``{model.name}-hue{degrees}``.

    Returns
    -------
    Model
        The same mesh with turned corner colours and textures.
    """
    from matplotlib.colors import hsv_to_rgb, rgb_to_hsv

    if not np.isfinite(degrees):
        raise ModelError(f"the hue rotation must be a finite number of degrees, got {degrees}")

    def turn(rgb: np.ndarray) -> np.ndarray:
        hsv = rgb_to_hsv(np.clip(rgb, 0.0, 1.0))
        hsv[..., 0] = (hsv[..., 0] + degrees / 360.0) % 1.0
        return hsv_to_rgb(hsv).astype(np.float32)

    return replace(
        model,
        name=name or f"{model.name}-hue{degrees:g}",
        corner_colors=turn(model.corner_colors),
        textures=[turn(image) for image in model.textures],
    )


def save_model(model: Model, path: str | Path) -> Path:
    """Write ``model`` as a mesh file with per-vertex colours (:func:`vertex_colors`); PLY keeps them.

    The format follows the suffix (``.ply``, ``.obj``, ``.off``, ``.stl``, ``.glb``);
    textures are baked into the vertex colours. The folder is created.
    """
    path = Path(path)
    if path.suffix.lower() not in SUPPORTED_SUFFIXES:
        raise ModelError(f"{path}: write a model as one of {', '.join(SUPPORTED_SUFFIXES)}")
    colors = np.clip(np.round(vertex_colors(model) * 255), 0, 255).astype(np.uint8)
    mesh = trimesh.Trimesh(model.vertices, model.faces, vertex_colors=colors, process=False)
    with atomic(path) as temporary:
        mesh.export(temporary)
    return path


def reversed_faces(model: Model) -> Model:
    """``model`` with every face wound the other way (its corners' colours and texture coordinates with them)."""
    return replace(
        model,
        faces=model.faces[:, ::-1].copy(),
        corner_colors=model.corner_colors[:, ::-1].copy(),
        corner_uv=model.corner_uv[:, ::-1].copy(),
    )


#: coincident vertices are merged within this fraction of a mesh's median edge length (:func:`welded`)
WELD_FRACTION = 1e-3


def welded(model: Model, fraction: float = WELD_FRACTION) -> Model:
    """``model`` with its coincident vertices merged, as a repair: what an STL file or a cut that duplicated its
    vertices leaves apart.

    An STL file gives every triangle its own three vertices, and many cutting tools give each side of a cut its
    own copy of the cut's vertices: the faces of such a mesh share no vertex, so it has a boundary along every
    edge. Vertices within ``fraction`` of the median edge length of each other (and chains of such) become the
    first of them (:func:`heatdata.core.mesh.merged_vertices`); faces this collapses, and second copies of a
    face, are dropped with their colours and texture coordinates.

    Parameters
    ----------
    model : Model
    fraction : float
        The tolerance, relative to the median length of the faces' edges.

    Returns
    -------
    Model
        ``model`` itself when no two vertices coincide; else the merged model, whose
        ``repairs`` say how many vertices were merged and faces dropped.
    """
    corners = model.vertices[model.faces]
    lengths = np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2).ravel()
    lengths = lengths[lengths > 0]
    if not len(lengths):
        return model
    tolerance = fraction * float(np.median(lengths))
    index, first = merged_vertices(model.vertices, tolerance)
    if len(first) == len(model.vertices):
        return model
    faces = index[model.faces]
    keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 2] != faces[:, 0])
    once = np.zeros(len(faces), bool)
    once[np.unique(np.sort(faces, axis=1), axis=0, return_index=True)[1]] = True
    keep &= once
    note = (
        f"{len(model.vertices) - len(first)} coincident vertices merged (within {tolerance:.3g}, "
        f"{fraction:g} of the median edge); {len(faces) - keep.sum()} face(s) this collapsed or repeated dropped"
    )
    log.info("%s: %s", model.name, note)
    used = np.zeros(len(first), bool)
    used[faces[keep]] = True
    reindex = np.cumsum(used) - 1
    return replace(
        model,
        vertices=model.vertices[first[used]],
        faces=reindex[faces[keep]],
        corner_colors=model.corner_colors[keep],
        corner_uv=model.corner_uv[keep],
        face_texture=model.face_texture[keep],
        repairs=[*model.repairs, note],
    )


def transformed(model: Model, rotation: np.ndarray, translation: np.ndarray) -> Model:
    """``model`` moved rigidly: ``x -> rotation @ x + translation``.

    Parameters
    ----------
    model : Model
        Any model.
    rotation : (3, 3) float
        A rotation (or any linear map: a reflection or a scale).
    translation : (3,) float
        Metres.

    Returns
    -------
    Model
        The model with moved vertices; faces and colours unchanged.
    """
    return replace(model, vertices=model.vertices @ np.asarray(rotation).T + np.asarray(translation))


#: the largest translation a motion may give (in the files' units): a kilometre in millimetres; far beyond it the
#: moved mesh's coordinates lose the precision of its vertices
MAX_TRANSLATION = 1e6


def rigid_motion(motion) -> np.ndarray:
    """``motion`` as a (4, 4) float64 rigid transform, or a :class:`StitchError` saying what it is not: a rotation
    (no reflection), a translation of at most :data:`MAX_TRANSLATION`, last row 0 0 0 1."""
    need = "a 4x4 rigid transform (a rotation, no reflection, last row 0 0 0 1)"
    try:
        m = np.asarray(motion, np.float64)
    except (TypeError, ValueError, OverflowError):
        raise StitchError(f"motion must be {need}, not numbers") from None
    if m.shape != (4, 4):
        raise StitchError(f"motion must be {need}, got shape {m.shape}")
    if not np.all(np.isfinite(m)):
        raise StitchError(f"motion must be {need} of finite numbers, got {np.sum(~np.isfinite(m))} NaN or infinite")
    if np.abs(m[:3, 3]).max() > MAX_TRANSLATION:
        raise StitchError(
            f"motion's translation {np.abs(m[:3, 3]).max():.3g} is beyond {MAX_TRANSLATION:g} (the files' units): "
            "the meshes would lose their precision"
        )
    rotation = m[:3, :3]
    if not np.allclose(rotation @ rotation.T, np.eye(3), atol=1e-6) or np.linalg.det(rotation) < 0:
        raise StitchError(f"motion must be {need}: its 3x3 part is not a rotation")
    if not np.allclose(m[3], [0.0, 0.0, 0.0, 1.0]):
        raise StitchError(f"motion must be {need}: its last row is {m[3].tolist()}")
    return m
