"""The ``heatdata`` command.

Exit codes: 0 success; 1 bad input (a heatdata error, its message names the file or
view); 2 wrong command-line usage; 130 interrupted (Ctrl-C).
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
from tqdm.contrib.logging import logging_redirect_tqdm

from heatdata.descriptors import (
    COLOR_KIND,
    DEFAULT_KIND,
    DESCRIPTORS,
    KINDS,
    DescriptorSpec,
    describe,
    file_name,
)
from heatdata.errors import HeatdataError
from heatdata.io.files import atomic, check_folder, check_output, require_file
from heatdata.io.tables import (
    DESCRIPTOR_SCHEMA,
    PREDICTION_SCHEMA,
    read_table,
    write_table,
)
from heatdata.jasnom.defaults import ALONG, ALPHA, BETA, GAMMA, SCAN_ALONG, SCAN_ROBUST
from heatdata.log import progress, setup_logging
from heatdata.recognition.evaluate import TIME_RULES
from heatdata.version import __version__
from heatdata.views.depth import MAX_DEPTH_JUMP

# Each command imports what it alone needs (the renderer's open3d, trimesh, matplotlib), so that a command
# starts in the time its own work needs: `heatdata recognize` answers a frame in under a second.
log = logging.getLogger("heatdata")


def demo_specs() -> list[DescriptorSpec]:
    """The demo's descriptors: the PVHK's sampling and source rules, and a C-PVHK."""
    from heatdata.experiments.demo import DEMO_SPECS

    return [*DEMO_SPECS, DescriptorSpec(COLOR_KIND, 64, "center", "polar", "c3")]


def cmd_demo(args: argparse.Namespace) -> None:
    """Render the embedded objects, describe every view, classify the test views."""
    from heatdata.experiments.demo import describe_and_classify
    from heatdata.experiments.views import view_plan
    from heatdata.io.catalog import embedded_catalog, read_catalog
    from heatdata.recognition.metrics import precision_by_object
    from heatdata.reporting.figures.recognition import plot_confusion, plot_view_confusion
    from heatdata.reporting.figures.views import draw_example_views

    start = time.perf_counter()
    specs = demo_specs()
    args.catalog = args.catalog or embedded_catalog()
    out = check_folder(args.out, inputs=[args.catalog])
    for name in ("descriptors.parquet", "predictions.parquet", "precision.csv", "views.png", "summary.md"):
        check_output(out / name, inputs=[args.catalog])
    catalog = read_catalog(args.catalog)
    if args.objects:
        wanted = args.objects.split(",")
        unknown = sorted(set(wanted) - set(catalog["object"]))
        if unknown:
            raise HeatdataError(f"{args.catalog}: unknown object(s) {unknown}")
        catalog = catalog[catalog["object"].isin(wanted)]
    plan = view_plan(
        catalog["object"].tolist(),
        args.train,
        args.test,
        elevation=args.elevation,
        distance=args.distance,
        seed=args.seed,
    )
    descriptors, predictions = describe_and_classify(catalog, plan, specs, noise=not args.no_noise, jobs=args.jobs)
    run = {k: v for k, v in vars(args).items() if k != "func"}
    write_table(descriptors, out / "descriptors.parquet", DESCRIPTOR_SCHEMA, run)
    write_table(predictions, out / "predictions.parquet", PREDICTION_SCHEMA, run)
    precision = precision_by_object(predictions)
    with atomic(out / "precision.csv") as temporary:
        precision.to_csv(temporary)
    for spec in specs:
        subset = predictions[predictions["descriptor"] == spec.name]
        plot_confusion(subset, out / f"confusion_objects_{file_name(spec.name)}.png", spec.name)
        plot_view_confusion(subset, out / f"confusion_views_{file_name(spec.name)}.png", spec.name)
    draw_example_views(
        catalog,
        out / "views.png",
        elevation=args.elevation,
        distance=args.distance,
        noise=not args.no_noise,
        seed=args.seed,
    )
    summary = _summary_markdown(precision, descriptors, args, time.perf_counter() - start, len(specs))
    with atomic(out / "summary.md") as temporary:
        temporary.write_text(summary)
    print(summary)


def _summary_markdown(
    precision: pd.DataFrame, descriptors: pd.DataFrame, args: argparse.Namespace, seconds: float, kinds: int
) -> str:
    from heatdata.reporting.figures.common import RENDERED_NOTE

    overall = precision.loc["all"].sort_values(ascending=False)
    lines = [
        "# heatdata demo: nearest-neighbour recognition of the embedded objects",
        "",
        f"{RENDERED_NOTE}",
        "",
        f"- objects: {descriptors['object'].nunique()}; library: {args.train} views per object; "
        f"test: {args.test} views per object; elevation {args.elevation} deg; distance {args.distance} m; "
        f"noise {'off' if args.no_noise else 'on (tau = 1.42e-3 1/m)'}; seed {args.seed}",
        f"- views: {descriptors['view_id'].nunique()}, mean {descriptors['n_vertices'].mean():.0f} vertices "
        f"(max {descriptors['n_vertices'].max()})",
        f"- description time per view ({kinds} descriptors, one core): "
        f"{descriptors.groupby('view_id')['seconds'].sum().mean() * 1e3:.0f} ms",
        f"- heatdata {__version__}; wall time {seconds:.0f} s with {args.jobs} processes",
        "",
        "## Object precision (fraction of test views whose nearest library view is the same object)",
        "",
        "| descriptor | precision |",
        "|---|---|",
    ]
    lines += [f"| {name} | {value:.1%} |" for name, value in overall.items()]
    lines += ["", "## Per object", "", precision.map(lambda v: f"{v:.1%}").to_markdown(), ""]
    return "\n".join(lines)


def cmd_render(args: argparse.Namespace) -> None:
    """Render one partial view of a model file to a .npz view file."""
    from heatdata.io.models import load_model
    from heatdata.views.render import render_view

    out = check_output(args.out, inputs=[args.model], suffixes=(".npz",), what="the view")
    model = load_model(args.model, size=tuple(args.size) if args.size else None, scale=args.scale)
    view = render_view(model, args.azimuth, args.elevation, args.distance, noise=not args.no_noise, seed=args.seed)
    view.save(out)
    print(
        json.dumps(
            {
                "view": str(out),
                "vertices": view.n_vertices,
                "faces": len(view.faces),
                "boundary": len(view.boundary),
                "repairs": view.repairs,
            }
        )
    )


def cmd_view_from_depth(args: argparse.Namespace) -> None:
    """A view from real data: a depth image (16-bit PNG in mm, float .npy in m) with intrinsics, or an organized
    cloud (PCD, range-map PLY); written as a .npz view, a coloured .ply, or both."""
    from heatdata.views.depth import read_frame

    inputs = [args.input, args.intrinsics, args.rgb, args.mask]
    outs = [check_output(p, inputs=inputs, suffixes=(".npz", ".ply"), what="the view") for p in args.out]
    if len({p.resolve() for p in outs}) < len(outs):
        raise HeatdataError(f"{' '.join(map(str, outs))}: an output is given twice")
    view = read_frame(
        args.input,
        args.intrinsics,
        args.rgb,
        args.mask,
        depth_range=args.depth_range,
        scale=args.scale,
        max_depth_jump=args.max_depth_jump,
    )
    for out in outs:
        if out.suffix.lower() == ".npz":
            view.save(out)
        else:
            view.to_ply(out)
    print(
        json.dumps(
            {
                "views": [str(p) for p in outs],
                "vertices": view.n_vertices,
                "faces": len(view.faces),
                "boundary": len(view.boundary),
                "repairs": view.repairs,
            }
        )
    )


def cmd_stitch(args: argparse.Namespace) -> None:
    """JASNOM (thesis ch. 7): align the second mesh onto the first by their boundaries and stitch them.

    The output is in the first mesh's frame. It prints the motion, J and its terms, the runner-up's J and the
    seam's mean gap, and warns when another pose is nearly as cheap (ambiguous) or the seam is wide (poor).
    """
    from heatdata.io.models import SUPPORTED_SUFFIXES, load_model, save_model
    from heatdata.jasnom.seam import stitch

    out = check_output(
        args.out, inputs=[args.first, args.second, args.motion], suffixes=SUPPORTED_SUFFIXES, what="the stitched model"
    )
    motion = None
    if args.motion is not None:
        require_file(args.motion, "motion file (a 4x4 matrix)")
        try:
            motion = np.loadtxt(args.motion, ndmin=2)
        except (OSError, ValueError) as error:
            raise HeatdataError(f"{args.motion}: not a 4x4 matrix of numbers ({error})") from error
        if motion.shape != (4, 4):
            raise HeatdataError(f"{args.motion}: not a 4x4 matrix of numbers (shape {motion.shape})")
        motion[:3, 3] *= args.scale
    first, second = (load_model(path, scale=args.scale, center=False) for path in (args.first, args.second))
    result = stitch(
        first,
        second,
        alpha=args.alpha,
        beta=args.beta,
        gamma=args.gamma,
        along=args.along,
        robust=args.robust,
        samples=args.samples,
        scans=args.scans,
        name=out.stem,
        motion=motion,
    )
    save_model(result.model, out)
    a = result.alignment
    if a.ambiguous:
        log.warning(
            "ambiguous: another pose costs nearly as little (J %.4g against %.4g): check the result, or give --motion",
            a.runner_up,
            a.cost,
        )
    if a.poor:
        log.warning(
            "poor: the seam's mean gap is %.1f%% of the size: the boundaries are not one curve here",
            100 * a.gap / a.size,
        )
    summary = {"model": str(out), "vertices": len(result.model.vertices), "faces": len(result.model.faces)}
    summary |= result.summary()
    del summary["facing"]  # a found motion always faces away (align's constraint)
    summary |= {
        "rotation": np.round(a.rotation, 6).tolist(),
        "translation": np.round(a.translation, 6).tolist(),
        "seconds": round(a.seconds, 2),
    }
    print(json.dumps(summary))


def cmd_describe(args: argparse.Namespace) -> None:
    """Describe a saved view; print the descriptor as JSON."""
    from heatdata.views.view import View

    view = View.load(args.view)
    kind = args.kind or (COLOR_KIND if args.color_map else DEFAULT_KIND)
    given = {
        "source": int(args.source) if args.source and args.source.isdigit() else args.source,
        "sampling": args.sampling,
        "color_map": args.color_map,
        "threshold": args.threshold,
    }
    if args.samples is not None:
        given["samples"] = None if args.samples == 0 else args.samples
    for item in args.option:
        key, sep, value = item.partition("=")
        if not sep:
            raise HeatdataError(f"--option {item!r}: give KEY=VALUE")
        given[key] = _option_value(value)
    spec = DescriptorSpec(kind, **given)
    if args.time is not None and not spec.impl.time_scaled:
        raise HeatdataError(f"--time is the fixed time of a time-scaled kind (ft-pvhk); a {spec.kind} takes none")
    if spec.impl.fitted:
        raise HeatdataError(
            f"{args.view}: {spec.kind} is learned on library views first (heatdata.fit_spec, or the "
            "workflow's fit_descriptor rule); one saved view cannot describe itself"
        )
    d = describe(view, [spec], times=None if args.time is None else [args.time])[0]
    out = {
        "descriptor": spec.name,
        "source": d.source,
        "time": d.time,
        "lambda2": d.lambda2,
        "repairs": list(view.repairs) + list(d.repairs),
        "values": np.round(d.values, 8).tolist(),
    }
    if d.weights is not None:
        out["weights"] = np.round(d.weights, 8).tolist()
    print(json.dumps(out))


def cmd_classify(args: argparse.Namespace) -> None:
    """Classify the test rows of a descriptor table against its training rows."""
    from heatdata.recognition.evaluate import classify, evaluate_library_sizes

    if args.out:
        check_output(args.out, inputs=[args.descriptors], suffixes=(".parquet",), what="the predictions")
    descriptors, _ = read_table(args.descriptors, schema=DESCRIPTOR_SCHEMA)
    names = sorted(descriptors["descriptor"].unique()) if args.descriptor is None else [args.descriptor]
    unknown = sorted(set(names) - set(descriptors["descriptor"]))
    if unknown:
        known = sorted(set(descriptors["descriptor"]))
        raise HeatdataError(f"{args.descriptors}: no descriptor {unknown}; it has {known}")
    train = descriptors[descriptors["split"] == "train"].groupby("object")["azimuth"].nunique()
    sizes = args.library_size or [None]
    jobs = [(name, size) for name in names for size in sizes]
    parts = []
    for name, size in progress(jobs, desc="classifying", unit="library"):
        if size is None:  # every train view
            parts.append(classify(descriptors, name, time_rule=args.time_rule).assign(library_size=int(train.max())))
        else:
            parts.append(evaluate_library_sizes(descriptors, name, [size], time_rule=args.time_rule))
    predictions = pd.concat(parts, ignore_index=True)
    if args.out:
        write_table(predictions, args.out, PREDICTION_SCHEMA, {"descriptors": str(args.descriptors)})
    print(_precision_lines(predictions, every_view=args.library_size is None))


def _precision_lines(predictions: pd.DataFrame, every_view: bool) -> str:
    """The object and class precision of each descriptor and library size, as a labelled table."""
    from heatdata.recognition.metrics import precision_table

    table = precision_table(predictions)
    table = table[table["group"] == "all"].pivot_table(
        index=["descriptor", "library_size"], columns="level", values="precision"
    )
    table = table.reset_index().rename(
        columns={"library_size": "library views", "object": "object precision", "class": "class precision"}
    )
    table = table[["descriptor", "library views", "object precision", "class precision"]]
    for column in ("object precision", "class precision"):
        table[column] = table[column].map(lambda v: f"{v:.1%}")
    library = "every train view of each object" if every_view else "library views per object evenly spaced in azimuth"
    head = (
        f"nearest-neighbour precision of {predictions['view_id'].nunique()} test views "
        f"({library}; object: the nearest library view is the same object, class: the same class)"
    )
    return head + "\n" + table.to_string(index=False)


def _option_value(text: str):
    """A command-line option value: a number if it reads as one, else the text."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return None if text == "none" else text


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
    from heatdata.views.depth import read_frame

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
    """One frame recognized as a scene (:meth:`Library.recognize_scene`), and the image an overlay is drawn on.

    A depth image or organized cloud is segmented into the objects on its support plane; a saved view, or a depth
    image cut by ``--mask`` or ``--depth-range``, is one object as it is.
    """
    from heatdata.reporting.figures.scenes import frame_image
    from heatdata.views.depth import read_depth_frame
    from heatdata.views.segment import SegmentSettings, segment_points, segment_view

    settings = SegmentSettings(max_depth_jump=args.max_depth_jump)
    path = Path(frame["depth"])
    suffix = path.suffix.lower()
    if suffix in (".pcd", ".ply") and not (frame["mask"] or args.depth_range):
        from heatdata.views.clouds import read_cloud_grid

        points, colors, intrinsics = read_cloud_grid(path, scale=args.scale)
        segmentation = segment_points(points, intrinsics, colors, settings, name=path.stem)
        return library.recognize_segments(segmentation, k=args.k), frame_image(points[..., 2], colors)
    if suffix == ".npz" or frame["mask"] or args.depth_range:
        view = _read_frame(frame, args)
        note = "a saved view, as it is" if suffix == ".npz" else view.repairs[0]
        image = _view_image(view) if suffix == ".npz" else None
        answer = library.recognize_segments(segment_view(view, note), k=args.k)
        if image is None:
            depth, rgb, _ = read_depth_frame(path, frame["intrinsics"], frame["rgb"])
            image = frame_image(depth, rgb)
        return answer, image
    depth, rgb, intrinsics = read_depth_frame(path, frame["intrinsics"], frame["rgb"])
    answer = library.recognize_scene(depth, intrinsics, rgb, k=args.k, settings=settings, name=path.stem)
    return answer, frame_image(depth, rgb)


def _view_image(view) -> np.ndarray:
    """(h, w, 3) uint8: a saved view drawn back on its image, its colours at its pixels, black elsewhere."""
    k = view.intrinsics
    image = np.zeros((k["height"], k["width"], 3), np.uint8)
    pixels = np.round(view.pixels).astype(int)
    inside = (pixels[:, 0] >= 0) & (pixels[:, 0] < k["width"]) & (pixels[:, 1] >= 0) & (pixels[:, 1] < k["height"])
    image[pixels[inside, 1], pixels[inside, 0]] = np.round(view.colors[inside] * 255).astype(np.uint8)
    return image


def _print_scene(frame: dict, answer, library) -> None:
    """The terminal's answer for one frame: a row per object, then what the frame and each object showed."""
    found = len(answer.detections)
    where = " on the support plane" if answer.plane is not None else ""
    print(f"{frame['depth']}: {found} object{'s' if found != 1 else ''}{where}; {library!r}")
    if not found:
        print(f"no object found ({answer.repairs[-1] if answer.repairs else 'nothing in the frame'})")
        return
    rows = []
    for number, d in enumerate(answer.detections, 1):
        best = None if d.recognition is None else d.recognition.best
        rows.append(
            [
                number,
                d.object or "unknown",
                d.label or "",
                "" if best is None else f"{best.distance:.4g}",
                "" if best is None else f"{best.azimuth:.0f}",
                d.pixels,
                " ".join(f"{c:+.3f}" for c in d.centroid),
                "{},{}-{},{}".format(*d.bbox),
            ]
        )
    columns = ["#", "object", "class", "distance", "azimuth", "pixels", "centroid x y z (m)", "bbox u0,v0-u1,v1"]
    print(pd.DataFrame(rows, columns=columns).to_string(index=False))
    for number, d in enumerate(answer.detections, 1):
        for note in d.notes:
            print(f"  {number}: {note}")
    for note in answer.repairs:
        print(f"  frame: {note}")


def cmd_recognize(args: argparse.Namespace) -> None:
    """What the sensor sees (thesis ch. 3-5): every object of a depth frame or organized cloud, found on its support
    plane and named by its nearest objects in a built library, with where it stands in the camera frame. A frame of
    one isolated object, a saved view, or a depth image cut by --mask or --depth-range is one object. Several frames
    of one object (a folder, or files with --moves, the degrees turned between them) are followed by the particle
    filter of ch. 4 (--exact: the exhaustive filter), which prints the posterior over objects after each frame."""
    from heatdata.recognition.library import load_library

    require_file(args.library, "library")
    frames = _frames(args)
    if len(frames) > 1 and args.moves is None:
        raise HeatdataError(f"{len(frames)} frames: give --moves, the degrees the sensor turned between them")
    if args.overlay is not None:
        if len(frames) > 1 or args.moves is not None:
            raise HeatdataError("--overlay draws one frame's objects; give one frame without --moves")
        check_output(args.overlay, inputs=[f[key] for f in frames for key in ("depth", "rgb", "mask") if f[key]])
        if args.overlay.suffix.lower() != ".png":
            raise HeatdataError(f"{args.overlay}: the overlay is written as a .png")
    library = load_library(args.library)
    if len(frames) == 1 and args.moves is None:
        answer, image = _scene(frames[0], args, library)
        if args.overlay is not None:
            from heatdata.reporting.figures.scenes import detection_marks, save_overlay

            save_overlay(args.overlay, image, detection_marks(answer.detections))
        if args.json:
            print(json.dumps({"frame": frames[0]["depth"], "library": str(args.library), **answer.to_dict()}))
            return
        _print_scene(frames[0], answer, library)
        return
    views = [_read_frame(frame, args) for frame in frames]
    steps = library.recognize_sequence(
        views, args.moves or [0.0], exact=args.exact, particles=args.particles, seed=args.seed
    )
    if args.json:
        print(json.dumps({"library": str(args.library), "exact": args.exact, "steps": [s.to_dict() for s in steps]}))
        return
    print(f"{len(views)} frames; {library!r}; {'exhaustive filter' if args.exact else f'{args.particles} particles'}")
    for step, frame in zip(steps, frames, strict=True):
        top = sorted(step.posterior.items(), key=lambda item: -item[1])[: args.k]
        belief = ", ".join(f"{obj} {p:.2f}" for obj, p in top)
        state = "converged" if step.converged else "not converged"
        print(f"frame {step.frame + 1} ({frame['name']}, moved {step.move:g} deg): {belief} ({state})")
    last = steps[-1]
    print(
        f"{'converged on' if last.converged else 'not converged; most probable:'} {last.estimate} "
        f"({last.posterior[last.estimate]:.0%}) after {len(steps)} frames"
    )


def cmd_kinds(args: argparse.Namespace) -> None:
    """List every descriptor kind, whether this machine can compute it, and its options."""
    for name, kind in KINDS.items():
        reason = DESCRIPTORS[name]
        print(f"{name}: {kind.summary}" + ("" if reason is None else f"\n  UNAVAILABLE here: {reason}"))
        for option in kind.options:
            print(f"  {option.name} (default {option.default!r}): {option.help}")


def cmd_import_sh3f(args: argparse.Namespace) -> None:
    """Extract a Sweet Home 3D furniture library into a catalogue folder."""
    from heatdata.io.sh3f import import_sh3f

    table = import_sh3f(args.sh3f, args.out, name_pattern=args.names, label=args.label, exclude_pattern=args.exclude)
    print(f"{len(table)} models in {Path(args.out) / 'catalog.csv'}")


def _number(low: float | None = None, *, positive: bool = False, whole: bool = False):
    """An argparse type: a finite number (above ``low``; > 0 with ``positive``; an integer with ``whole``)."""

    def parse(text: str):
        try:
            value = int(text) if whole else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a {'whole ' if whole else ''}number") from None
        if not np.isfinite(value) or (positive and value <= 0) or (low is not None and value < low):
            need = "a positive number" if positive else "a finite number" if low is None else f"a number >= {low:g}"
            raise argparse.ArgumentTypeError(f"{text!r}: need {need}")
        return value

    return parse


def _frame_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of a depth frame or an organized cloud (view-from-depth, recognize)."""
    parser.add_argument("--intrinsics", type=Path, help="JSON or YAML: fx, fy, cx, cy, width, height (depth images)")
    parser.add_argument("--rgb", type=Path, help="colour image registered to the depth image")
    parser.add_argument("--mask", type=Path, help="image whose non-zero pixels are the object's")
    parser.add_argument(
        "--depth-range",
        type=_number(0.0),
        nargs=2,
        metavar=("NEAR", "FAR"),
        help="without a mask: keep the pixels between these depths, metres",
    )
    parser.add_argument(
        "--scale",
        type=_number(positive=True),
        default=1.0,
        help="cloud units to metres (default 1; MeshLab range maps are often mm: 0.001)",
    )
    parser.add_argument(
        "--max-depth-jump",
        type=_number(positive=True),
        default=MAX_DEPTH_JUMP,
        help=f"relative depth step that cuts the mesh (default {MAX_DEPTH_JUMP})",
    )


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="heatdata",
        description="Heat-diffusion descriptors of partial 3D views.",
        epilog="Exit codes: 0 success; 1 bad input (the message names the file or view); 2 wrong usage. "
        "The full experiment with a report is the Snakemake workflow: snakemake --cores 2",
    )
    parser.add_argument("--version", action="version", version=f"heatdata {__version__}")
    parser.add_argument("-v", "--verbose", action="store_true", help="debug logging")
    sub = parser.add_subparsers(dest="command", required=True)

    demo = sub.add_parser(
        "demo",
        help="render, describe and classify the embedded objects without Snakemake",
        description=cmd_demo.__doc__,
    )
    demo.add_argument("--catalog", type=Path, help="catalogue CSV (default: the embedded models)")
    demo.add_argument("--objects", help="comma-separated object ids (default: all in the catalogue)")
    demo.add_argument("--out", default="results/demo", help="output folder (default: results/demo)")
    demo.add_argument("--train", type=_number(1, whole=True), default=40, help="library views per object (default 40)")
    demo.add_argument("--test", type=_number(1, whole=True), default=120, help="test views per object (default 120)")
    demo.add_argument("--elevation", type=_number(), default=30.0, help="view elevation, degrees (default 30)")
    demo.add_argument(
        "--distance", type=_number(positive=True), default=1.0, help="camera distance, metres (default 1)"
    )
    demo.add_argument("--seed", type=int, default=0, help="noise seed (default 0)")
    demo.add_argument("--no-noise", action="store_true", help="render without sensor noise")
    demo.add_argument(
        "--jobs", type=_number(1, whole=True), default=os.cpu_count() or 1, help="processes (default: all cores)"
    )
    demo.set_defaults(func=cmd_demo)

    render = sub.add_parser("render", help="render one partial view of a model", description=cmd_render.__doc__)
    render.add_argument("model", type=Path, help="OBJ, PLY, STL, OFF or GLB file")
    render.add_argument("--out", type=Path, required=True, help="output .npz view (its folder is created)")
    render.add_argument(
        "--azimuth", type=_number(), default=0.0, help="camera azimuth about the model's +y axis, degrees (default 0)"
    )
    render.add_argument("--elevation", type=_number(), default=30.0, help="camera elevation, degrees (default 30)")
    render.add_argument(
        "--distance",
        type=_number(positive=True),
        default=1.0,
        help="camera distance from the model's centre, metres (default 1)",
    )
    render.add_argument(
        "--size",
        type=_number(0.0),
        nargs=3,
        metavar=("W", "H", "D"),
        help="real size in metres (width x, height y, depth z)",
    )
    render.add_argument("--scale", type=_number(positive=True), default=1.0, help="file units to metres (default 1)")
    render.add_argument("--seed", type=_number(0, whole=True), default=0, help="seed of the sensor noise (default 0)")
    render.add_argument("--no-noise", action="store_true", help="render without the Kinect noise of thesis 2.6.1")
    render.set_defaults(func=cmd_render)

    depth = sub.add_parser(
        "view-from-depth",
        help="a view from a depth image or an organized point cloud",
        description=cmd_view_from_depth.__doc__,
    )
    depth.add_argument("input", type=Path, help="depth image (.png 16-bit mm, .npy float m) or cloud (.pcd, .ply)")
    depth.add_argument(
        "-o",
        "--out",
        type=Path,
        required=True,
        action="append",
        help="output .npz view and/or .ply mesh with colours (repeatable)",
    )
    _frame_arguments(depth)
    depth.set_defaults(func=cmd_view_from_depth)

    join = sub.add_parser(
        "stitch",
        help="JASNOM: one model from two non-overlapping meshes (thesis ch. 7)",
        description=cmd_stitch.__doc__,
    )
    join.add_argument(
        "first", type=Path, help="the mesh that stays put: the output is in its frame (PLY, OBJ, OFF, STL, GLB)"
    )
    join.add_argument("second", type=Path, help="the mesh moved onto it")
    join.add_argument("-o", "--out", type=Path, required=True, help="the stitched mesh (.ply keeps vertex colours)")
    join.add_argument(
        "--alpha",
        type=_number(positive=True),
        default=ALPHA,
        help=f"steepness of the interpenetration penalty, relative to the sampling (default {ALPHA:g})",
    )
    join.add_argument(
        "--beta",
        type=_number(0.0),
        default=BETA,
        help=f"weight of the interpenetration penalty J2, eq. 7.4; 0 to patch a hole (default {BETA:g})",
    )
    join.add_argument(
        "--gamma", type=_number(0.0), default=GAMMA, help=f"weight of the crease term J3 (default {GAMMA:g})"
    )
    join.add_argument(
        "--scans",
        action="store_true",
        help="the meshes are depth scans, each in its camera's frame (camera at the origin), taken from "
        "opposite sides (the object flipped): the alignment keeps each on the far side from the "
        "other's camera and tolerates the band of surface neither saw",
    )
    join.add_argument(
        "--along",
        type=_number(0.0),
        help="weight of the gap along the seam's continuation in J1: below 1 tolerates a band of "
        f"unseen surface (default {ALONG:g}; with --scans {SCAN_ALONG:g})",
    )
    join.add_argument(
        "--robust",
        type=_number(0.0),
        help=f"soft-L1 width of the residuals, in boundary radii (default 0: squares; with --scans {SCAN_ROBUST:g})",
    )
    join.add_argument(
        "--samples",
        type=_number(8, whole=True),
        default=128,
        help="boundary samples for the alignment; the coarse search tries twice as many (default 128)",
    )
    join.add_argument("--scale", type=_number(positive=True), default=1.0, help="file units to metres (default 1)")
    join.add_argument(
        "--motion",
        type=Path,
        help="a known motion of the second mesh into the first's frame (registered cameras): a text "
        "file with a 4x4 matrix, translation in file units; nothing is searched",
    )
    join.set_defaults(func=cmd_stitch)

    desc = sub.add_parser(
        "describe", help="any descriptor of a saved view (PVHK by default)", description=cmd_describe.__doc__
    )
    desc.add_argument("view", type=Path, help=".npz view written by 'heatdata render'")
    desc.add_argument("--samples", type=int, help="boundary samples (default 64); 0: one per boundary vertex")
    desc.add_argument("--source", help="closest (default), center, interior or a vertex index")
    desc.add_argument("--sampling", choices=["arclength", "polar"], help="boundary sampling (default arclength)")
    desc.add_argument("--color-map", default=None, help=f"c1, c2, c3, c4, hue or sat-hue: compute a {COLOR_KIND}")
    desc.add_argument(
        "--kind",
        choices=list(KINDS),
        help=f"default {DEFAULT_KIND}, or {COLOR_KIND} with "
        "--color-map; 'heatdata kinds' lists every kind and its options",
    )
    desc.add_argument(
        "--option",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="any other option of the kind, e.g. --option seed=3 for an esf (repeatable)",
    )
    desc.add_argument("--time", type=float, help="the fixed time of an ft-pvhk (the object's time scale, Alg. 5.1)")
    desc.add_argument("--threshold", type=float, help="the pvst's threshold T_a (default 0.75 of equilibrium)")
    desc.set_defaults(func=cmd_describe)

    cls = sub.add_parser(
        "classify", help="nearest-neighbour precision of a descriptor table", description=cmd_classify.__doc__
    )
    cls.add_argument("descriptors", type=Path, help="descriptors.parquet")
    cls.add_argument("--descriptor", help="descriptor name (default: every one in the table)")
    cls.add_argument(
        "--library-size",
        type=_number(1, whole=True),
        action="append",
        metavar="N",
        help="library views per object, evenly spaced in azimuth among the train views "
        "(repeatable; default: every train view)",
    )
    cls.add_argument(
        "--time-rule",
        choices=TIME_RULES,
        default=TIME_RULES[0],
        help="which objects an ft-pvhk test view is compared with, each at its time scale: plausible "
        "(default: those whose time scale is at most the view's own 1/lambda_2) or every",
    )
    cls.add_argument("--out", type=Path, help="write predictions.parquet here")
    cls.set_defaults(func=cmd_classify)

    rec = sub.add_parser(
        "recognize",
        help="the objects a depth frame (or a sequence) is nearest in a built library (thesis ch. 3-5)",
        description=cmd_recognize.__doc__,
        epilog="E.g. heatdata recognize depth.png --intrinsics camera.json "
        "--library results/libraries/hgd_color=hue-saturation-40.parquet",
    )
    rec.add_argument(
        "frames",
        type=Path,
        nargs="+",
        help="depth image (.png 16-bit mm, .npy m), organized cloud (.pcd, .ply), view (.npz), or a folder of them",
    )
    rec.add_argument("--library", type=Path, required=True, help="a library file (results/libraries/*.parquet)")
    _frame_arguments(rec)
    rec.add_argument(
        "-k", type=_number(1, whole=True), default=5, help="nearest objects to keep per object (default 5)"
    )
    rec.add_argument("--json", action="store_true", help="print JSON for programs")
    rec.add_argument("--overlay", type=Path, help="draw the frame with each object tinted, boxed and named (a .png)")
    rec.add_argument(
        "--moves",
        type=_number(),
        nargs="+",
        metavar="DEG",
        help="degrees the sensor turned between frames: one per gap, or one for all (a sequence)",
    )
    rec.add_argument("--exact", action="store_true", help="a sequence by the exhaustive filter, not particles")
    rec.add_argument("--particles", type=_number(1, whole=True), default=100, help="particles (default 100)")
    rec.add_argument("--seed", type=_number(0, whole=True), default=0, help="the particle filter's seed (default 0)")
    rec.set_defaults(func=cmd_recognize)

    kinds = sub.add_parser("kinds", help="list the descriptor kinds and their options", description=cmd_kinds.__doc__)
    kinds.set_defaults(func=cmd_kinds)

    imp = sub.add_parser(
        "import-sh3f",
        help="import a Sweet Home 3D furniture library",
        description=f"{cmd_import_sh3f.__doc__} E.g. after 'apt-get install sweethome3d-furniture': "
        "heatdata import-sh3f /usr/share/sweethome3d/furniture/Scopia.sh3f models/ --names chair",
    )
    imp.add_argument("sh3f", type=Path)
    imp.add_argument("out", type=Path)
    imp.add_argument("--names", help="regular expression on the furniture names")
    imp.add_argument("--label", help="class for every imported model (default: its name)")
    imp.add_argument("--exclude", help="regular expression of furniture names to leave out")
    imp.set_defaults(func=cmd_import_sh3f)
    return parser


def _without_open3d_viewer() -> None:
    """Spare the command open3d's web viewer: ``import open3d`` imports ``open3d.visualization.draw_plotly``, and
    with it plotly and dash (0.3 s of a 0.5 s import), which no command draws with. A stand-in module that refuses
    to draw takes its place in this process; code that imports heatdata as a library is left as it is."""
    if "open3d" in sys.modules or OPEN3D_VIEWER in sys.modules:
        return
    import types

    def refuse(*args, **kwargs):
        raise RuntimeError("open3d's plotly viewer is not loaded in the heatdata command")

    viewer = types.ModuleType(OPEN3D_VIEWER, "open3d's plotly viewer, not loaded in the heatdata command")
    viewer.get_plotly_fig = viewer.draw_plotly = viewer.draw_plotly_server = refuse  # type: ignore[attr-defined]
    sys.modules[OPEN3D_VIEWER] = viewer


OPEN3D_VIEWER = "open3d.visualization.draw_plotly"


def main(argv: list[str] | None = None) -> int:
    _without_open3d_viewer()
    parser = build_parser()
    args = parser.parse_args(argv)
    setup_logging(args.verbose)
    try:
        with logging_redirect_tqdm(loggers=[logging.root]):  # log lines print above a progress bar
            args.func(args)
    except HeatdataError as exc:
        log.error("%s", exc)
        return 1
    except OSError as exc:  # the system refused a file operation: its own message names the file
        log.error("%s", exc)
        return 1
    except KeyboardInterrupt:  # outputs are written atomically: none is left half written
        log.error("interrupted; no output was left half written")
        return 130
    return 0


if __name__ == "__main__":
    sys.exit(main())
