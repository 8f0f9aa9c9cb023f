"""Kinds combined: several descriptors of one view, each distance on its own scale (issue 28, a measurement).

Reads a run's descriptor table and, for each library size, scores each descriptor alone and three ways of
adding their distances, everything learned from the library views only (no test view):

- ``sum``: each kind's distance divided by its scale, the median distance from a library view to its
  nearest other library view, then added;
- ``learned``: the same with weights on a grid of the simplex (steps of 0.1), chosen by leave-one-out
  precision among the library views (each library view against all the others);
- ``rank``: the ranks of the library views under each kind, added (rank fusion).

    .venv/bin/python scripts/combine_kinds.py results/chairs_12/descriptors.parquet \\
        --descriptor esf pvst/polar/interior/64/T0.75/log-time --out docs/results/chairs_12_combined.csv

Only views that every named descriptor describes are used (a NaN row of one kind drops the view), so a kind
alone may score a little differently from the workflow's table. Time-scaled kinds (FT-PVHK) are refused:
their test views have one row per object. One row per library size and method.
"""

from __future__ import annotations

import argparse
import itertools
import time

import numpy as np
import pandas as pd

from heatdata.descriptors import kind_of
from heatdata.io.tables import read_table
from heatdata.log import setup_logging
from heatdata.recognition.evaluate import CLASSIFY_COLUMNS, library_subset

STEP = 0.1  # of the weight grid


def described_views(path: str, names: list[str]) -> pd.DataFrame:
    """The rows of ``names``, for the views that every one of them describes with finite values."""
    table, _ = read_table(path, columns=list(CLASSIFY_COLUMNS), filters=[("descriptor", "in", names)])
    missing = sorted(set(names) - set(table["descriptor"]))
    if missing:
        raise SystemExit(f"combine_kinds: {path} has no descriptor {', '.join(missing)}")
    for name, rows in table.groupby("descriptor"):
        if kind_of(rows["kind"].iloc[0]).time_scaled:
            raise SystemExit(
                f"combine_kinds: {name} is time-scaled (a test view has a row per object); "
                "combine kinds with one row per view"
            )
    finite = table["values"].map(lambda v: bool(np.all(np.isfinite(v))))
    counts = table[finite].groupby("view_id")["descriptor"].nunique()
    return table[table["view_id"].isin(counts[counts == len(names)].index)]


def distance_matrices(table: pd.DataFrame, names: list[str], rows: np.ndarray, columns: np.ndarray) -> dict:
    """Each descriptor's own distance between the views ``rows`` and ``columns`` (view ids)."""
    out = {}
    for name in names:
        values = table[table["descriptor"] == name].set_index("view_id")
        impl = kind_of(values["kind"].iloc[0])
        out[name] = impl.distance_matrix(
            np.stack(values.loc[rows, "values"].to_numpy()), np.stack(values.loc[columns, "values"].to_numpy())
        )
    return out


def precision(distances: np.ndarray, library_objects: np.ndarray, query_objects: np.ndarray) -> float:
    """Share of queries whose nearest library view (NaN distances never nearest) is of their object."""
    return float(np.mean(library_objects[np.nan_to_num(distances, nan=np.inf).argmin(axis=1)] == query_objects))


def combine(table: pd.DataFrame, names: list[str], size: int) -> list[dict]:
    """Each kind alone and the three combinations at one library size."""
    first = table[table["descriptor"] == names[0]]
    tests, library = first[first["split"] == "test"], library_subset(first, size)
    query_objects, library_objects = tests["object"].to_numpy(), library["object"].to_numpy()
    queries = distance_matrices(table, names, tests["view_id"].to_numpy(), library["view_id"].to_numpy())
    among = distance_matrices(table, names, library["view_id"].to_numpy(), library["view_id"].to_numpy())
    for d in among.values():
        np.fill_diagonal(d, np.nan)  # a library view is not its own neighbour
    scale = {n: float(np.median(np.nanmin(among[n], axis=1))) for n in names}
    rows = [dict(method=n, precision=precision(queries[n], library_objects, query_objects), weights="") for n in names]
    grid = [
        w
        for w in itertools.product(np.arange(0.0, 1.0 + STEP / 2, STEP), repeat=len(names))
        if abs(sum(w) - 1.0) < 1e-9
    ]
    loo = [
        precision(
            sum(wk * among[n] / scale[n] for wk, n in zip(w, names, strict=True)), library_objects, library_objects
        )
        for w in grid
    ]
    best = grid[int(np.argmax(loo))]
    for method, weights in (("sum", [1.0] * len(names)), ("learned", best)):
        d = sum(wk * queries[n] / scale[n] for wk, n in zip(weights, names, strict=True))
        rows.append(
            dict(
                method=method,
                precision=precision(d, library_objects, query_objects),
                weights=" ".join(f"{w:.1f}" for w in weights),
            )
        )
    ranks = sum(np.argsort(np.argsort(queries[n], axis=1), axis=1) for n in names)
    rows.append(dict(method="rank", precision=precision(ranks, library_objects, query_objects), weights=""))
    return [
        dict(
            r, library_size=size, test_views=len(tests), leave_one_out=max(loo) if r["method"] == "learned" else np.nan
        )
        for r in rows
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("descriptors", help="descriptors.parquet of a workflow run")
    parser.add_argument("--descriptor", nargs="+", required=True, help="two or more descriptor names")
    parser.add_argument("--sizes", type=int, nargs="+", default=[5, 8, 12, 40])
    parser.add_argument("--out", required=True, help="CSV to write")
    args = parser.parse_args()
    if len(args.descriptor) < 2:
        raise SystemExit("combine_kinds: name two or more descriptors")
    setup_logging()
    start = time.perf_counter()
    table = described_views(args.descriptors, args.descriptor)
    rows = [row for size in args.sizes for row in combine(table, args.descriptor, size)]
    frame = pd.DataFrame(rows).assign(seconds=round(time.perf_counter() - start))
    frame.to_csv(args.out, index=False)
    print(frame.pivot(index="method", columns="library_size", values="precision").mul(100).round(1).to_string())


if __name__ == "__main__":
    main()
