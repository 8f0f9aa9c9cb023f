"""FT-PVHK time-scale choices on a run's descriptor table (issue 17; thesis Alg. 5.2).

Alg. 5.2 computes each view's FT-PVHK at its own object's time scale; for a test view that is its label. The
workflow instead describes every test view at every object's time scale and compares it with each object's
library at that object's scale, the nearest over the objects its ``time_scale_rule`` allows winning.
Distances at different time scales are not on one scale, though: a small time scale leaves a peaked
temperature profile, whose distances are larger. This script measures, for each library size, with and
without the part weights of eq. 5.14:

* ``nearest``: over every object (the workflow's ``time_scale_rule: every``, its default before issue 17);
* ``normalized``: the same distances, each divided by its object's spread at its own time scale (the median,
  over the object's library views, of the distance to the nearest other library view of the object), also
  label-free;
* ``plausible``: ``nearest`` among the objects whose time scale (Alg. 5.1: the smallest 1/lambda_2 of their
  library views) is at most the test view's own 1/lambda_2, which its own object's nearly always is (all
  objects when none is); label-free, and the workflow's default (``time_scale_rule: plausible``, computed there by
  :func:`heatdata.recognition.evaluate.classify`: the same predictions);
* ``known``: the test view at its true object's time scale against every library view (each at its own
  object's): the thesis's Alg. 5.2 read literally, which uses the test view's label.

    .venv/bin/python scripts/ft_time_scales.py results/chairs/descriptors.parquet ft-pvhk/polar/center/64 \\
        --out docs/results/chairs_ft_time_scales.csv
"""

import argparse
import time

import numpy as np
import pandas as pd

from heatdata.descriptors import kind_of
from heatdata.experiments.publish import print_precision
from heatdata.io.tables import iter_table, read_table
from heatdata.log import setup_logging
from heatdata.recognition.evaluate import library_subset

COLUMNS = ["object", "view_id", "split", "azimuth", "kind", "time_object", "time", "t_global", "values", "weights"]


def stack(frame: pd.DataFrame, column: str) -> np.ndarray:
    """(rows, M) array of a list column."""
    return np.stack(frame[column].to_numpy())


def spread(kind, values: np.ndarray, weights: np.ndarray | None) -> float:
    """Median distance from each library view of one object to its nearest other one (0 with one view)."""
    if len(values) < 2:
        return 0.0
    d = kind.distance_matrix(values, values, query_weights=weights, library_weights=weights)
    np.fill_diagonal(d, np.inf)
    return float(np.median(d.min(axis=1)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("descriptors", help="descriptors.parquet of a workflow run")
    parser.add_argument("descriptor", help="an ft-pvhk descriptor name")
    parser.add_argument("--sizes", type=int, nargs="+", default=[40, 12, 8, 5])
    parser.add_argument("--out", help="CSV to write")
    args = parser.parse_args()
    setup_logging()
    start = time.perf_counter()
    rows = [("descriptor", "==", args.descriptor)]
    train, _ = read_table(args.descriptors, columns=COLUMNS, filters=[*rows, ("split", "==", "train")])
    kind = kind_of(train["kind"].iloc[0])
    objects = sorted(train["object"].unique())
    time_scale = train.groupby("object")["time"].first().loc[objects].to_numpy()
    libraries = {size: library_subset(train, size) for size in args.sizes}
    results = []
    for size, library in libraries.items():
        for weighted in (True, False):
            lib = {
                o: (stack(g, "values"), stack(g, "weights") if weighted else None) for o, g in library.groupby("object")
            }
            every = np.concatenate([lib[o][0] for o in objects])
            every_weights = np.concatenate([lib[o][1] for o in objects]) if weighted else None
            owner = np.repeat(objects, [len(lib[o][0]) for o in objects])
            scale = np.array([spread(kind, *lib[o]) for o in objects])
            truth, distances, known, own_scale = [], [], [], []
            for group in iter_table(args.descriptors, columns=COLUMNS, filters=[*rows, ("split", "==", "test")]):
                views = sorted(group["view_id"].unique())
                d = np.empty((len(views), len(objects)))
                for k, o in enumerate(objects):
                    at = group[group["time_object"] == o].set_index("view_id").loc[views]
                    d[:, k] = kind.nearest(
                        stack(at, "values"),
                        lib[o][0],
                        query_weights=stack(at, "weights") if weighted else None,
                        library_weights=lib[o][1],
                    ).distance
                own = group[group["time_object"] == group["object"]].set_index("view_id").loc[views]
                nearest = kind.nearest(
                    stack(own, "values"),
                    every,
                    query_weights=stack(own, "weights") if weighted else None,
                    library_weights=every_weights,
                ).index
                truth.extend(own["object"])
                distances.append(d)
                known.extend(owner[nearest])
                own_scale.extend(own["t_global"])
            truth, d = np.array(truth), np.concatenate(distances)
            mask = time_scale[None, :] <= np.array(own_scale)[:, None]
            plausible = np.where(mask | ~mask.any(axis=1, keepdims=True), d, np.inf)  # none plausible: all
            for rule, predicted in (
                ("nearest", np.array(objects)[d.argmin(axis=1)]),
                ("normalized", np.array(objects)[(d / scale).argmin(axis=1)]),
                ("plausible", np.array(objects)[plausible.argmin(axis=1)]),
                ("known", np.array(known)),
            ):
                results.append(
                    {
                        "library_size": size,
                        "weights": "weighted" if weighted else "unweighted",
                        "rule": rule,
                        "test_views": len(truth),
                        "precision": round(float(np.mean(predicted == truth)), 4),
                    }
                )
            inside = np.mean(time_scale[np.searchsorted(objects, truth)] <= np.array(own_scale))
            print(
                f"{size} views, {'weighted' if weighted else 'unweighted'}: {time.perf_counter() - start:.0f} s; "
                f"own object plausible for {inside:.1%} of the test views",
                flush=True,
            )
    table = pd.DataFrame(results)
    print_precision(table, ["weights", "rule"], args.out)


if __name__ == "__main__":
    main()
