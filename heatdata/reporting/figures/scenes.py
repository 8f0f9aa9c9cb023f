"""Overlays of a recognized scene: the frame with each object's pixels tinted, boxed and named, and the outline of
its posed model where the pose is accepted.

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


#: the posed model's outline is drawn this many pixels wide
OUTLINE = 2


@dataclass(frozen=True)
class Mark:
    """One object drawn on a frame: its pixels (None: its box alone), its box ``u0, v0, u1, v1``, its label and the
    outline of its posed model (None: not posed)."""

    mask: np.ndarray | None
    bbox: tuple[int, int, int, int]
    text: str
    outline: np.ndarray | None = None


def pose_outline(matrix: np.ndarray, surface, intrinsics: dict) -> np.ndarray:
    """(h, w) bool: the outline of a posed model as the camera sees it.

    The model's surface samples (:class:`heatdata.recognition.pose.Surface`) the camera sees are projected, the gaps
    between them closed (a disc as wide as the samples' spacing there) and filled, and the region's border kept.

    Parameters
    ----------
    matrix : (4, 4) float
        Model-to-camera pose.
    surface : Surface
        The model's samples.
    intrinsics : dict
        The frame's camera.

    Returns
    -------
    (h, w) bool
    """
    from scipy.ndimage import binary_closing, binary_erosion, binary_fill_holes

    from heatdata.recognition.pose import visible
    from heatdata.views.depth import pixels_of

    posed = surface.points @ np.asarray(matrix)[:3, :3].T + np.asarray(matrix)[:3, 3]
    shape = (int(intrinsics["height"]), int(intrinsics["width"]))
    region = np.zeros(shape, bool)
    if not np.all(posed[:, 2] > 0):
        return region
    seen = posed[visible(posed, np.zeros(3))]
    pixel, inside = pixels_of(seen, intrinsics)
    region[pixel[inside, 1], pixel[inside, 0]] = True
    radius = max(1, math.ceil(intrinsics["fx"] * surface.spacing / float(np.median(seen[:, 2]))))
    v, u = np.mgrid[-radius : radius + 1, -radius : radius + 1]
    disc = u**2 + v**2 <= radius**2
    region = binary_fill_holes(binary_closing(np.pad(region, radius), structure=disc))[radius:-radius, radius:-radius]
    return region & ~binary_erosion(region, iterations=OUTLINE)


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


def detection_marks(detections: list, surfaces: dict | None = None, intrinsics: dict | None = None) -> list[Mark]:
    """The marks of :class:`heatdata.recognition.answers.Detection` s: ``number object (confidence)``, and the
    outline of each accepted pose (given the library's ``surfaces`` and the frame's ``intrinsics``)."""
    marks = []
    for number, detection in enumerate(detections, 1):
        text = f"{number} {detection.object or 'unknown'}"
        if math.isfinite(detection.confidence):
            text += f" ({detection.confidence:.2f})"
        pose, outline = detection.pose, None
        if pose is not None and pose.accepted and intrinsics is not None and pose.object in (surfaces or {}):
            outline = pose_outline(pose.matrix, (surfaces or {})[pose.object], intrinsics)
        marks.append(Mark(detection.mask, detection.bbox, text, outline))
    return marks


def row_marks(
    rows: pd.DataFrame, shape: tuple[int, int], surfaces: dict | None = None, intrinsics: dict | None = None
) -> list[Mark]:
    """The marks of a scene's rows of a detection table (:func:`heatdata.experiments.scenes.score_scene`): the
    answer (unknown below the library's threshold or when no pose explains it), the true object in brackets where
    it differs, and the outline of each accepted pose (given the library's ``surfaces`` and the ``intrinsics``)."""
    from heatdata.experiments.scenes import unpack_mask

    marks = []
    for row in rows[rows["detection"] >= 0].sort_values("detection").itertuples():
        name = row.object if row.known else ""
        text = f"{row.detection + 1} {name or 'unknown'}"
        if name != row.truth:
            text += f" [{row.truth or 'no object'}]"
        u0, v0, u1, v1 = (int(b) for b in row.bbox)
        outline = None
        if row.verified and intrinsics is not None and row.posed in (surfaces or {}):
            matrix = np.asarray(row.pose, dtype=np.float64).reshape(4, 4)
            outline = pose_outline(matrix, (surfaces or {})[row.posed], intrinsics)
        marks.append(Mark(unpack_mask(row.mask, row.bbox, shape), (u0, v0, u1, v1), text, outline))
    return marks


def legend_lines(marks: list[Mark]) -> list[str]:
    """What the overlay's legend explains: the tinted box and its label, and, where the marks show them, the
    unknown answer, the true object in brackets and the posed model's outline."""
    lines = ["tint and box: an object found on the table: its number, and its name (confidence) where named"]
    if any(" unknown" in mark.text for mark in marks):
        lines.append("unknown: unsure, or no pose of a library object fits it")
    if any("[" in mark.text for mark in marks):
        lines.append("[name]: the true object, where the answer differs")
    if any(mark.outline is not None for mark in marks):
        lines.append("outline: the named object's model at its verified pose")
    return lines


def _draw_legend(draw: ImageDraw.ImageDraw, picture: Image.Image, lines: list[str]) -> None:
    """The legend in the frame's bottom-left corner, white on a dark box."""
    font = ImageFont.load_default(size=max(10, picture.height // 40))
    heights = [draw.textbbox((0, 0), line, font=font) for line in lines]
    width = max(right - left for left, _, right, _ in heights) + 8
    height = sum(bottom - top + 3 for _, top, _, bottom in heights) + 6
    top = picture.height - height - 4
    draw.rectangle((4, top, 4 + width, top + height), fill=(0, 0, 0))
    y = top + 3
    for line, (_, line_top, _, line_bottom) in zip(lines, heights):
        draw.text((8, y - line_top), line, fill=(255, 255, 255), font=font)
        y += line_bottom - line_top + 3


def overlay_image(image: np.ndarray, marks: list[Mark]) -> Image.Image:
    """The frame with each mark's pixels tinted, its box drawn and its label written above it, and a legend
    (:func:`legend_lines`) in the bottom-left corner.

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
    for number, mark in enumerate(marks):
        if mark.outline is not None:
            canvas[mark.outline] = TINTS[number % len(TINTS)]
    picture = Image.fromarray(np.round(canvas).astype(np.uint8))
    draw = ImageDraw.Draw(picture)
    font = ImageFont.load_default(size=max(11, picture.height // 32))
    labels: list[tuple[int, int, int, int]] = []  # the label boxes drawn so far, which a new one must not cover
    for number, mark in enumerate(marks):
        tint = TINTS[number % len(TINTS)]
        u0, v0, u1, v1 = mark.bbox
        draw.rectangle((u0, v0, u1, v1), outline=tint, width=2)
        left, top, right, bottom = draw.textbbox((u0, v0), mark.text, font=font)
        width, height = int(right - left) + 4, int(bottom - top) + 4
        x = int(max(0, min(u0, picture.width - width)))  # the label stays inside the frame
        y = _label_row(labels, x, width, height, above=int(v0) - height, below=int(v1) + 2, limit=picture.height)
        labels.append((x, y, x + width, y + height))
        draw.rectangle(labels[-1], fill=(0, 0, 0))
        draw.text((x + 2, y + 2 - (top - v0)), mark.text, fill=tint, font=font)
    if marks:
        _draw_legend(draw, picture, legend_lines(marks))
    return picture


def _label_row(labels: list, x: int, width: int, height: int, *, above: int, below: int, limit: int) -> int:
    """The top of a label ``width`` x ``height`` at ``x``: above its box where that is free, else below it, else
    the nearest free row further up or down; free means inside the frame and over no label drawn before."""

    def free(y: int) -> bool:
        return 0 <= y <= limit - height and not any(
            x < r and r0 < x + width and y < b and t < y + height for r0, t, r, b in labels
        )

    tries = [above, below] + [row for step in range(1, 40) for row in (above - step * height, below + step * height)]
    return next((y for y in tries if free(y)), max(0, min(above, limit - height)))


def save_overlay(path: StrPath, image: np.ndarray, marks: list[Mark]) -> None:
    """Write :func:`overlay_image` as a PNG (written whole, then renamed)."""
    with atomic(path) as temporary:
        overlay_image(image, marks).save(temporary, format="PNG")


def known_curve(scores: pd.DataFrame) -> bytes:
    """The known/unknown curve of a library's scene answers as a PNG: as the confidence threshold rises, the share
    of right answers still said and the share of mistakes said to be unknown.

    Parameters
    ----------
    scores : pandas.DataFrame
        One library's rows of a detection table (:func:`heatdata.experiments.scenes.recognize_scene_files`: every
        detection verified, ``threshold`` the library's).

    Returns
    -------
    bytes
    """
    import io

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    segments = scores[scores["detection"] >= 0]
    right = segments[(segments["truth"] != "") & segments["correct"]]
    wrong = segments[(segments["truth"] == "") | ~segments["correct"]]
    thresholds = np.linspace(0.0, 1.0, 201)

    def said(rows: pd.DataFrame, threshold: float) -> np.ndarray:
        return rows["verified"].to_numpy() & ~(rows["confidence"].to_numpy() < threshold)

    figure, axes = plt.subplots(figsize=(6.0, 3.6), dpi=110)
    if len(right):
        axes.plot(thresholds, [said(right, t).mean() for t in thresholds], label=f"right answers said ({len(right)})")
    if len(wrong):
        rejected = [1.0 - said(wrong, t).mean() for t in thresholds]
        axes.plot(thresholds, rejected, label=f"mistakes said to be unknown ({len(wrong)})")
    limit = float(segments["threshold"].iloc[0]) if len(segments) else float("nan")
    if math.isfinite(limit):
        axes.axvline(limit, color="grey", linestyle="--", label=f"the library's threshold ({limit:.3g})")
    axes.set_xlabel("confidence threshold")
    axes.set_ylabel("share")
    axes.set_ylim(-0.02, 1.02)
    axes.legend(loc="lower left", fontsize=8)
    figure.tight_layout()
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png")
    plt.close(figure)
    return buffer.getvalue()
