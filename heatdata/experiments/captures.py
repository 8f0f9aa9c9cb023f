"""Captured depth frames on disk: the folders of frames and camera files the workflow reads as test views."""

from __future__ import annotations

from pathlib import Path

from heatdata.errors import ViewError
from heatdata.io.files import is_partial

CAPTURE_SUFFIXES = (".png", ".npy")


#: frames of a sequence besides depth images: organized clouds and saved views
FRAME_SUFFIXES = (*CAPTURE_SUFFIXES, ".pcd", ".ply", ".npz")


CAMERA_NAMES = ("camera.json", "camera.yaml", "camera.yml")


def find_captures(root) -> list[dict]:
    """The captures of a folder laid out as ``<root>/<object>/<name>.png`` (or ``.npy``), one folder per object.

    Beside a depth image ``<name>.png`` may lie ``<name>.rgb.png`` (colour) and
    ``<name>.mask.png`` (the object's pixels). The intrinsics are ``<name>.json`` (or
    ``.yaml``) when present, else ``camera.json`` / ``camera.yaml`` in the object's folder,
    else in ``root``.

    Returns
    -------
    list of dict
        ``object, name, depth, intrinsics, rgb, mask`` (paths as strings, ``""`` when
        absent), sorted by object and name.

    Raises
    ------
    ViewError
        ``root`` is not a folder, holds no capture, or a capture has no intrinsics.
    """
    root = Path(root)
    if not root.is_dir():
        raise ViewError(f"{root}: no such folder of captures")
    captures = []
    for folder in sorted(p for p in root.iterdir() if p.is_dir() and not is_partial(p)):
        for depth in sorted(folder.iterdir()):
            if _is_frame(depth, CAPTURE_SUFFIXES):
                captures.append({"object": folder.name, **_frame(depth, [folder, root])})
    if not captures:
        raise ViewError(f"{root}: no capture (expected <object>/<name>.png or .npy)")
    return captures


def find_frames(folder) -> list[dict]:
    """The frames of a sequence in one folder, sorted by name: depth images (with their colour, mask and
    intrinsics beside them, as in :func:`find_captures`), organized clouds (``.pcd``, ``.ply``) and saved views
    (``.npz``).

    Returns
    -------
    list of dict
        ``name, depth, intrinsics, rgb, mask`` (paths as strings, ``""`` when absent).

    Raises
    ------
    ViewError
        ``folder`` is not a folder or holds no frame, or a depth image has no intrinsics.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise ViewError(f"{folder}: no such folder of frames")
    frames = [_frame(path, [folder]) for path in sorted(folder.iterdir()) if _is_frame(path, FRAME_SUFFIXES)]
    if not frames:
        raise ViewError(f"{folder}: no frame (depth .png or .npy, cloud .pcd or .ply, view .npz)")
    return frames


def _is_frame(path: Path, suffixes: tuple[str, ...]) -> bool:
    """A frame's file: of one of ``suffixes``, not a colour, mask or label image beside a depth image, nor a hidden
    file or one being written (:func:`heatdata.io.files.is_partial`)."""
    name = path.name.lower()
    beside = (".rgb.png", ".mask.png", ".labels.png")
    usable = path.suffix.lower() in suffixes and not name.endswith(beside) and not is_partial(path)
    return usable and path.is_file()


def _frame(depth: Path, folders: list[Path]) -> dict:
    """A frame's files: a depth image's intrinsics (``<name>.json`` beside it, else ``camera.json`` in
    ``folders``), colour and mask; a cloud or a saved view stands alone."""
    stem = depth.name[: -len(depth.suffix)]
    files = {"name": stem, "depth": str(depth), "intrinsics": "", "rgb": "", "mask": ""}
    if depth.suffix.lower() not in CAPTURE_SUFFIXES:
        return files
    own = [depth.parent / f"{stem}{suffix}" for suffix in (".json", ".yaml", ".yml")]
    shared = [folder / name for folder in folders for name in CAMERA_NAMES]
    intrinsics = next((p for p in own + shared if p.is_file()), None)
    if intrinsics is None:
        where = " or ".join(str(f) for f in folders)
        raise ViewError(f"{depth}: no intrinsics ({stem}.json beside it, or camera.json in {where})")
    extra = {kind: depth.parent / f"{stem}.{kind}.png" for kind in ("rgb", "mask")}
    return {**files, "intrinsics": str(intrinsics), **{k: str(p) if p.is_file() else "" for k, p in extra.items()}}
