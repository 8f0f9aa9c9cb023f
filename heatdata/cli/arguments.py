"""Argument types and option groups shared by the ``heatdata`` commands."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from heatdata.views.depth import MAX_DEPTH_JUMP

#: the most boundary samples a descriptor takes (a flat 1920 x 1080 view's boundary has 6,000 vertices)
MAX_BOUNDARY_SAMPLES = 4096
#: the most views per object a command renders (one every 0.1 degree)
MAX_VIEWS = 3600
#: the arguments that name what a command writes; every other path a command is given is one it reads
OUTPUT_ARGUMENTS = ("out", "overlay")


def command_inputs(args: argparse.Namespace, *found) -> list[Path]:
    """Every file a command reads, for :func:`heatdata.io.files.check_output`: each path among its arguments but its
    outputs (:data:`OUTPUT_ARGUMENTS`), and ``found``, the files it finds beside them (a frame's ``<name>.json``, a
    library's index). Checking the arguments themselves, not a list per command, covers an option added later.

    Parameters
    ----------
    args : argparse.Namespace
        The command's parsed arguments.
    *found : str or Path or None
        Files the command reads that no argument names (None and "" are skipped).

    Returns
    -------
    list of Path
    """
    given = [value for name, value in vars(args).items() if name not in OUTPUT_ARGUMENTS]
    flat = [item for value in given for item in (value if isinstance(value, (list, tuple)) else [value])]
    return [item for item in flat if isinstance(item, Path)] + [Path(item) for item in found if item]


def _plain(value):
    """``value`` in JSON's own types: NaN and infinities as null, numpy's numbers as Python's."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return None
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 2**53:
        return float(value) if abs(value) < 1e308 else None  # JSON readers hold 53-bit integers
    return value


def dump_json(value) -> str:
    """Strict JSON of a command's answer for programs: no NaN or Infinity (null instead), no integer a reader
    cannot hold.

    Parameters
    ----------
    value : dict
        The answer.

    Returns
    -------
    str
    """
    return json.dumps(_plain(value), allow_nan=False)


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
            shown = (lambda v: f"{v:.0f}") if whole else (lambda v: f"{v:g}")
            need = (
                "a positive number" if positive else "a finite number" if low is None else f"a number >= {shown(low)}"
            )
            if high is not None:
                need = f"a number in [{shown(low)}, {shown(high)}]" if low is not None else f"a number <= {shown(high)}"
            raise argparse.ArgumentTypeError(f"{text!r}: need {need}")
        return value

    return parse


def frame_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of a depth frame or an organized cloud (view-from-depth, recognize)."""
    parser.add_argument(
        "--intrinsics", type=Path, help="JSON or YAML: fx, fy, cx, cy, width, height (depth images, unorganized PCDs)"
    )
    parser.add_argument("--rgb", type=Path, help="colour image registered to the depth image")
    parser.add_argument("--mask", type=Path, help="image whose non-zero pixels are the object's")
    parser.add_argument(
        "--depth-range",
        type=number(0.0),
        nargs=2,
        metavar=("NEAR", "FAR"),
        help="keep the pixels between these depths, metres (with --mask: the pixels both keep)",
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


def segment_arguments(parser: argparse.ArgumentParser) -> None:
    """The segmentation's settings a user reaches (segment, recognize; defaults measured on real table-tops,
    :class:`heatdata.segmentation.settings.SegmentSettings`)."""
    from heatdata.segmentation.settings import SegmentSettings

    defaults = SegmentSettings()
    parser.add_argument(
        "--cluster-distance",
        type=number(positive=True),
        default=defaults.cluster_distance,
        help=f"metres: a reading this near an object's surface joins it (default {defaults.cluster_distance})",
    )
    parser.add_argument(
        "--min-pixels",
        type=number(3, whole=True),
        default=defaults.min_pixels,
        help=f"smaller objects are dropped, and said so (default {defaults.min_pixels})",
    )
    parser.add_argument(
        "--concavity",
        type=number(positive=True, high=179.0),
        default=defaults.concavity,
        help=f"degrees: surfaces meeting at a sharper concave crease are two objects (default {defaults.concavity:g})",
    )


def segment_settings(args: argparse.Namespace):
    """The :class:`heatdata.segmentation.settings.SegmentSettings` of :func:`segment_arguments`' options and
    ``--max-depth-jump``."""
    from heatdata.segmentation.settings import SegmentSettings

    return SegmentSettings(
        cluster_distance=args.cluster_distance,
        min_pixels=args.min_pixels,
        concavity=args.concavity,
        max_depth_jump=args.max_depth_jump,
    )
