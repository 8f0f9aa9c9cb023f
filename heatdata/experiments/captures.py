"""Captured depth frames on disk: the folders of frames and camera files the workflow reads as test views."""

from __future__ import annotations

from pathlib import Path

from heatdata.errors import ViewError

CAPTURE_SUFFIXES = (".png", ".npy")


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
    for folder in sorted(p for p in root.iterdir() if p.is_dir()):
        for depth in sorted(folder.iterdir()):
            if depth.suffix.lower() not in CAPTURE_SUFFIXES or depth.name.lower().endswith((".rgb.png", ".mask.png")):
                continue
            stem = depth.name[: -len(depth.suffix)]
            own = [folder / f"{stem}{suffix}" for suffix in (".json", ".yaml", ".yml")]
            shared = [folder / name for name in CAMERA_NAMES] + [root / name for name in CAMERA_NAMES]
            intrinsics = next((p for p in own + shared if p.is_file()), None)
            if intrinsics is None:
                raise ViewError(f"{depth}: no intrinsics ({stem}.json beside it, or camera.json in {folder} or {root})")
            extra = {kind: folder / f"{stem}.{kind}.png" for kind in ("rgb", "mask")}
            captures.append(
                {
                    "object": folder.name,
                    "name": stem,
                    "depth": str(depth),
                    "intrinsics": str(intrinsics),
                    **{kind: str(path) if path.is_file() else "" for kind, path in extra.items()},
                }
            )
    if not captures:
        raise ViewError(f"{root}: no capture (expected <object>/<name>.png or .npy)")
    return captures
