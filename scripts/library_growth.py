"""How precision falls as a library grows: object and class precision against the number of objects it holds.

    .venv/bin/python scripts/library_growth.py results/furniture_all --described --objects 14 58 200 all \\
        --draws 5 --out docs/results/library_growth.csv --figure docs/images/library_growth.png

The run's objects are put in a random order (one per draw, seeded), and a library of N objects holds the first N: so
the libraries of one draw are nested, and each larger one adds objects to the smaller. Every test view of the N
objects is classified against the library views of the N (:func:`heatdata.recognition.evaluate.evaluate_library_sizes`,
as the classify rule does, at each library size of views per object). Object precision is the share of test views
whose nearest library view is of their own object; class precision the share whose nearest view is of their class
(for the furniture run, the Sweet Home 3D catalogue's category: living room, kitchen, ...). A library of every object
is the same in every draw and is measured once (``all``: every object the run holds). Rendered views, not real
sensor data.

``--described`` reads the run's per-object tables (``descriptors/<object>.parquet``) instead of its collected
``descriptors.parquet``: the objects described so far, for a run too long to wait for (every Sweet Home 3D model
takes hours on 2 cores). It says how many objects that is.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import pandas as pd

from heatdata.descriptors import DescriptorSpec
from heatdata.io.tables import read_metadata, read_table
from heatdata.recognition.evaluate import CLASSIFY_COLUMNS, evaluate_library_sizes


def growth(
    descriptors: pd.DataFrame, names: list[str], counts: list[int | str], sizes: list[int], draws: int
) -> pd.DataFrame:
    """One row per draw, number of objects, descriptor and library size: object and class precision."""
    objects = np.array(sorted(descriptors["object"].unique()))
    rows = []
    for count in [len(objects) if c == "all" else int(c) for c in counts]:
        if count > len(objects):
            raise SystemExit(f"--objects {count}: the run has {len(objects)} objects")
        for draw in range(1 if count == len(objects) else draws):
            chosen = np.random.default_rng(draw).permutation(objects)[:count]
            subset = descriptors[descriptors["object"].isin(chosen)]
            for name in names:
                start = time.perf_counter()
                predictions = evaluate_library_sizes(subset, name, sizes)
                for size, answers in predictions.groupby("library_size"):
                    rows.append(
                        {
                            "descriptor": name,
                            "objects": count,
                            "library_size": int(size),
                            "draw": draw,
                            "classes": subset["label"].nunique(),
                            "test_views": len(answers),
                            "object_precision": float(answers["correct"].mean()),
                            "class_precision": float((answers["predicted_label"] == answers["label"]).mean()),
                        }
                    )
                print(
                    f"{count} objects, draw {draw}, {name}: "
                    + ", ".join(f"{r['library_size']} views {r['object_precision']:.3f}" for r in rows[-len(sizes) :])
                    + f" ({time.perf_counter() - start:.0f} s)",
                    flush=True,
                )
    return pd.DataFrame(rows)


def summary(draws: pd.DataFrame) -> pd.DataFrame:
    """Mean, lowest and highest precision over the draws (and the mean number of classes the objects fall in)."""
    keys = ["descriptor", "library_size", "objects"]
    table = draws.groupby(keys, sort=False).agg(
        classes=("classes", "mean"),
        draws=("draw", "size"),
        test_views=("test_views", "first"),
        object_precision=("object_precision", "mean"),
        object_lowest=("object_precision", "min"),
        object_highest=("object_precision", "max"),
        class_precision=("class_precision", "mean"),
        class_lowest=("class_precision", "min"),
        class_highest=("class_precision", "max"),
    )
    return table.reset_index().round(4)


def figure(table: pd.DataFrame, path: Path, what: str) -> None:
    """Object and class precision against the number of objects, a line per descriptor and library size."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2), sharey=True)
    colours = dict(zip(table["descriptor"].unique(), plt.get_cmap("tab10").colors, strict=False))
    styles = dict(zip(sorted(table["library_size"].unique(), reverse=True), ["-", "--", ":"], strict=False))
    for axis, (column, title) in zip(axes, [("object", "object precision"), ("class", "class precision")], strict=True):
        for (name, size), rows in table.groupby(["descriptor", "library_size"], sort=False):
            axis.errorbar(
                rows["objects"],
                rows[f"{column}_precision"],
                yerr=[
                    rows[f"{column}_precision"] - rows[f"{column}_lowest"],
                    rows[f"{column}_highest"] - rows[f"{column}_precision"],
                ],
                color=colours[name],
                linestyle=styles[size],
                marker="o",
                markersize=4,
                capsize=3,
                label=f"{name}, {size} views",
            )
        axis.set_xscale("log")
        axis.set_xticks(sorted(table["objects"].unique()), [str(n) for n in sorted(table["objects"].unique())])
        axis.minorticks_off()
        axis.set_xlabel("objects in the library")
        axis.set_title(title)
        axis.grid(alpha=0.3)
        axis.set_ylim(0, 1)
    axes[0].set_ylabel("share of test views")
    axes[1].legend(fontsize=8, loc="lower left")
    fig.suptitle(f"{what}: rendered views, not sensor data (bars: lowest and highest of the draws)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def objects_count(text: str) -> int | str:
    """A number of objects, or ``all``."""
    if text == "all":
        return text
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: a number of objects, or all") from None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", type=Path, help="a run's results folder (descriptors.parquet)")
    parser.add_argument(
        "--objects", nargs="+", required=True, type=objects_count, help="library sizes in objects ('all': every one)"
    )
    parser.add_argument(
        "--described", action="store_true", help="read the objects described so far (descriptors/*.parquet)"
    )
    parser.add_argument("--views", type=int, nargs="+", default=[40, 12], help="library views per object (40 12)")
    parser.add_argument("--draws", type=int, default=5, help="random orders of the objects (default 5)")
    parser.add_argument("--out", type=Path, required=True, help="the table to write (.csv)")
    parser.add_argument("--figure", type=Path, help="the figure to write (.png)")
    args = parser.parse_args()
    start = time.perf_counter()
    columns = [*CLASSIFY_COLUMNS, "time_object", "weights"]
    tables = (
        sorted((args.run / "descriptors").glob("*.parquet")) if args.described else [args.run / "descriptors.parquet"]
    )
    if not tables or not tables[0].is_file():
        raise SystemExit(f"{args.run}: no descriptor table{' described yet' if args.described else ''}")
    names = [DescriptorSpec.from_dict(entry).name for entry in read_metadata(tables[0])["descriptors"]]
    descriptors = pd.concat([read_table(path, columns=columns)[0] for path in tables], ignore_index=True)
    if args.described:
        print(f"{args.run}: {descriptors['object'].nunique()} objects described so far", flush=True)
    draws = growth(descriptors, names, args.objects, args.views, args.draws)
    result = summary(draws)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    result.to_csv(args.out, index=False)
    print(result.to_string(index=False))
    if args.figure:
        figure(result, args.figure, f"{descriptors['object'].nunique()} Sweet Home 3D models")
    print(f"{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
