"""Recognition scored on real RGB-D frames with boxes drawn around their objects (the layout of the YCB frames in
``realdata/ycb``: ``<name>-depth.png``, ``<name>-color.png``, one ``meta.yml`` camera matrix and a ``truth.json``).

``truth.json`` holds, per frame, ``known`` (``{object: [u0, v0, u1, v1]}``, objects the library holds),
``not_in_models`` (boxes of objects it lacks, to be answered unknown) and ``not_scored`` (boxes of objects left
out of the measure, e.g. a lookalike of a known one). A detection belongs to the box that holds at least half of its
own bounding box (the most of it, where several do); a detection no box holds is one "of nothing".

Per box: a known object is **named right** when a detection of it names it; an unknown one is **answered unknown**
when none of its detections names an object. A detection of nothing counts when it names an object.
"""

from __future__ import annotations

import json
import logging
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from heatdata.errors import ConfigError
from heatdata.recognition.answers import SceneRecognition
from heatdata.recognition.library import Library
from heatdata.segmentation.settings import SegmentSettings
from heatdata.typing import StrPath
from heatdata.views.depth import read_depth_frame

log = logging.getLogger(__name__)

#: a detection belongs to a box that holds at least this share of its bounding box
HELD = 0.5


@dataclass(frozen=True)
class BoxTruth:
    """One frame's boxes (``u0, v0, u1, v1`` pixels): the library's objects, those it lacks, those not scored."""

    known: dict[str, tuple[int, int, int, int]]
    unknown: list[tuple[int, int, int, int]]
    unscored: dict[str, tuple[int, int, int, int]]

    def boxes(self) -> list[tuple[str, str, tuple[int, int, int, int]]]:
        """Every box as ``(name, kind, box)``: kind ``known``, ``unknown`` (named ``unknown-<i>``) or ``unscored``."""
        return (
            [(name, "known", box) for name, box in self.known.items()]
            + [(f"unknown-{i}", "unknown", box) for i, box in enumerate(self.unknown)]
            + [(name, "unscored", box) for name, box in self.unscored.items()]
        )


def read_box_truth(path: StrPath) -> dict[str, BoxTruth]:
    """A folder's ``truth.json``: each frame's boxes.

    Parameters
    ----------
    path : str or Path
        The JSON file.

    Returns
    -------
    dict of str to BoxTruth
        By frame name.

    Raises
    ------
    ConfigError
        Not such a file: no ``frames`` mapping, or a box that is not four numbers with u0 < u1 and v0 < v1.
    """
    path = Path(path)
    try:
        frames = json.loads(path.read_text())["frames"]
        if not isinstance(frames, dict):
            raise TypeError("frames is not a mapping")
        truth = {}
        for name, boxes in frames.items():
            truth[str(name)] = BoxTruth(
                {str(k): _box(v) for k, v in boxes.get("known", {}).items()},
                [_box(v) for v in boxes.get("not_in_models", [])],
                {str(k): _box(v) for k, v in boxes.get("not_scored", {}).items()},
            )
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        raise ConfigError(f"{path}: not a truth file of boxes ({type(exc).__name__}: {exc})") from None
    return truth


def _box(value) -> tuple[int, int, int, int]:
    u0, v0, u1, v1 = (int(x) for x in value)
    if not (u0 < u1 and v0 < v1):
        raise ValueError(f"a box is u0 v0 u1 v1 with u0 < u1 and v0 < v1, got {value}")
    return u0, v0, u1, v1


def _held(inner: tuple, outer: tuple) -> float:
    """The share of box ``inner`` inside box ``outer``."""
    width = min(inner[2], outer[2]) - max(inner[0], outer[0])
    height = min(inner[3], outer[3]) - max(inner[1], outer[1])
    area = max(1, (inner[2] - inner[0]) * (inner[3] - inner[1]))
    return max(0, width) * max(0, height) / area


def score_scene(name: str, scene: SceneRecognition, truth: BoxTruth) -> pd.DataFrame:
    """One frame's answers against its boxes (the module docstring).

    Parameters
    ----------
    name : str
        The frame.
    scene : SceneRecognition
        Its answers (:meth:`heatdata.recognition.library.Library.recognize_scene`).
    truth : BoxTruth

    Returns
    -------
    pandas.DataFrame
        One row per box and per detection of nothing: ``frame, truth`` (the box's name, ``""`` for nothing),
        ``kind`` (known, unknown, unscored, nothing), ``detections``, ``answers`` (the objects named, ``;``-joined),
        ``nearest`` (the nearest objects of its detections), ``right`` (known: named right; unknown: answered
        unknown; nothing: named no object).
    """
    boxes = truth.boxes()
    owned: dict[str, list] = {box_name: [] for box_name, _, _ in boxes}
    nothing: list = []
    for detection in scene.detections:
        held = [(_held(detection.bbox, box), box_name) for box_name, _, box in boxes]
        share, owner = max(held, default=(0.0, ""))
        (owned[owner] if share >= HELD else nothing).append(detection)
    rows = []
    for box_name, kind, _ in boxes:
        found = owned[box_name]
        named = [d.object for d in found if d.object is not None]
        right = box_name in named if kind == "known" else not named
        rows.append(_row(name, box_name, kind, found, named, right))
    for detection in nothing:
        named = [] if detection.object is None else [detection.object]
        rows.append(_row(name, "", "nothing", [detection], named, not named))
    return pd.DataFrame(rows)


def _row(frame: str, truth: str, kind: str, found: list, named: list[str], right: bool) -> dict:
    nearest = [d.recognition.best.object for d in found if d.recognition is not None]
    return {
        "frame": frame,
        "truth": truth,
        "kind": kind,
        "detections": len(found),
        "answers": ";".join(named),
        "nearest": ";".join(nearest),
        "right": bool(right),
    }


def frame_files(folder: StrPath) -> list[tuple[str, Path, Path]]:
    """A folder's frames: ``(name, depth, colour)`` for each ``<name>-depth.png`` with its ``<name>-color.png``.

    Raises
    ------
    ConfigError
        No such frame in the folder, or a depth image without its colour image.
    """
    folder = Path(folder)
    frames = []
    for depth in sorted(folder.glob("*-depth.png")):
        name = depth.name[: -len("-depth.png")]
        color = folder / f"{name}-color.png"
        if not color.is_file():
            raise ConfigError(f"{depth}: no colour image {color.name} beside it")
        frames.append((name, depth, color))
    if not frames:
        raise ConfigError(f"{folder}: no <name>-depth.png frames")
    return frames


def score_folder(
    library: Library, folder: StrPath, settings: SegmentSettings | None = None, threshold: float | None = None
) -> pd.DataFrame:
    """Every frame of a folder recognized with ``library`` and scored against its ``truth.json``
    (:func:`score_scene`), with each frame's seconds.

    Parameters
    ----------
    library : Library
        With surface samples, for the pose check.
    folder : str or Path
        ``<name>-depth.png`` (uint16 millimetres), ``<name>-color.png``, ``meta.yml`` (the camera matrix,
        :func:`heatdata.views.depth.read_intrinsics`) and ``truth.json``.
    settings : SegmentSettings, optional
        The segmentation's.
    threshold : float, optional
        The confidence threshold (default: the library's rule, :meth:`Library.threshold`).

    Returns
    -------
    pandas.DataFrame
        :func:`score_scene`'s rows of every frame, with ``seconds`` (the frame's recognition, warm).
    """
    folder = Path(folder)
    truth = read_box_truth(folder / "truth.json")
    parts = []
    for name, depth_path, color_path in frame_files(folder):
        if name not in truth:
            log.warning("%s: no boxes in truth.json; left out", depth_path)
            continue
        depth, rgb, intrinsics = read_depth_frame(depth_path, folder / "meta.yml", color_path)
        start = time.perf_counter()
        scene = library.recognize_scene(depth, intrinsics, rgb, settings=settings, name=name, threshold=threshold)
        seconds = time.perf_counter() - start
        parts.append(score_scene(name, scene, truth[name]).assign(seconds=seconds))
        log.info("%s: %d objects, %.2f s", name, len(scene.detections), seconds)
    return pd.concat(parts, ignore_index=True)


def summary(scores: pd.DataFrame) -> dict:
    """The measures of :func:`score_folder`'s rows.

    Returns
    -------
    dict
        ``known`` and ``known_right`` (named right), ``unknown`` and ``unknown_right`` (answered unknown),
        ``nothing_named`` (detections of nothing that name an object), ``frames`` and ``median_seconds``.
    """
    known = scores[scores["kind"] == "known"]
    unknown = scores[scores["kind"] == "unknown"]
    nothing = scores[scores["kind"] == "nothing"]
    per_frame = scores.groupby("frame")["seconds"].first()
    return {
        "frames": len(per_frame),
        "known": len(known),
        "known_right": int(known["right"].sum()),
        "unknown": len(unknown),
        "unknown_right": int(unknown["right"].sum()),
        "nothing_named": int((~nothing["right"]).sum()),
        "median_seconds": float(np.median(per_frame)) if len(per_frame) else float("nan"),
    }
