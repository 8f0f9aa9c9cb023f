"""The ``heatdata`` command.

Exit codes: 0 success; 1 bad input (a heatdata error, its message names the file or
view); 2 wrong command-line usage; 130 interrupted (Ctrl-C); 143 terminated (SIGTERM).
"""

from __future__ import annotations

import argparse
import logging
import sys
from pathlib import Path

import numpy as np
import pandas as pd
from tqdm.contrib.logging import logging_redirect_tqdm

from heatdata.cli.arguments import (
    MAX_BOUNDARY_SAMPLES,
    MAX_VIEWS,
    command_inputs,
    dump_json,
    frame_arguments,
    number,
)
from heatdata.cli.demo import add_demo
from heatdata.cli.recognize import add_index, add_recognize
from heatdata.cli.segment import add_segment
from heatdata.cli.stitch import add_stitch
from heatdata.descriptors import (
    COLOR_KIND,
    DEFAULT_DESCRIPTOR,
    DEFAULT_KIND,
    DESCRIPTORS,
    KINDS,
    THRESHOLD_KIND,
    DescriptorSpec,
    describe,
)
from heatdata.descriptors.base import article, kind_of
from heatdata.errors import HeatdataError, Terminated, did_you_mean
from heatdata.io.files import check_output
from heatdata.io.tables import (
    DESCRIPTOR_SCHEMA,
    PREDICTION_SCHEMA,
    read_table,
    write_table,
)
from heatdata.log import printable, progress, setup_logging
from heatdata.recognition.evaluate import TIME_RULES
from heatdata.version import __version__

# Each command imports what it alone needs (the renderer's open3d, trimesh, matplotlib), so that a command
# starts in the time its own work needs: `heatdata recognize` answers a frame in under a second.
log = logging.getLogger("heatdata")


def cmd_render(args: argparse.Namespace) -> None:
    """Render one partial view of a model file to a .npz view file."""
    from heatdata.io.catalog import UNITS
    from heatdata.io.models import load_model
    from heatdata.views.render import render_view

    out = check_output(args.out, inputs=command_inputs(args), suffixes=(".npz",), what="the view")
    size = tuple(args.size) if args.size else None
    model = load_model(args.model, size=size, scale=args.scale * UNITS[args.units], up_axis=args.up_axis)
    view = render_view(model, args.azimuth, args.elevation, args.distance, noise=not args.no_noise, seed=args.seed)
    view.save(out)
    _print_view(view, [out], args.json)


def add_render(sub) -> None:
    """The ``render`` command's arguments."""
    render = sub.add_parser("render", help="render one partial view of a model", description=cmd_render.__doc__)
    render.add_argument("model", type=Path, help="OBJ, PLY, STL, OFF or GLB file")
    render.add_argument("-o", "--out", type=Path, required=True, help="output .npz view (its folder is created)")
    render.add_argument("--json", action="store_true", help="print JSON for programs")
    render.add_argument(
        "--azimuth", type=number(), default=0.0, help="camera azimuth about the model's +y axis, degrees (default 0)"
    )
    render.add_argument("--elevation", type=number(), default=30.0, help="camera elevation, degrees (default 30)")
    render.add_argument(
        "--distance",
        type=number(positive=True),
        default=1.0,
        help="camera distance from the model's centre, metres (default 1)",
    )
    render.add_argument(
        "--size",
        type=number(0.0),
        nargs=3,
        metavar=("W", "H", "D"),
        help="real size in metres (width x, height y, depth z)",
    )
    render.add_argument("--scale", type=number(positive=True), default=1.0, help="file units to metres (default 1)")
    render.add_argument(
        "--units", choices=("m", "cm", "mm"), default="m", help="the file's units, times --scale (default m)"
    )
    render.add_argument(
        "--up-axis",
        choices=("y", "z"),
        default="y",
        help="the file's up axis: z for YCB, BOP and most CAD and scanner files (default y)",
    )
    render.add_argument("--seed", type=number(0, whole=True), default=0, help="seed of the sensor noise (default 0)")
    render.add_argument("--no-noise", action="store_true", help="render without the Kinect noise of thesis 2.6.1")
    render.set_defaults(func=cmd_render)


def cmd_view_from_depth(args: argparse.Namespace) -> None:
    """A view from real data: a depth image (16-bit PNG in mm, float .npy in m) with intrinsics, or a cloud (PCD of
    any DATA kind, unorganized ones with --intrinsics; a range-map or range-grid PLY); written as a .npz view, a
    coloured .ply mesh and/or a .pcd cloud that PCL reads (binary_compressed, with colour)."""
    from heatdata.frames.clouds import read_frame
    from heatdata.frames.pcd import write_view_pcd

    inputs = command_inputs(args)
    outs = [check_output(p, inputs=inputs, suffixes=(".npz", ".ply", ".pcd"), what="the view") for p in args.out]
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
    view.write([p for p in outs if p.suffix.lower() != ".pcd"])
    for out in outs:
        if out.suffix.lower() == ".pcd":
            write_view_pcd(view, out)
    _print_view(view, outs, args.json)


def add_view_from_depth(sub) -> None:
    """The ``view-from-depth`` command's arguments."""
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
        help="output .npz view, .ply mesh with colours and/or .pcd cloud (repeatable)",
    )
    frame_arguments(depth)
    depth.add_argument("--json", action="store_true", help="print JSON for programs")
    depth.set_defaults(func=cmd_view_from_depth)


def _print_view(view, outs: list[Path], as_json: bool) -> None:
    """What a command that writes a view prints: a line a person reads and its repairs, or JSON (``--json``)."""
    if as_json:
        summary = {"vertices": view.n_vertices, "faces": len(view.faces), "boundary": len(view.boundary)}
        print(dump_json({"views": [str(p) for p in outs], **summary, "repairs": view.repairs}))
        return
    print(
        f"{', '.join(map(str, outs))}: {view.n_vertices:,} vertices, {len(view.faces):,} faces, "
        f"{len(view.boundary):,} on the outer boundary"
    )
    for repair in view.repairs:
        print(f"  {repair}")


def _implied_kind(args: argparse.Namespace) -> str:
    """The kind ``describe``'s options ask for when ``--kind`` is not given: the default descriptor's unless a
    colour map, a PVST threshold or a boundary option names a heat kind."""
    if args.color_map:
        return COLOR_KIND
    if args.threshold is not None:
        return THRESHOLD_KIND
    if args.samples is not None or args.source is not None or args.sampling is not None:
        return DEFAULT_KIND
    return DEFAULT_DESCRIPTOR.kind


def cmd_describe(args: argparse.Namespace) -> None:
    """Describe a saved view; print the descriptor as JSON."""
    from heatdata.views.view import View

    view = View.load(args.view)
    given = {
        "source": int(args.source) if args.source and args.source.isdigit() else args.source,
        "sampling": args.sampling,
        "color_map": args.color_map,
        "threshold": args.threshold,
    }
    kind = args.kind or _implied_kind(args)
    if kind == DEFAULT_DESCRIPTOR.kind and not args.kind:
        given.update(DEFAULT_DESCRIPTOR.options)
    if args.samples is not None:
        given["samples"] = None if args.samples == 0 else args.samples
    for item in args.option:
        key, sep, value = item.partition("=")
        if not sep:
            raise HeatdataError(f"--option {item!r}: give KEY=VALUE")
        given[key] = _option_value(value)
    spec = DescriptorSpec(kind, **given)
    if args.time is not None and not spec.impl.time_scaled:
        raise HeatdataError(
            f"--time is the fixed time of a time-scaled kind (ft-pvhk); {article(spec.kind)} {spec.kind} takes none"
        )
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
    print(dump_json(out))


def _kind_name(name: str) -> str:
    """argparse's check of ``--kind``: a registered kind, else an error with the nearest name."""
    try:
        return kind_of(name).name
    except HeatdataError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def add_describe(sub) -> None:
    """The ``describe`` command's arguments."""
    desc = sub.add_parser(
        "describe",
        help="any descriptor of a saved view (the default descriptor unless told)",
        description=cmd_describe.__doc__,
    )
    desc.add_argument("view", type=Path, help=".npz view written by 'heatdata render'")
    desc.add_argument(
        "--samples",
        type=number(0, high=MAX_BOUNDARY_SAMPLES, whole=True),
        help=f"boundary samples (default 64, at most {MAX_BOUNDARY_SAMPLES}); 0: one per boundary vertex",
    )
    desc.add_argument("--source", help="closest (default), center, interior or a vertex index")
    desc.add_argument("--sampling", choices=["arclength", "polar"], help="boundary sampling (default arclength)")
    desc.add_argument("--color-map", default=None, help=f"c1, c2, c3, c4, hue or sat-hue: compute a {COLOR_KIND}")
    desc.add_argument(
        "--kind",
        type=_kind_name,
        help=f"one of {', '.join(KINDS)}; "
        f"default: the default descriptor ({DEFAULT_DESCRIPTOR.name}); a {DEFAULT_KIND} with --samples, "
        f"--source or --sampling, a {COLOR_KIND} with --color-map, a {THRESHOLD_KIND} with --threshold; "
        "'heatdata kinds' lists every kind and its options",
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


def cmd_classify(args: argparse.Namespace) -> None:
    """Classify the test rows of a descriptor table against its training rows."""
    from heatdata.recognition.evaluate import classify, evaluate_library_sizes

    if args.out:
        check_output(args.out, inputs=command_inputs(args), suffixes=(".parquet",), what="the predictions")
    descriptors, _ = read_table(args.descriptors, schema=DESCRIPTOR_SCHEMA)
    names = sorted(descriptors["descriptor"].unique()) if args.descriptor is None else [args.descriptor]
    unknown = sorted(set(names) - set(descriptors["descriptor"]))
    if unknown:
        known = sorted(set(descriptors["descriptor"]))
        raise HeatdataError(
            f"{args.descriptors}: no descriptor {unknown}{did_you_mean(unknown[0], known)}; it has {known}"
        )
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


def add_classify(sub) -> None:
    """The ``classify`` command's arguments."""
    cls = sub.add_parser(
        "classify", help="nearest-neighbour precision of a descriptor table", description=cmd_classify.__doc__
    )
    cls.add_argument("descriptors", type=Path, help="descriptors.parquet")
    cls.add_argument("--descriptor", help="descriptor name (default: every one in the table)")
    cls.add_argument(
        "--library-size",
        type=number(1, high=MAX_VIEWS, whole=True),
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
    table["descriptor"] = table["descriptor"].map(printable)  # a table's names come from a file
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


def cmd_kinds(args: argparse.Namespace) -> None:
    """List every descriptor kind, whether this machine can compute it, and its options."""
    for name, kind in KINDS.items():
        reason = DESCRIPTORS[name]
        print(f"{name}: {kind.summary}\n  " + ("available here" if reason is None else f"UNAVAILABLE here: {reason}"))
        for option in kind.options:
            print(f"  {option.name} (default {option.default!r}): {option.help}")


def add_kinds(sub) -> None:
    """The ``kinds`` command's arguments."""
    kinds = sub.add_parser("kinds", help="list the descriptor kinds and their options", description=cmd_kinds.__doc__)
    kinds.set_defaults(func=cmd_kinds)


def cmd_import_sh3f(args: argparse.Namespace) -> None:
    """Extract a Sweet Home 3D furniture library into a catalogue folder."""
    from heatdata.io.sh3f import import_sh3f

    table = import_sh3f(
        args.sh3f,
        args.out,
        name_pattern=args.names,
        label=args.label,
        exclude_pattern=args.exclude,
        classes=args.classes,
    )
    print(f"{len(table)} models in {Path(args.out) / 'catalog.csv'}")


def add_import_sh3f(sub) -> None:
    """The ``import-sh3f`` command's arguments."""
    imp = sub.add_parser(
        "import-sh3f",
        help="import a Sweet Home 3D furniture library",
        description=f"{cmd_import_sh3f.__doc__} E.g. after 'apt-get install sweethome3d-furniture': "
        "heatdata import-sh3f /usr/share/sweethome3d/furniture/Scopia.sh3f models/ --names chair",
    )
    imp.add_argument("sh3f", type=Path, help="a Sweet Home 3D furniture library (.sh3f)")
    imp.add_argument("out", type=Path, help="the catalogue folder: catalog.csv and one folder per model")
    imp.add_argument("--names", help="regular expression on the furniture names")
    imp.add_argument("--label", help="class for every imported model (default: as --classes says)")
    imp.add_argument(
        "--classes",
        choices=("name", "category"),
        default="name",
        help="without --label, each model's class: its furniture name (default) or its catalogue category",
    )
    imp.add_argument("--exclude", help="regular expression of furniture names or object ids to leave out")
    imp.set_defaults(func=cmd_import_sh3f)


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

    for add in (add_demo, add_render, add_view_from_depth, add_segment, add_stitch, add_describe, add_classify,
                add_recognize, add_index, add_kinds, add_import_sh3f):  # fmt: skip
        add(sub)
    for command in sub.choices.values():  # -v after the command too: heatdata recognize ... -v
        command.add_argument("-v", "--verbose", action="store_true", default=argparse.SUPPRESS, help="debug logging")
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
    except KeyboardInterrupt as exc:  # outputs are written atomically: none is left half written
        terminated = isinstance(exc, Terminated)
        log.error("%s; no output was left half written", "terminated" if terminated else "interrupted")
        return 143 if terminated else 130
    return 0
