"""Overlays of a recognized scene: the frame with each object's pixels tinted, boxed and named.

Drawn with Pillow (no matplotlib), so ``heatdata recognize --overlay`` costs a few milliseconds. The same drawing
serves a :class:`heatdata.recognition.answers.SceneRecognition` (the command) and a scene's rows of a detection
table (the workflow's report, which also names the true object where the answer differs).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from PIL import Image, ImageDraw, ImageFont

from heatdata.io.files import atomic
from heatdata.typing import StrPath

#: one tint per object, in order (colour-blind-safe, Okabe & Ito)
TINTS = [(230, 159, 0), (86, 180, 233), (0, 158, 115), (240, 228, 66), (0, 114, 178), (213, 94, 0), (204, 121, 167)]
ALPHA = 0.45  # the tint's weight over the frame


@dataclass(frozen=True)
class Mark:
    """One object drawn on a frame: its pixels (None: its box alone), its box ``u0, v0, u1, v1`` and its label."""

    mask: np.ndarray | None
    bbox: tuple[int, int, int, int]
    text: str


def frame_image(depth: np.ndarray, rgb: np.ndarray | None = None) -> np.ndarray:
    """(h, w, 3) uint8: the colour image, or the depth shaded grey (near light, no reading black) without one."""
    if rgb is not None:
        rgb = np.asarray(rgb)
        return rgb.astype(np.uint8) if rgb.dtype.kind in "ui" else np.round(np.clip(rgb, 0, 1) * 255).astype(np.uint8)
    depth = np.asarray(depth, np.float64)
    valid = np.isfinite(depth) & (depth > 0)
    grey = np.zeros(depth.shape)
    if valid.any():
        near, far = np.percentile(depth[valid], [1, 99])
        grey[valid] = 1.0 - 0.8 * np.clip((depth[valid] - near) / max(far - near, 1e-9), 0, 1)
    return np.repeat(np.round(grey * 255).astype(np.uint8)[..., None], 3, axis=2)


def detection_marks(detections: list) -> list[Mark]:
    """The marks of :class:`heatdata.recognition.answers.Detection` s: ``number object (confidence)``."""
    marks = []
    for number, detection in enumerate(detections, 1):
        text = f"{number} {detection.object or 'unknown'}"
        if math.isfinite(detection.confidence):
            text += f" ({detection.confidence:.2f})"
        marks.append(Mark(detection.mask, detection.bbox, text))
    return marks


def row_marks(rows: pd.DataFrame, shape: tuple[int, int]) -> list[Mark]:
    """The marks of a scene's rows of a detection table (:func:`heatdata.experiments.scenes.score_scene`): the
    answer (unknown below the library's threshold), and the true object in brackets where it differs."""
    from heatdata.experiments.scenes import unpack_mask

    marks = []
    for row in rows[rows["detection"] >= 0].sort_values("detection").itertuples():
        name = row.object if row.known else ""
        text = f"{row.detection + 1} {name or 'unknown'}"
        if name != row.truth:
            text += f" [{row.truth or 'no object'}]"
        u0, v0, u1, v1 = (int(b) for b in row.bbox)
        marks.append(Mark(unpack_mask(row.mask, row.bbox, shape), (u0, v0, u1, v1), text))
    return marks


def overlay_image(image: np.ndarray, marks: list[Mark]) -> Image.Image:
    """The frame with each mark's pixels tinted, its box drawn and its label written above it.

    Parameters
    ----------
    image : (h, w, 3) uint8
        The frame (:func:`frame_image`).
    marks : list of Mark
        What to draw (:func:`detection_marks`, :func:`row_marks`).

    Returns
    -------
    PIL.Image.Image
    """
    canvas = np.asarray(image, np.float64).copy()
    for number, mark in enumerate(marks):
        if mark.mask is not None:
            colour = np.array(TINTS[number % len(TINTS)], np.float64)
            canvas[mark.mask] = (1 - ALPHA) * canvas[mark.mask] + ALPHA * colour
    picture = Image.fromarray(np.round(canvas).astype(np.uint8))
    draw = ImageDraw.Draw(picture)
    font = ImageFont.load_default(size=max(11, picture.height // 32))
    for number, mark in enumerate(marks):
        tint = TINTS[number % len(TINTS)]
        u0, v0, u1, v1 = mark.bbox
        draw.rectangle((u0, v0, u1, v1), outline=tint, width=2)
        left, top, right, bottom = draw.textbbox((u0, v0), mark.text, font=font)
        y = v0 - (bottom - top) - 4 if v0 - (bottom - top) - 4 >= 0 else v1 + 2
        x = max(0, min(u0, picture.width - (right - left) - 4))  # the label stays inside the frame
        draw.rectangle((x, y, x + right - left + 4, y + bottom - top + 4), fill=(0, 0, 0))
        draw.text((x + 2, y + 2 - (top - v0)), mark.text, fill=tint, font=font)
    return picture


def save_overlay(path: StrPath, image: np.ndarray, marks: list[Mark]) -> None:
    """Write :func:`overlay_image` as a PNG (written whole, then renamed)."""
    with atomic(path) as temporary:
        overlay_image(image, marks).save(temporary, format="PNG")
