"""Segmentation scored on folders of labelled real frames (the layout of mOSD's frames: ``<name>.depth.png``,
``<name>.rgb.png``, ``<name>.labels.png`` and one ``intrinsics.json``), per frame and per category."""

from __future__ import annotations

import logging
import re
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from heatdata.errors import ConfigError, ViewError
from heatdata.segmentation.score import score_segmentation
from heatdata.segmentation.segment import label_image, segment_frame
from heatdata.segmentation.settings import SegmentSettings
from heatdata.typing import StrPath
from heatdata.views.depth import read_depth_frame, read_image

log = logging.getLogger(__name__)

#: mOSD's scenes by number (Richtsfeld et al. 2012): learn 0-16 boxes, 17-24 stacked, 25-32 occluded, 33-44 cylinders;
#: test 43-54 mixed objects, 55-65 complex scenes
MOSD_CATEGORIES = {
    "learn": [(16, "boxes"), (24, "stacked"), (32, "occluded"), (44, "cylinders")],
    "test": [(15, "boxes"), (23, "stacked"), (30, "occluded"), (42, "cylinders"), (54, "mixed"), (65, "complex")],
}


@dataclass
class LabelledFrame:
    """One real frame with its truth: depth (metres, NaN no reading), colour, intrinsics, object ids (0 none)."""

    name: str
    category: str
    depth: np.ndarray
    rgb: np.ndarray | None
    intrinsics: dict
    truth: np.ndarray


def mosd_category(name: str) -> str:
    """An mOSD frame's category from its name (``learn20`` is stacked boxes); ``other`` for a name it does not
    follow."""
    match = re.fullmatch(r"(learn|test)(\d+)", name)
    if match is None:
        return "other"
    number = int(match.group(2))
    return next((c for last, c in MOSD_CATEGORIES[match.group(1)] if number <= last), "other")


def mosd_objects(labels: np.ndarray) -> np.ndarray:
    """mOSD's labels as object ids: ``10 k + j`` is part j of object k (k >= 2); below 20 the table or nothing."""
    labels = np.asarray(labels, np.int64)
    return np.where(labels >= 20, labels // 10, 0)


def read_labelled_frames(folder: StrPath) -> Iterator[LabelledFrame]:
    """The labelled frames of a folder, in the order of their names' numbers.

    Raises
    ------
    ViewError
        No such folder, no ``intrinsics.json`` or no ``*.depth.png`` in it.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise ViewError(f"{folder}: no such folder of labelled frames")
    intrinsics = folder / "intrinsics.json"
    names = sorted(
        (p.name.removesuffix(".depth.png") for p in folder.glob("*.depth.png")),
        key=lambda n: (re.sub(r"\d+", "", n), int(re.sub(r"\D", "", n) or 0), n),
    )
    if not names:
        raise ViewError(f"{folder}: no <name>.depth.png frames")
    for name in names:
        rgb_path = folder / f"{name}.rgb.png"
        depth, rgb, k = read_depth_frame(
            folder / f"{name}.depth.png", intrinsics, rgb_path if rgb_path.exists() else None
        )
        truth = mosd_objects(read_image(folder / f"{name}.labels.png", "label image", "depth"))
        yield LabelledFrame(name, mosd_category(name), np.where(depth > 0, depth, np.nan), rgb, k, truth)


def score_folder(folder: StrPath, settings: SegmentSettings | None = None) -> pd.DataFrame:
    """Segment each labelled frame of ``folder`` and score it (:func:`heatdata.segmentation.score.score_segmentation`).

    Returns
    -------
    pandas.DataFrame
        A row per frame: ``frame, category, objects, found, segments, leftovers, of_nothing, seconds``.
    """
    rows = []
    for frame in read_labelled_frames(folder):
        tic = time.perf_counter()
        found = segment_frame(frame.depth, frame.intrinsics, frame.rgb, settings, name=frame.name)
        seconds = time.perf_counter() - tic
        score = score_segmentation(label_image(found, frame.depth.shape), frame.truth)
        log.info("%s: %d of %d objects found in %.2f s", frame.name, score.found, score.objects, seconds)
        rows.append(
            {
                "frame": frame.name,
                "category": frame.category,
                "objects": score.objects,
                "found": score.found,
                "segments": score.segments,
                "leftovers": score.leftovers,
                "of_nothing": score.of_nothing,
                "seconds": seconds,
            }
        )
    return pd.DataFrame(rows)


def by_category(scores: pd.DataFrame) -> pd.DataFrame:
    """The per-frame scores summed per category and over all: objects found (and their share), leftover pieces per
    object, segments of nothing (and their share of the segments), median seconds a frame."""
    counts = ["objects", "found", "segments", "leftovers", "of_nothing"]
    table = scores.groupby("category", sort=False)[counts].sum()
    table.loc["all"] = scores[counts].sum()
    table["found_share"] = table["found"] / table["objects"]
    table["leftovers_per_object"] = table["leftovers"] / table["objects"]
    table["of_nothing_share"] = table["of_nothing"] / table["segments"].clip(lower=1)
    seconds = scores.groupby("category", sort=False)["seconds"].median()
    table["median_seconds"] = pd.concat([seconds, pd.Series({"all": scores["seconds"].median()})])
    return table.reset_index()


def real_frame_folders(folders: list[str]) -> dict[str, Path]:
    """The config's ``real_frames.folders`` by name (each folder's own name), checked before any job runs.

    Raises
    ------
    ConfigError
        A folder that does not exist, holds no ``*.depth.png`` with its ``.labels.png`` or no ``intrinsics.json``,
        or two folders of one name.
    """
    found: dict[str, Path] = {}
    for folder in map(Path, folders):
        where = f"real_frames.folders: {folder}"
        if not folder.is_dir():
            raise ConfigError(f"{where}: no such folder")
        if not (folder / "intrinsics.json").is_file():
            raise ConfigError(f"{where}: no intrinsics.json (fx, fy, cx, cy, width, height)")
        frames = sorted(folder.glob("*.depth.png"))
        if not frames:
            raise ConfigError(f"{where}: no <name>.depth.png frames")
        unlabelled = [p.name for p in frames if not p.with_name(p.name.replace(".depth.", ".labels.")).is_file()]
        if unlabelled:
            raise ConfigError(f"{where}: {len(unlabelled)} frame(s) without <name>.labels.png, e.g. {unlabelled[0]}")
        if folder.name in found:
            raise ConfigError(f"{where}: two folders named {folder.name!r}; results are kept by folder name")
        found[folder.name] = folder
    return found


def frame_files(folder: StrPath) -> list[str]:
    """Every file of a folder of labelled frames that its scores depend on (a rule's input)."""
    folder = Path(folder)
    files = [folder / "intrinsics.json"]
    for depth in sorted(folder.glob("*.depth.png")):
        files += [depth, depth.with_name(depth.name.replace(".depth.", ".labels."))]
        rgb = depth.with_name(depth.name.replace(".depth.", ".rgb."))
        files += [rgb] if rgb.is_file() else []
    return [str(f) for f in files]


def worst_frames(scores: pd.DataFrame, count: int = 3) -> pd.DataFrame:
    """The ``count`` frames segmented worst: the fewest of their objects found, then the most leftover pieces and
    segments of nothing per object."""
    ranked = scores.assign(
        missed=1 - scores["found"] / scores["objects"].clip(lower=1),
        extra=(scores["leftovers"] + scores["of_nothing"]) / scores["objects"].clip(lower=1),
    )
    return ranked.sort_values(["missed", "extra", "frame"], ascending=[False, False, True]).head(count)
