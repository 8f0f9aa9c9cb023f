"""Overlays of a recognized scene: the frame with each detection's pixels tinted, boxed and named.

Drawn with Pillow (no matplotlib), so ``heatdata recognize --overlay`` costs a few milliseconds.
"""

from __future__ import annotations

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from heatdata.io.files import atomic
from heatdata.typing import StrPath

#: one tint per detection, in order (colour-blind-safe, Okabe & Ito)
TINTS = [(230, 159, 0), (86, 180, 233), (0, 158, 115), (240, 228, 66), (0, 114, 178), (213, 94, 0), (204, 121, 167)]
ALPHA = 0.45  # the tint's weight over the frame


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


def overlay_image(image: np.ndarray, detections: list, *, truth: list[str] | None = None) -> Image.Image:
    """The frame with each detection tinted, its bounding box drawn and labelled ``number object (distance)``.

    Parameters
    ----------
    image : (h, w, 3) uint8
        The frame (:func:`frame_image`).
    detections : list of Detection
        With their masks (:meth:`heatdata.recognition.library.Library.recognize_scene`).
    truth : list of str, optional
        The true object of each detection ("" for none), drawn after the answer where it differs.

    Returns
    -------
    PIL.Image.Image
    """
    canvas = np.asarray(image, np.float64).copy()
    for number, detection in enumerate(detections):
        if detection.mask is not None:
            colour = np.array(TINTS[number % len(TINTS)], np.float64)
            canvas[detection.mask] = (1 - ALPHA) * canvas[detection.mask] + ALPHA * colour
    picture = Image.fromarray(np.round(canvas).astype(np.uint8))
    draw = ImageDraw.Draw(picture)
    font = ImageFont.load_default(size=max(11, picture.height // 32))
    for number, detection in enumerate(detections):
        tint = TINTS[number % len(TINTS)]
        u0, v0, u1, v1 = detection.bbox
        draw.rectangle((u0, v0, u1, v1), outline=tint, width=2)
        text = f"{number + 1} {detection.object or 'unknown'}"
        if np.isfinite(detection.distance):
            text += f" ({detection.distance:.3g})"
        if truth is not None and truth[number] != (detection.object or ""):
            text += f" [{truth[number] or 'no object'}]"
        left, top, right, bottom = draw.textbbox((u0, v0), text, font=font)
        y = v0 - (bottom - top) - 4 if v0 - (bottom - top) - 4 >= 0 else v1 + 2
        draw.rectangle((u0, y, u0 + right - left + 4, y + bottom - top + 4), fill=(0, 0, 0))
        draw.text((u0 + 2, y + 2 - (top - v0)), text, fill=tint, font=font)
    return picture


def save_overlay(path: StrPath, image: np.ndarray, detections: list, *, truth: list[str] | None = None) -> None:
    """Write :func:`overlay_image` as a PNG (written whole, then renamed)."""
    with atomic(path) as temporary:
        overlay_image(image, detections, truth=truth).save(temporary, format="PNG")
