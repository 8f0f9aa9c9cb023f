"""Argument types and option groups shared by the ``heatdata`` commands."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from heatdata.views.depth import MAX_DEPTH_JUMP


def number(low: float | None = None, *, high: float | None = None, positive: bool = False, whole: bool = False):
    """An argparse type: a finite number (at least ``low``, at most ``high``; > 0 with ``positive``; an integer with
    ``whole``)."""

    def parse(text: str):
        try:
            value = int(text) if whole else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a {'whole ' if whole else ''}number") from None
        too_high = high is not None and value > high
        if not np.isfinite(value) or (positive and value <= 0) or (low is not None and value < low) or too_high:
            need = "a positive number" if positive else "a finite number" if low is None else f"a number >= {low:g}"
            if high is not None:
                need = f"a number in [{low:g}, {high:g}]" if low is not None else f"a number <= {high:g}"
            raise argparse.ArgumentTypeError(f"{text!r}: need {need}")
        return value

    return parse


def frame_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of a depth frame or an organized cloud (view-from-depth, recognize)."""
    parser.add_argument("--intrinsics", type=Path, help="JSON or YAML: fx, fy, cx, cy, width, height (depth images)")
    parser.add_argument("--rgb", type=Path, help="colour image registered to the depth image")
    parser.add_argument("--mask", type=Path, help="image whose non-zero pixels are the object's")
    parser.add_argument(
        "--depth-range",
        type=number(0.0),
        nargs=2,
        metavar=("NEAR", "FAR"),
        help="without a mask: keep the pixels between these depths, metres",
    )
    parser.add_argument(
        "--scale",
        type=number(positive=True),
        default=1.0,
        help="cloud units to metres (default 1; MeshLab range maps are often mm: 0.001)",
    )
    parser.add_argument(
        "--max-depth-jump",
        type=number(positive=True),
        default=MAX_DEPTH_JUMP,
        help=f"relative depth step that cuts the mesh (default {MAX_DEPTH_JUMP})",
    )
