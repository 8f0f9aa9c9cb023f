"""``heatdata recognize``: every object of a frame, one object, or a sequence of frames, against a built library."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from heatdata.cli.arguments import (
    command_inputs,
    dump_json,
    frame_arguments,
    number,
    segment_arguments,
    segment_settings,
)
from heatdata.descriptors import DEFAULT_DESCRIPTOR, file_name
from heatdata.errors import HeatdataError, did_you_mean
from heatdata.io.files import check_output, require_file
from heatdata.log import printable
from heatdata.recognition.multiview.filters import MAX_PARTICLES


def _frames(args: argparse.Namespace) -> list[dict]:
    """The frames to recognize: the files given, or the frames of one folder (``find_frames``)."""
    from heatdata.experiments.captures import FRAME_SUFFIXES, find_frames

    if len(args.frames) == 1 and Path(args.frames[0]).is_dir():
        if args.intrinsics or args.rgb or args.mask:
            raise HeatdataError(
                f"{args.frames[0]}: the frames of a folder carry their own <name>.json, <name>.rgb.png and "
                "<name>.mask.png (or a camera.json); --intrinsics, --rgb and --mask are for one frame"
            )
        return find_frames(args.frames[0])
    frames = []
    for path in args.frames:
        require_file(path, "frame")
        if Path(path).suffix.lower() not in FRAME_SUFFIXES:
            raise HeatdataError(f"{path}: a frame is a depth image (.png, .npy), a cloud (.pcd, .ply) or a view (.npz)")
        frames.append({"name": Path(path).stem, "depth": str(path), "intrinsics": "", "rgb": "", "mask": ""})
    if (args.rgb or args.mask) and len(frames) > 1:
        raise HeatdataError("--rgb and --mask belong to one frame; give a folder of frames for a sequence")
    for frame in frames:
        frame.update(intrinsics=str(args.intrinsics or ""), rgb=str(args.rgb or ""), mask=str(args.mask or ""))
    return frames


def _read_frame(frame: dict, args: argparse.Namespace):
    """A frame's view: a saved view, or a depth image or organized cloud (``read_frame``)."""
    if Path(frame["depth"]).suffix.lower() == ".npz":
        from heatdata.views.view import View

        return View.load(frame["depth"])
    from heatdata.frames.clouds import read_frame

    return read_frame(
        frame["depth"],
        frame["intrinsics"],
        frame["rgb"],
        frame["mask"],
        depth_range=args.depth_range,
        scale=args.scale,
        max_depth_jump=args.max_depth_jump,
    )


def _scene(frame: dict, args: argparse.Namespace, library):
    """One frame recognized as a scene (:meth:`Library.recognize_scene`), the image an overlay is drawn on, and the
    camera's intrinsics.

    A depth image (its readings in ``--mask`` or ``--depth-range``, when given) or an organized cloud is segmented
    into the objects on its support plane, or into the one object it holds; a saved view is one object as it is.
    """
    from heatdata.frames.clouds import CLOUD_SUFFIXES
    from heatdata.reporting.figures.scenes import frame_image
    from heatdata.segmentation.segment import segment_points, segment_view
    from heatdata.views.depth import read_depth_frame, read_image, read_intrinsics

    settings = segment_settings(args)
    path = Path(frame["depth"])
    suffix = path.suffix.lower()
    if suffix == ".npz":
        view = _read_frame(frame, args)
        segmentation = segment_view(view, "a saved view, as it is")
        answer = library.recognize_segments(segmentation, k=args.k, threshold=args.threshold, pose=not args.no_pose)
        return answer, _view_image(view), view.intrinsics
    if suffix in CLOUD_SUFFIXES:
        if frame["mask"] or args.depth_range:
            _read_frame(frame, args)  # refuses them, as for every cloud
        from heatdata.frames.clouds import read_cloud_grid

        camera = read_intrinsics(frame["intrinsics"]) if frame["intrinsics"] else None
        points, colors, intrinsics = read_cloud_grid(path, scale=args.scale, intrinsics=camera)
        segmentation = segment_points(points, intrinsics, colors, settings, name=path.stem)
        answer = library.recognize_segments(segmentation, k=args.k, threshold=args.threshold, pose=not args.no_pose)
        return answer, frame_image(points[..., 2], colors), intrinsics
    depth, rgb, intrinsics = read_depth_frame(path, frame["intrinsics"], frame["rgb"])
    mask = read_image(frame["mask"], "mask", "L") > 0 if frame["mask"] else None
    answer = library.recognize_scene(
        depth,
        intrinsics,
        rgb,
        k=args.k,
        settings=settings,
        mask=mask,
        depth_range=args.depth_range,
        name=path.stem,
        threshold=args.threshold,
        pose=not args.no_pose,
    )
    return answer, frame_image(depth, rgb), intrinsics


def _view_image(view) -> np.ndarray:
    """(h, w, 3) uint8: a saved view drawn back on its image, its colours at its pixels, black elsewhere."""
    k = view.intrinsics
    image = np.zeros((k["height"], k["width"], 3), np.uint8)
    pixels = np.round(view.pixels).astype(int)
    inside = (pixels[:, 0] >= 0) & (pixels[:, 0] < k["width"]) & (pixels[:, 1] >= 0) & (pixels[:, 1] < k["height"])
    image[pixels[inside, 1], pixels[inside, 0]] = np.round(view.colors[inside] * 255).astype(np.uint8)
    return image


def say(line: str) -> None:
    """Print one line of the terminal's answer, its control characters escaped (:func:`heatdata.log.printable`):
    the names in it come from files."""
    print(printable(line))


def _print_scene(frame: dict, answer, library) -> None:
    """The terminal's answer for one frame: a row per object, then what the frame and each object showed."""
    found = len(answer.detections)
    where = " on the support plane" if answer.plane is not None else ""
    say(f"{frame['depth']}: {found} object{'s' if found != 1 else ''}{where}; {library!r}")
    if not found:
        say(f"no object found ({answer.repairs[-1] if answer.repairs else 'nothing in the frame'})")
        return
    rows = []
    for rank, d in enumerate(answer.detections, 1):
        best = None if d.recognition is None else d.recognition.answer
        pose = d.pose
        rows.append(
            [
                rank,
                printable(d.object or "unknown"),
                printable(d.label or ""),
                "" if np.isnan(d.confidence) else f"{d.confidence:.2f}",
                "" if best is None else f"{best.distance:.4g}",
                "" if best is None else f"{best.azimuth:.0f}",
                "" if pose is None else " ".join(f"{c:+.3f}" for c in pose.matrix[:3, 3]),
                "" if pose is None else f"{pose.fitness:.2f}",
                "" if pose is None or np.isnan(pose.rmse) else f"{pose.rmse * 1000:.1f}",
                d.pixels,
                " ".join(f"{c:+.3f}" for c in d.centroid),
                "{},{}-{},{}".format(*d.bbox),
            ]
        )
    columns = [
        "#", "object", "class", "confidence", "distance", "azimuth", "position x y z (m)", "fitness", "rmse (mm)",
        "pixels", "centroid x y z (m)", "bbox u0,v0-u1,v1",
    ]  # fmt: skip
    print(pd.DataFrame(rows, columns=columns).to_string(index=False))
    for rank, d in enumerate(answer.detections, 1):
        if d.recognition is not None and d.object is None:
            say(f"  {rank}: {_unknown(d.recognition)}")
        if d.pose is not None and d.object is not None:
            matrix = "; ".join(" ".join(f"{x:+.4f}" for x in row) for row in d.pose.matrix[:3])
            say(f"  {rank}: pose of the {d.pose.object} (model to camera, rows of [R | t]): [{matrix}]")
        for note in d.notes:
            say(f"  {rank}: {note}")
    for note in answer.repairs:
        say(f"  frame: {note}")


def _unknown(answer) -> str:
    """Why an answer is unknown: its confidence, or no candidate's pose explaining the segment."""
    if not answer.confident:
        return f"unknown: nearest {answer.best.object}, confidence {answer.confidence:.2f} < {answer.threshold:.3g}"
    pose = answer.pose
    return (
        f"unknown: no candidate's pose explains it (nearest {answer.best.object}, confidence {answer.confidence:.2f}; "
        f"its best pose leaves {1 - pose.explained:.0%} of the points farther than {pose.tolerance * 100:.1f} cm "
        f"from its surface and puts {pose.in_front:.0%} of its visible surface in front of the measured depth)"
    )


def cmd_recognize(args: argparse.Namespace) -> None:
    """What the sensor sees (thesis ch. 3-5): every object of a depth frame or organized cloud, found on its support
    plane and named by its nearest objects in a built library, with where it stands in the camera frame: its 6-DoF
    pose by ICP from the nearest library view, verified against the frame's depth (an answer no candidate's pose
    explains, or below the confidence threshold, is unknown). --mask or
    --depth-range keep part of a depth frame (each object in it is still one answer); a frame of one isolated object,
    or a saved view, is one object. Several frames
    of one object (a folder, or files with --moves, the degrees turned between them) are followed by the particle
    filter of ch. 4 (--exact: the exhaustive filter), which prints the posterior over objects after each frame.
    A library is searched through its index (name.faiss beside it, or built when it loads); --exact compares every
    library view."""
    from heatdata.recognition.index import index_path
    from heatdata.recognition.library import load_library

    args.library = _library_file(args.library)
    frames = _frames(args)
    if len(frames) > 1 and args.moves is None:
        raise HeatdataError(f"{len(frames)} frames: give --moves, the degrees the sensor turned between them")
    if args.overlay is not None:
        if len(frames) > 1 or args.moves is not None:
            raise HeatdataError("--overlay draws one frame's objects; give one frame without --moves")
        beside = [f[key] for f in frames for key in ("depth", "intrinsics", "rgb", "mask")]
        inputs = command_inputs(args, *beside, index_path(args.library))
        check_output(args.overlay, inputs=inputs, suffixes=(".png",), what="the overlay")
    library = load_library(args.library, index=not args.exact)
    if len(frames) == 1 and args.moves is None:
        answer, image, intrinsics = _scene(frames[0], args, library)
        if args.overlay is not None:
            from heatdata.reporting.figures.scenes import detection_marks, save_overlay

            save_overlay(args.overlay, image, detection_marks(answer.detections, library.surfaces, intrinsics))
            print(f"overlay written to {printable(str(args.overlay))}", file=sys.stderr)
        if args.json:
            print(dump_json({"frame": frames[0]["depth"], "library": str(args.library), **answer.to_dict()}))
            return
        _print_scene(frames[0], answer, library)
        return
    if args.no_pose:
        raise HeatdataError("--no-pose is for the objects of one frame; a sequence is not posed")
    views = [_read_frame(frame, args) for frame in frames]
    steps = library.recognize_sequence(
        views, args.moves or [0.0], exact=args.exact, particles=args.particles, seed=args.seed, threshold=args.threshold
    )
    if args.json:
        print(dump_json({"library": str(args.library), "exact": args.exact, "steps": [s.to_dict() for s in steps]}))
        return
    say(f"{len(views)} frames; {library!r}; {'exhaustive filter' if args.exact else f'{args.particles} particles'}")
    for step, frame in zip(steps, frames, strict=True):
        top = sorted(step.posterior.items(), key=lambda item: -item[1])[: args.k]
        belief = ", ".join(f"{obj} {p:.2f}" for obj, p in top)
        if step.unknown > 0:
            belief += f"; none of them {step.unknown:.2f}"
        state = "converged" if step.converged else "not converged"
        say(f"frame {step.frame + 1} ({frame['name']}, moved {step.move:g} deg): {belief} ({state})")
    last = steps[-1]
    if last.estimate is None:
        said = f"an object the library lacks ({last.unknown:.0%})"
    else:
        said = f"{last.estimate} ({last.posterior[last.estimate]:.0%})"
    say(f"{'converged on' if last.converged else 'not converged; most probable:'} {said} after {len(steps)} frames")


#: the library ``recognize`` reads when none is named: the main job's, of the default descriptor (the workflow's
#: ``primary_descriptor``) at its largest library size, 40 views an object
DEFAULT_LIBRARY = Path("libraries") / f"{file_name(DEFAULT_DESCRIPTOR.name)}-40.parquet"


def _library_file(given: Path | None) -> Path:
    """The library ``recognize`` reads: ``given``, or the main job's of the default descriptor; when it is not there,
    an error that lists the libraries beside it, or says how to build them."""
    path = Path("results") / DEFAULT_LIBRARY if given is None else given
    if path.is_file():
        return path
    what = "no --library given, and the main job's library of the default descriptor is not there"
    what = what if given is None else "no such library"
    found = sorted(p.name for p in path.parent.glob("*.parquet")) if path.parent.is_dir() else []
    if found:
        raise HeatdataError(f"{path}: {what}{did_you_mean(path.name, found)}; {path.parent} holds {', '.join(found)}")
    raise HeatdataError(f"{path}: {what}; build the libraries with snakemake --cores 2 (the main job)")


def add_recognize(sub) -> None:
    """The ``recognize`` command's arguments, on the ``heatdata`` parser's subcommands ``sub``."""
    rec = sub.add_parser(
        "recognize",
        help="the objects a depth frame (or a sequence) is nearest in a built library (thesis ch. 3-5)",
        description=cmd_recognize.__doc__,
        epilog=f"E.g. heatdata recognize depth.png --intrinsics camera.json --library results/{DEFAULT_LIBRARY}",
    )
    rec.add_argument(
        "frames",
        type=Path,
        nargs="+",
        help="depth image (.png 16-bit mm, .npy m), organized cloud (.pcd, .ply), view (.npz), or a folder of them",
    )
    rec.add_argument(
        "--library",
        type=Path,
        help=f"a library file (default results/{DEFAULT_LIBRARY}: the main job's, of the default descriptor)",
    )
    frame_arguments(rec)
    segment_arguments(rec)
    rec.add_argument(
        "-k", type=number(1, high=1000, whole=True), default=5, help="nearest objects to keep per object (default 5)"
    )
    rec.add_argument("--json", action="store_true", help="print JSON for programs")
    rec.add_argument(
        "--threshold",
        type=number(0.0, high=1.0),
        help="confidence below which an object is unknown, in [0, 1] (default: none where poses are checked, as the "
        "pose check decides what is unknown; with --no-pose or for a sequence, the library's, which rejects 95%% of "
        "its own objects left out of it): higher rejects more objects the library lacks, and more that it holds; "
        "for a sequence, the prior of its unknown hypothesis",
    )
    rec.add_argument(
        "--no-pose",
        action="store_true",
        help="skip each object's 6-DoF pose (ICP) and its verification: faster, and every confident answer is said",
    )
    rec.add_argument(
        "--overlay",
        type=Path,
        help="draw the frame with each object tinted, boxed and named, and its posed model outlined (a .png)",
    )
    rec.add_argument(
        "--moves",
        type=number(),
        nargs="+",
        metavar="DEG",
        help="degrees the sensor turned between frames: one per gap, or one for all (a sequence)",
    )
    rec.add_argument(
        "--exact",
        action="store_true",
        help="compare every library view, not through the library's index; a sequence by the exhaustive filter, "
        "not particles",
    )
    rec.add_argument(
        "--particles",
        type=number(1, high=MAX_PARTICLES, whole=True),
        default=100,
        help=f"particles (default 100, at most {MAX_PARTICLES:,})",
    )
    rec.add_argument("--seed", type=number(0, whole=True), default=0, help="the particle filter's seed (default 0)")
    rec.set_defaults(func=cmd_recognize)


def cmd_index(args: argparse.Namespace) -> None:
    """Build a library's search index and write it beside the library file (name.faiss beside name.parquet), where
    heatdata recognize and load_library read it. A library without one still answers: it builds one in memory each
    time it loads (seconds at hundreds of thousands of views). The index finds candidates fast; the kind's own
    distance ranks them (see the recognition guide's section on large libraries)."""
    from heatdata.recognition.library import write_library_index

    require_file(args.library, "library")
    written = write_library_index(args.library)
    say(f"{written}: the index of {args.library}")


def add_index(sub) -> None:
    """The ``index`` command's arguments, on the ``heatdata`` parser's subcommands ``sub``."""
    index = sub.add_parser(
        "index",
        help="write a library's search index beside it (name.faiss)",
        description=cmd_index.__doc__,
        epilog=f"E.g. heatdata index results/{DEFAULT_LIBRARY}",
    )
    index.add_argument("library", type=Path, help="a library file (results/libraries/*.parquet)")
    index.set_defaults(func=cmd_index)
