"""How much of the HGD's colour option is colour (issue 28): colour alone, shape alone, and each shape with colour.

The HGD with ``color: hue-saturation`` is its shape histogram (weight 1/2) followed by an area-weighted colour
histogram (weight 1/2), under one chi-square distance. This script reads a run's descriptor table, which must
hold ``esf``, ``hgd`` and ``hgd/color=hue-saturation``, takes the colour part out of the last, and scores by
the workflow's protocol (the nearest library view among ``n`` per object evenly spaced in azimuth, over every
test view): the colour part alone, the ESF and the HGD alone, and each with the same colour part appended with
the same weight. So the ESF gets the colour the HGD gets, and a gain is not put down to the wrong part.

    .venv/bin/python scripts/color_share.py results/chairs_12/descriptors.parquet \\
        --out docs/results/chairs_12_colour_share.csv

Rendered views, not real sensor data. One row per variant and library size.
"""

from __future__ import annotations

import argparse

import numpy as np
import pandas as pd

from heatdata.core.distances import chi_square_matrix
from heatdata.descriptors.hgd import HUES
from heatdata.io.tables import read_table
from heatdata.recognition.evaluate import library_subset

NAMES = ("esf", "hgd", "hgd/color=hue-saturation")
COLOUR_BINS = 2 * HUES + 1
CHUNK = 256  # queries per distance matrix (memory)


def variants(path: str) -> tuple[pd.DataFrame, dict[str, np.ndarray]]:
    """The views (one row each) and each variant's (views, bins) histograms, in the views' order."""
    table, _ = read_table(
        path,
        columns=["descriptor", "object", "view_id", "split", "azimuth", "values"],
        filters=[("descriptor", "in", list(NAMES))],
    )
    missing = sorted(set(NAMES) - set(table["descriptor"]))
    if missing:
        raise SystemExit(
            f"color_share: {path} has no descriptor {', '.join(missing)} (config/experiments/chairs.yaml has them)"
        )
    by_name = {name: rows.set_index("view_id") for name, rows in table.groupby("descriptor")}
    views = by_name["hgd"].reset_index()[["view_id", "object", "split", "azimuth"]]

    def stacked(name):
        return np.stack(by_name[name].loc[views["view_id"], "values"].to_numpy())

    colour = stacked(NAMES[2])[:, -COLOUR_BINS:]  # weight 1/2 of each row
    esf, hgd = stacked("esf"), stacked("hgd")
    return views, {
        "colour alone": 2 * colour,
        "ESF": esf,
        "HGD": hgd,
        "ESF + colour": np.hstack([0.5 * esf, colour]),
        "HGD + colour": np.hstack([0.5 * hgd, colour]),
    }


def precision(views: pd.DataFrame, values: np.ndarray, size: int) -> float:
    library, tests = library_subset(views, size), views[views["split"] == "test"]
    index = pd.Index(views["view_id"])
    lib, query = values[index.get_indexer(library["view_id"])], values[index.get_indexer(tests["view_id"])]
    usable = np.isfinite(lib).all(axis=1)  # a view the kind could not describe is never nearest
    nearest = np.concatenate(
        [
            np.flatnonzero(usable)[chi_square_matrix(query[k : k + CHUNK], lib[usable]).argmin(axis=1)]
            for k in range(0, len(query), CHUNK)
        ]
    )
    return float(np.mean(library["object"].to_numpy()[nearest] == tests["object"].to_numpy()))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("descriptors", help="descriptors.parquet of a workflow run")
    parser.add_argument("--sizes", type=int, nargs="+", default=[5, 8, 12, 40])
    parser.add_argument("--out", required=True, help="CSV to write")
    args = parser.parse_args()
    views, features = variants(args.descriptors)
    rows = [
        dict(variant=name, library_size=size, precision=round(100 * precision(views, values, size), 1))
        for name, values in features.items()
        for size in args.sizes
    ]
    frame = pd.DataFrame(rows).assign(test_views=int((views["split"] == "test").sum()))
    frame.to_csv(args.out, index=False)
    print(frame.pivot(index="variant", columns="library_size", values="precision").to_string())


if __name__ == "__main__":
    main()
