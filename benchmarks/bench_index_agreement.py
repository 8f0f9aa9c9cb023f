"""Answers through the search index against the exact search, on real runs' descriptors, for every kind with an index.

For each descriptor of a run (its table ``descriptors.parquet``) whose kind has an index space, the library is
every train view of every object (40 per object in the runs below) and the queries are every test view's
descriptor row. Each query is searched through the index (:mod:`heatdata.recognition.index`) and exhaustively, and
the answer counts as identical when its five nearest objects, their nearest library views and distances, and the
two distances the confidence reads (the nearest view's and the nearest other object's) are all equal. The figures
are the share of identical answers and the median search time each way.

    .venv/bin/snakemake --cores 2                       # the default run: results/
    .venv/bin/python benchmarks/bench_index_agreement.py results results/chairs_learned
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import pandas as pd
from record import write

MATCHES = 5


def library_of(rows: pd.DataFrame, spec):
    """A :class:`heatdata.Library` of ``rows`` (train views of one descriptor) with an index, without a file."""
    from heatdata.recognition.index import build_index
    from heatdata.recognition.library import Library

    metadata = {
        "spec": {"kind": spec.kind, "options": dict(spec.options), "fitted": None, "name": spec.name},  # not fitted:
        # the rows are described already
        "time_rule": "plausible",
        "library_size": int(rows.groupby("object").size().max()),
        "heatdata_version": "",
        "confidence": None,
    }
    library = Library(rows.assign(split="train").reset_index(drop=True), metadata, spec.name)
    library.use_index(build_index(library._values, spec.impl.index_space, what=spec.name))
    return library


def agreement(run: Path) -> list[tuple[str, float, str]]:
    from heatdata.descriptors import DescriptorSpec, kind_of
    from heatdata.io.tables import read_metadata, read_table
    from heatdata.recognition.confidence import nearest_two

    specs = {}
    for entry in read_metadata(run / "descriptors.parquet")["descriptors"]:
        spec = DescriptorSpec(**entry)
        specs[spec.name] = spec
    figures = []
    for name, spec in specs.items():
        if kind_of(spec.kind).index_space is None:
            continue
        rows, _ = read_table(run / "descriptors.parquet", filters=[("descriptor", "==", name)])
        rows = rows[[bool(np.isfinite(v).all()) for v in rows["values"]]]
        library = library_of(rows[rows["split"] == "train"], spec)
        tests = rows[rows["split"] == "test"]
        same, fast, slow = 0, [], []
        for k in range(len(tests)):
            query = tests.iloc[[k]]
            tic = time.perf_counter()
            near = library.distances(query)
            fast.append(time.perf_counter() - tic)
            tic = time.perf_counter()
            exact = library.distances(query, exact=True)
            slow.append(time.perf_counter() - tic)
            a, b = library._nearest_views(near)[:MATCHES], library._nearest_views(exact)[:MATCHES]
            two = nearest_two(near[None], library._codes)[1:], nearest_two(exact[None], library._codes)[1:]
            same += bool(np.array_equal(a, b) and np.array_equal(near[a], exact[b]) and two[0] == two[1])
        label = f"{run.name or run}: {name} ({len(library.objects)} objects, {len(library.views):,} views)"
        print(f"{label}: {same}/{len(tests)} identical", flush=True)
        figures += [
            (f"{label}: identical answers", same / len(tests), "share"),
            (f"{label}: test views", len(tests), "views"),
            (f"{label}: search through the index, median", 1e3 * float(np.median(fast)), "ms"),
            (f"{label}: exact search, median", 1e3 * float(np.median(slow)), "ms"),
        ]
    return figures


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", type=Path, nargs="+", help="runs' results folders (with descriptors.parquet)")
    args = parser.parse_args()
    write([figure for run in args.runs for figure in agreement(run)])


if __name__ == "__main__":
    main()
