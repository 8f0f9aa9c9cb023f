"""Scores of a segmentation against per-pixel truth, as object-segmentation benchmarks (OSD, mOSD) count them.

An object counts when it holds at least ``min_object`` pixels; it is **found** when one segment overlaps it with mask
IoU >= 0.5 (at most one segment can, so a match is one to one). A segment lying mostly on objects that matches none
is a **leftover piece** (a box's face cut from the box, a bowl's inside); a segment lying less than half on objects is
a segment **of nothing** (the table, the wall, a shadow).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from heatdata.errors import ViewError

MIN_OBJECT = 1000  # pixels: smaller objects are not counted (the mOSD measure)
MATCH_IOU = 0.5


@dataclass(frozen=True)
class SegmentationScore:
    """One frame's counts.

    Attributes
    ----------
    objects : int
        Objects of at least ``min_object`` pixels.
    found : int
        Of them, matched by a segment with IoU >= 0.5.
    segments : int
        Segments the segmentation gave.
    leftovers : int
        Segments lying mostly on objects that match none (any size of object).
    of_nothing : int
        Segments lying less than half on objects.
    ious : tuple of float
        Each counted object's best IoU with a segment.
    """

    objects: int
    found: int
    segments: int
    leftovers: int
    of_nothing: int
    ious: tuple[float, ...]


def score_segmentation(labels: np.ndarray, truth: np.ndarray, min_object: int = MIN_OBJECT) -> SegmentationScore:
    """Count a label image's segments against a truth image's objects.

    Parameters
    ----------
    labels : (h, w) int
        The segmentation: 0 for no object, 1..N for segments.
    truth : (h, w) int
        Object ids: 0 where there is no object, one id per object (parts of one object share it).
    min_object : int
        Objects with fewer pixels are not counted (but a segment on one is neither a leftover nor of nothing).

    Returns
    -------
    SegmentationScore
    """
    labels, truth = np.asarray(labels), np.asarray(truth)
    if labels.shape != truth.shape:
        raise ViewError(f"labels {labels.shape} and truth {truth.shape} differ in size")
    segment_ids = np.unique(labels[labels > 0])
    object_ids = np.unique(truth[truth > 0])
    # the overlap table, segments by objects (+ one column: no object)
    s = np.searchsorted(segment_ids, labels[labels > 0])
    o = np.where(truth[labels > 0] > 0, np.searchsorted(object_ids, truth[labels > 0]) + 1, 0)
    overlap = np.zeros((len(segment_ids), len(object_ids) + 1), np.int64)
    np.add.at(overlap, (s, o), 1)
    segment_size = overlap.sum(axis=1)
    object_size = np.bincount(np.searchsorted(object_ids, truth[truth > 0]), minlength=len(object_ids))
    union = segment_size[:, None] + object_size[None, :] - overlap[:, 1:]
    iou = np.where(union > 0, overlap[:, 1:] / np.maximum(union, 1), 0.0)
    matched = iou >= MATCH_IOU
    counted = object_size >= min_object
    best = iou.max(axis=0) if len(segment_ids) else np.zeros(len(object_ids))
    on_objects = overlap[:, 1:].sum(axis=1)
    of_nothing = on_objects * 2 < segment_size
    leftovers = ~of_nothing & ~matched.any(axis=1)
    return SegmentationScore(
        objects=int(counted.sum()),
        found=int(matched[:, counted].any(axis=0).sum()),
        segments=len(segment_ids),
        leftovers=int(leftovers.sum()),
        of_nothing=int(of_nothing.sum()),
        ious=tuple(float(v) for v in best[counted]),
    )
