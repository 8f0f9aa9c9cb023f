"""``heatdata segment``: a frame's objects as a label image, the segmentation that ``recognize`` uses."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from heatdata.cli.arguments import command_inputs, dump_json, number, segment_arguments, segment_settings
from heatdata.errors import HeatdataError
from heatdata.io.files import atomic, check_output
from heatdata.log import printable


def cmd_segment(args: argparse.Namespace) -> None:
    """Segment a frame into the objects on its support plane: a 16-bit label image of the frame's size (0 for no
    object, 1..N for the objects, largest first), a line per object, and an overlay picture with --overlay."""
    from PIL import Image

    from heatdata.frames.clouds import read_frame_grid
    from heatdata.segmentation.segment import label_image, segment_points

    inputs = command_inputs(args)
    out = check_output(args.out, inputs=inputs, suffixes=(".png",), what="the label image")
    overlay = None if args.overlay is None else check_output(args.overlay, inputs=inputs, suffixes=(".png",))
    if overlay is not None and overlay.resolve() == out.resolve():
        raise HeatdataError(f"{out}: the label image and the overlay are one file")
    settings = segment_settings(args)
    points, colors, intrinsics = read_frame_grid(args.frame, args.intrinsics, args.rgb, scale=args.scale)
    found = segment_points(points, intrinsics, colors, settings, name=Path(args.frame).stem)
    labels = label_image(found, points.shape[:2])
    with atomic(out) as temporary:
        Image.fromarray(labels).save(temporary, format="PNG")
    if overlay is not None:
        from heatdata.reporting.figures.scenes import Mark, frame_image, save_overlay

        marks = [Mark(s.mask, s.bbox, str(n)) for n, s in enumerate(found.segments, start=1)]
        save_overlay(overlay, frame_image(points[..., 2], colors), marks)
        print(f"overlay written to {printable(str(overlay))}", file=sys.stderr)
    if args.json:
        rows = [
            {
                "label": n,
                "pixels": s.pixels,
                "bbox": list(s.bbox),
                "centroid": [round(float(c), 4) for c in s.centroid],
                "extent": round(float(s.extent), 4),
                "notes": s.notes,
            }
            for n, s in enumerate(found.segments, start=1)
        ]
        plane = None if found.plane is None else [round(float(c), 6) for c in found.plane]
        print(dump_json({"labels": str(out), "plane": plane, "segments": rows, "notes": found.notes}))
        return
    print(f"{out}: {len(found.segments)} object(s) in a {points.shape[1]}x{points.shape[0]} frame")
    for n, segment in enumerate(found.segments, start=1):
        x, y, z = segment.centroid
        notes = f"  ({'; '.join(segment.notes)})" if segment.notes else ""
        where = f"({x:+.3f}, {y:+.3f}, {z:.3f}) m, {segment.extent:.3f} m across"
        print(f"  {n:3d}: {segment.pixels:7,} px at {where}{notes}")
    for note in found.notes:
        print(f"  {note}")


def add_segment(sub) -> None:
    """The ``segment`` command's arguments."""
    from heatdata.views.depth import MAX_DEPTH_JUMP

    parser = sub.add_parser("segment", help="a frame's objects as a label image", description=cmd_segment.__doc__)
    parser.add_argument("frame", type=Path, help="depth image (.png 16-bit mm, .npy float m) or cloud (.pcd, .ply)")
    parser.add_argument("-o", "--out", type=Path, required=True, help="the 16-bit label image to write (.png)")
    parser.add_argument(
        "--intrinsics", type=Path, help="JSON or YAML: fx, fy, cx, cy, width, height (depth images, unorganized PCDs)"
    )
    parser.add_argument("--rgb", type=Path, help="colour image registered to the depth image")
    parser.add_argument("--overlay", type=Path, help="also draw the objects over the frame (.png)")
    parser.add_argument("--scale", type=number(positive=True), default=1.0, help="cloud units to metres (default 1)")
    segment_arguments(parser)
    parser.add_argument(
        "--max-depth-jump",
        type=number(positive=True),
        default=MAX_DEPTH_JUMP,
        help=f"relative depth step between two objects (default {MAX_DEPTH_JUMP})",
    )
    parser.add_argument("--json", action="store_true", help="print JSON for programs")
    parser.set_defaults(func=cmd_segment)
