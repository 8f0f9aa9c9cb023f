"""BOP's file formats (Hodan et al., the Benchmark for 6D Object Pose estimation): a scene folder in, the results
CSV out, so that heatdata's poses are scored by the standard ``bop_toolkit`` beside the field's.

A BOP scene folder (``<dataset>/test/000048/``) holds ``scene_camera.json`` (per image: ``cam_K``, nine row-major
numbers, and ``depth_scale``: the depth PNG's unit in millimetres), ``depth/<im_id>.png`` and ``rgb/<im_id>.png``
(or ``.jpg``). Its models (``models/obj_000001.ply``) are in millimetres; ``models_info.json`` gives each one's
diameter and extents.

A result row is ``scene_id,im_id,obj_id,score,R,t,time``: ``R`` the nine numbers of the model-to-camera rotation,
row-major, and ``t`` the translation in millimetres, both in the model file's own frame (BOP's ``R, t`` map a model
point in millimetres to the camera's), ``time`` the seconds the image took.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from heatdata.errors import ViewError
from heatdata.io.files import atomic
from heatdata.typing import StrPath
from heatdata.views.depth import read_image
from heatdata.views.view import check_intrinsics

#: the columns of BOP's results CSV (bop19 and later)
RESULT_COLUMNS = "scene_id,im_id,obj_id,score,R,t,time"


@dataclass(frozen=True)
class BopImage:
    """One image of a BOP scene: its ids, its files and its camera.

    Attributes
    ----------
    scene_id, im_id : int
    depth, rgb : Path
        The depth PNG and the colour image.
    intrinsics : dict
        ``fx, fy, cx, cy, width, height`` (:func:`heatdata.views.view.check_intrinsics`).
    depth_scale : float
        Millimetres per unit of the depth PNG.
    """

    scene_id: int
    im_id: int
    depth: Path
    rgb: Path
    intrinsics: dict
    depth_scale: float

    def read(self) -> tuple[np.ndarray, np.ndarray]:
        """The depth in metres (NaN where there is no reading) and the colour image.

        Returns
        -------
        depth : (h, w) float64
        rgb : (h, w, 3) uint8
        """
        depth = read_image(self.depth, "depth image", "depth") * (self.depth_scale / 1000.0)
        depth[depth <= 0] = np.nan
        rgb = read_image(self.rgb, "colour image", "RGB")
        check_intrinsics(self.intrinsics, depth.shape, str(self.depth))
        return depth, rgb


def read_bop_scene(folder: StrPath) -> list[BopImage]:
    """The images of a BOP scene folder, in the order of their ids.

    Parameters
    ----------
    folder : str or Path
        ``<dataset>/<split>/<scene_id>/``, its name the scene's id.

    Returns
    -------
    list of BopImage

    Raises
    ------
    ViewError
        No ``scene_camera.json``, one that is not BOP's, an image without its depth or colour file, a folder whose
        name is not a number.
    """
    folder = Path(folder)
    if not folder.name.isdigit():
        raise ViewError(f"{folder}: a BOP scene folder is named by its scene id (000048)")
    path = folder / "scene_camera.json"
    try:
        cameras = json.loads(path.read_text())
        if not isinstance(cameras, dict):
            raise TypeError("not a mapping of image ids")
    except (OSError, ValueError, TypeError) as exc:
        raise ViewError(f"{path}: not BOP's scene_camera.json ({type(exc).__name__}: {exc})") from None
    images = []
    for key in sorted(cameras, key=lambda k: int(k) if str(k).isdigit() else -1):
        if not str(key).isdigit():
            raise ViewError(f"{path}: image id {key!r} is not a number")
        entry = cameras[key]
        try:
            k = np.asarray(entry["cam_K"], dtype=np.float64).reshape(3, 3)
            scale = float(entry.get("depth_scale", 1.0))
        except (KeyError, TypeError, ValueError) as exc:
            raise ViewError(f"{path}: image {key}: no cam_K of nine numbers ({type(exc).__name__}: {exc})") from None
        if not (np.isfinite(scale) and scale > 0):
            raise ViewError(f"{path}: image {key}: depth_scale must be a positive number, got {scale}")
        depth = folder / "depth" / f"{int(key):06d}.png"
        rgb = next((p for p in (folder / "rgb" / f"{int(key):06d}{s}" for s in (".png", ".jpg")) if p.is_file()), None)
        if not depth.is_file() or rgb is None:
            raise ViewError(f"{folder}: image {key} lacks its depth/{depth.name} or rgb/{int(key):06d}.png (or .jpg)")
        width, height = _image_size(depth)
        camera = {"fx": k[0, 0], "fy": k[1, 1], "cx": k[0, 2], "cy": k[1, 2], "width": width, "height": height}
        images.append(BopImage(int(folder.name), int(key), depth, rgb, camera, scale))
    return images


def _image_size(path: Path) -> tuple[int, int]:
    from PIL import Image

    with Image.open(path) as image:
        return image.size


def bop_object_id(name: str) -> int:
    """BOP's object id of a library object named after its model file (``obj_000005`` is 5).

    Raises
    ------
    ViewError
        A name that does not end in BOP's ``obj_<number>``.
    """
    match = re.search(r"obj_(\d+)$", name)
    if match is None:
        raise ViewError(f"{name}: not a BOP model's name (obj_000001): its object id is unknown")
    return int(match.group(1))


def file_frame_pose(matrix: np.ndarray, rotation: np.ndarray, centre: np.ndarray, scale: float) -> np.ndarray:
    """A heatdata pose (model to camera, metres) as the model file's own: its points in file units to the camera in
    millimetres.

    heatdata loads a file's point ``p`` as ``scale (rotation p - centre)`` (:func:`heatdata.io.models.load_model`:
    the turn to y up, the bounding box centred, the units to metres), so the file's pose is
    ``R = R_hd rotation`` and ``t = 1000 (t_hd - scale R_hd centre)``, with ``scale`` 0.001 for a file in millimetres
    (BOP's; any other unit scales the rotation too).

    Parameters
    ----------
    matrix : (4, 4) float
        heatdata's pose: the loaded model's frame to the camera's, metres.
    rotation : (3, 3) float
        The turn the loader gave the file (:data:`heatdata.io.models.UP_AXES`).
    centre : (3,) float
        The turned file's bounding-box centre, in file units.
    scale : float
        File units to metres.

    Returns
    -------
    (4, 4) float64
        File units to the camera's millimetres.
    """
    r = np.asarray(matrix, np.float64)[:3, :3]
    pose = np.eye(4)
    pose[:3, :3] = 1000.0 * scale * r @ rotation
    pose[:3, 3] = 1000.0 * (np.asarray(matrix, np.float64)[:3, 3] - scale * r @ np.asarray(centre, np.float64))
    return pose


def write_bop_results(rows: list[dict], path: StrPath) -> Path:
    """BOP's results CSV (``bop_toolkit_lib.inout.load_bop_results`` reads it).

    Parameters
    ----------
    rows : list of dict
        ``scene_id, im_id, obj_id, score, time`` and ``pose``: (4, 4) model file (millimetres) to camera
        (millimetres), as :func:`file_frame_pose` gives it.
    path : str or Path
        The ``.csv`` to write (whole, then renamed).

    Returns
    -------
    Path
    """
    lines = [RESULT_COLUMNS]
    for row in rows:
        pose = np.asarray(row["pose"], np.float64)
        rotation = " ".join(f"{x:.9g}" for x in pose[:3, :3].ravel())
        translation = " ".join(f"{x:.6f}" for x in pose[:3, 3])
        lines.append(
            f"{int(row['scene_id'])},{int(row['im_id'])},{int(row['obj_id'])},{float(row['score']):.6f},"
            f"{rotation},{translation},{float(row['time']):.4f}"
        )
    path = Path(path)
    with atomic(path) as temporary:
        temporary.write_text("\n".join(lines) + "\n")
    return path
