"""Real frames' segmentation as pictures: each frame beside its truth and its segments."""

from __future__ import annotations

import numpy as np

from heatdata.experiments.real_frames import LabelledFrame
from heatdata.segmentation.score import SegmentationScore
from heatdata.typing import StrPath


def _colours(ids: np.ndarray) -> np.ndarray:
    """(h, w, 3) float: a distinct colour per id (tab20), white for 0."""
    import matplotlib

    table = matplotlib.colormaps["tab20"](np.arange(20))[:, :3]
    picture = table[(ids - 1) % 20]
    picture[ids == 0] = 1.0
    return picture


def draw_frames(rows: list[tuple[LabelledFrame, np.ndarray, SegmentationScore]], path: StrPath) -> None:
    """A row per frame: the colour image (or the depth), the truth's objects and the segments, titled with what was
    found.

    Parameters
    ----------
    rows : list of (LabelledFrame, (h, w) int, SegmentationScore)
        Each frame, its label image (:func:`heatdata.segmentation.segment.label_image`) and its score.
    path : str or Path
        The PNG to write.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(len(rows), 3, figsize=(12, 3.2 * len(rows)), squeeze=False)
    for (frame, labels, score), (left, middle, right) in zip(rows, axes):
        if frame.rgb is not None:
            left.imshow(frame.rgb)
        else:
            left.imshow(np.nan_to_num(frame.depth, nan=0.0), cmap="gray_r")
        middle.imshow(_colours(frame.truth), interpolation="nearest")
        right.imshow(_colours(labels.astype(np.int64)), interpolation="nearest")
        left.set_title(f"{frame.name} ({frame.category})", fontsize=10)
        middle.set_title(f"truth: {score.objects} objects of >= 1000 px", fontsize=10)
        right.set_title(
            f"segments: {score.found} found, {score.leftovers} leftover, {score.of_nothing} of nothing", fontsize=10
        )
        for axis in (left, middle, right):
            axis.axis("off")
    figure.tight_layout()
    figure.savefig(path, dpi=72)
    plt.close(figure)
