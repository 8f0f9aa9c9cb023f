"""Answers through the search index against the exact search, on real runs' descriptors, for every kind with an index.

For each descriptor of a run (its table ``descriptors.parquet``) whose kind has an index space, the library is
every train view of every object (40 per object in the runs below) and the queries are every test view's
descriptor row. Each query is searched through the index (:mod:`heatdata.recognition.index`) and exhaustively, and
the answer counts as identical when its five nearest objects, their nearest library views and distances, and the
two distances the confidence reads (the nearest view's and the nearest other object's) are all equal. The figures
are the share of identical answers and the median search time each way.

The classify rule's predictions (:func:`heatdata.recognition.evaluate.evaluate_table`, libraries of 40 and 8 views per
object) are compared too, the index forced on (``exact=False``; the rule searches through one above 5,000 library
views): a prediction is identical when its nearest library view is, and its distance within a relative 1e-4 (the
exhaustive MHD search sums in float32). The figures are the share of identical predictions and the time each way.

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
CLASSIFY_SIZES = [40, 8]


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
        spec = DescriptorSpec.from_dict(entry)
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
            *classify_agreement(run, name, label),
            (f"{label}: identical answers", same / len(tests), "share"),
            (f"{label}: test views", len(tests), "views"),
            (f"{label}: search through the index, median", 1e3 * float(np.median(fast)), "ms"),
            (f"{label}: exact search, median", 1e3 * float(np.median(slow)), "ms"),
        ]
    return figures


def classify_agreement(run: Path, name: str, label: str) -> list[tuple[str, float, str]]:
    """The classify rule's predictions through the index against its exhaustive ones (module docstring)."""
    from heatdata.recognition.evaluate import evaluate_table

    answers, seconds = [], []
    for exact in (False, True):
        tic = time.perf_counter()
        answers.append(evaluate_table(run / "descriptors.parquet", name, CLASSIFY_SIZES, exact=exact))
        seconds.append(time.perf_counter() - tic)
    near, exact = answers
    same = (near["predicted_view_id"].to_numpy() == exact["predicted_view_id"].to_numpy()) & np.isclose(
        near["distance"].to_numpy(), exact["distance"].to_numpy(), rtol=1e-4, atol=0
    )  # the exhaustive MHD search sums in float32
    failed = near["predicted_view_id"].to_numpy() == ""  # no prediction either way (a test view with NaN values)
    share = float(np.mean(same | (failed & (exact["predicted_view_id"].to_numpy() == ""))))
    print(f"{label}: classify {share:.4f} identical ({len(near)} predictions)", flush=True)
    sizes = " and ".join(map(str, CLASSIFY_SIZES))
    return [
        (f"{label}: classify, libraries of {sizes} views: identical predictions", share, "share"),
        (f"{label}: classify through the index", seconds[0], "s"),
        (f"{label}: classify, exact", seconds[1], "s"),
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", type=Path, nargs="+", help="runs' results folders (with descriptors.parquet)")
    args = parser.parse_args()
    write([figure for run in args.runs for figure in agreement(run)])


if __name__ == "__main__":
    main()
