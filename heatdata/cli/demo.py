"""``heatdata demo``: the main job's experiment without Snakemake, in one process pool."""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import pandas as pd

from heatdata.cli.arguments import MAX_VIEWS, command_inputs, number
from heatdata.descriptors import COLOR_KIND, DescriptorSpec, file_name
from heatdata.errors import HeatdataError
from heatdata.io.files import atomic, check_folder, check_output
from heatdata.io.tables import DESCRIPTOR_SCHEMA, PREDICTION_SCHEMA, write_table
from heatdata.version import __version__


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
    out = check_folder(args.out, inputs=command_inputs(args))
    for name in ("descriptors.parquet", "predictions.parquet", "precision.csv", "views.png", "summary.md"):
        check_output(out / name, inputs=command_inputs(args))
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


def add_demo(sub) -> None:
    """The ``demo`` command's arguments, on the ``heatdata`` parser's subcommands ``sub``."""
    demo = sub.add_parser(
        "demo",
        help="render, describe and classify the embedded objects without Snakemake",
        description=cmd_demo.__doc__,
    )
    demo.add_argument("--catalog", type=Path, help="catalogue CSV (default: the embedded models)")
    demo.add_argument("--objects", help="comma-separated object ids (default: all in the catalogue)")
    demo.add_argument("--out", default="results/demo", help="output folder (default: results/demo)")
    demo.add_argument(
        "--train", type=number(1, high=MAX_VIEWS, whole=True), default=40, help="library views per object (default 40)"
    )
    demo.add_argument(
        "--test", type=number(1, high=MAX_VIEWS, whole=True), default=120, help="test views per object (default 120)"
    )
    demo.add_argument("--elevation", type=number(), default=30.0, help="view elevation, degrees (default 30)")
    demo.add_argument("--distance", type=number(positive=True), default=1.0, help="camera distance, metres (default 1)")
    demo.add_argument("--seed", type=int, default=0, help="noise seed (default 0)")
    demo.add_argument("--no-noise", action="store_true", help="render without sensor noise")
    demo.add_argument(
        "--jobs", type=number(1, whole=True), default=os.cpu_count() or 1, help="processes (default: all cores)"
    )
    demo.set_defaults(func=cmd_demo)
