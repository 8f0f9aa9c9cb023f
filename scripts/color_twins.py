"""Colour twins (issue 17; thesis 3.4): how often each descriptor tells an object from its hue-turned twin.

Reads a run of ``config/experiments/twins.yaml`` (its predictions and catalogue; nothing is described again) and writes,
per descriptor and library size, the object precision over every test view (``all``) and over the views of
the objects that have a twin (``pairs``), the share of those views whose prediction is the object or its twin
(``shape``: the shape was right), and among those the share that picked the right one of the two (``colour``;
chance is 50%). ``--figure`` draws the last, pair by pair, at the largest library.

    .venv/bin/python scripts/color_twins.py results/twins --out docs/results/twins_precision.csv \\
        --figure docs/images/colour_twins.png
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from heatdata.io.tables import read_table


def twin_table(results: Path) -> pd.DataFrame:
    """The run's test predictions with ``pair`` (the original object's id, empty without a twin) for both views."""
    catalog = pd.read_csv(results / "catalog.csv", keep_default_na=False)
    twins = catalog[catalog["hue"].astype(str).str.strip() != ""]
    original_of = {t: t.rsplit("-hue", 1)[0] for t in twins["object"]}
    original_of.update({o: o for o in original_of.values()})
    predictions, _ = read_table(results / "evaluation" / "predictions.parquet")
    predictions["pair"] = predictions["object"].map(original_of).fillna("")
    predictions["predicted_pair"] = predictions["predicted_object"].map(original_of).fillna("")
    return predictions


def summary(predictions: pd.DataFrame) -> pd.DataFrame:
    rows = []
    for (name, size), group in predictions.groupby(["descriptor", "library_size"]):
        paired = group[group["pair"] != ""]
        shape = paired[paired["predicted_pair"] == paired["pair"]]
        rows.append(
            {
                "descriptor": name,
                "library_size": size,
                "all": group["correct"].mean(),
                "pairs": paired["correct"].mean(),
                "shape": len(shape) / len(paired),
                "colour": shape["correct"].mean(),
                "test_views": len(group),
            }
        )
    return pd.DataFrame(rows).round(4)


def figure(predictions: pd.DataFrame, path: Path) -> None:
    size = predictions["library_size"].max()
    paired = predictions[(predictions["pair"] != "") & (predictions["library_size"] == size)]
    shape = paired[paired["predicted_pair"] == paired["pair"]]
    table = 100 * shape.groupby(["descriptor", "pair"])["correct"].mean().unstack()
    table = table.loc[pd.unique(shape["descriptor"])]  # the run's order: its config's
    table["all pairs"] = 100 * shape.groupby("descriptor")["correct"].mean()
    fig, ax = plt.subplots(figsize=(11, 0.45 * len(table) + 1.6))
    ax.imshow(table.to_numpy(), cmap="RdYlGn", vmin=40, vmax=100, aspect="auto")
    for (i, j), value in np.ndenumerate(table.to_numpy()):
        ax.text(j, i, f"{value:.0f}", ha="center", va="center", fontsize=8)
    ax.set_xticks(range(len(table.columns)), table.columns, rotation=20)
    ax.set_yticks(range(len(table)), [name.replace("/polar/center/64", "") for name in table.index])
    ax.set_title(
        f"Colour twins: % of views that pick the right one of an object and its hue-turned twin "
        f"(shape right; chance 50)\n{size} library views; rendered views, not real sensor data",
        fontsize=10,
    )
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", type=Path, help="the results folder of a config/experiments/twins.yaml run")
    parser.add_argument("--out", help="CSV to write")
    parser.add_argument("--figure", type=Path, help="PNG of the colour column, pair by pair")
    args = parser.parse_args()
    predictions = twin_table(args.results)
    table = summary(predictions)
    print(table.to_string(index=False))
    if args.out:
        table.to_csv(args.out, index=False)
    if args.figure:
        figure(predictions, args.figure)


if __name__ == "__main__":
    main()
