"""A classify job on a run's descriptor table (rule classify): the nearest library view of every test view by
the distance matrix over the whole table in memory (each kind's ``distance_matrix`` and argmin, as before
``nearest_mhd`` and ``evaluate_table``) and as the rule runs now (the kind's exact search, ``Kind.nearest``, on
test rows read one row group at a time, ``evaluate_table``), each in its own process for its peak memory,
answers compared.

    .venv/bin/python benchmarks/bench_classify.py results/chairs/descriptors.parquet \\
        [--descriptor ft-pvhk/polar/center/64] [--size 40]
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time

import numpy as np
from record import write


def run(table: str, descriptor: str, size: int, method: str) -> dict:
    """One classify in this process; ``method`` "matrix" puts the base class's argmin back in place of the
    kind's search (memory: the whole (Q, N) matrix at once, as the old code held it)."""
    from heatdata.descriptors.base import KINDS, Kind
    from heatdata.io.tables import read_table
    from heatdata.recognition.evaluate import evaluate_library_sizes, evaluate_table

    if method == "matrix":

        def by_matrix(self, queries, library, *, query_weights=None, library_weights=None, within=None, chunk=None):
            return Kind.nearest(
                self,
                queries,
                library,
                query_weights=query_weights,
                library_weights=library_weights,
                within=within,
                chunk=len(queries),
            )

        for kind in {type(k) for k in KINDS.values()}:
            kind.nearest = by_matrix
    start = time.perf_counter()
    if method == "matrix":
        rows, _ = read_table(
            table,
            filters=[("descriptor", "==", descriptor)],
            columns=[
                "object",
                "label",
                "view_id",
                "split",
                "azimuth",
                "descriptor",
                "kind",
                "time_object",
                "values",
                "weights",
            ],
        )
        predictions = evaluate_library_sizes(rows, descriptor, [size])
    else:
        predictions = evaluate_table(table, descriptor, [size])
    seconds = time.perf_counter() - start
    return {
        "seconds": seconds,
        "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        "views": len(predictions),
        "precision": float(predictions["correct"].mean()),
        "view_ids": predictions["view_id"].tolist(),
        "predicted": predictions["predicted_view_id"].tolist(),
        "distance": predictions["distance"].tolist(),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("table")
    parser.add_argument("--descriptor", default="ft-pvhk/polar/center/64")
    parser.add_argument("--size", type=int, default=40)
    parser.add_argument("--method", choices=["matrix", "search"], help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.method:
        print(json.dumps(run(args.table, args.descriptor, args.size, args.method)))
        return
    results = {}
    for method in ("matrix", "search"):
        out = subprocess.run(
            [
                sys.executable,
                __file__,
                args.table,
                "--descriptor",
                args.descriptor,
                "--size",
                str(args.size),
                "--method",
                method,
            ],
            capture_output=True,
            text=True,
            check=True,
        )
        results[method] = json.loads(out.stdout.splitlines()[-1])
    old, new = results["matrix"], results["search"]
    by_view = [
        {
            view: (predicted, distance)
            for view, predicted, distance in zip(r["view_ids"], r["predicted"], r["distance"], strict=True)
        }
        for r in (old, new)
    ]
    same = by_view[0].keys() == by_view[1].keys() and all(by_view[0][v][0] == by_view[1][v][0] for v in by_view[0])
    a, b = (np.array([answers[v][1] for v in sorted(by_view[0])]) for answers in by_view)
    gap = float(np.nanmax(np.abs(a - b) / np.maximum(np.abs(a), 1e-12)))
    print(f"{args.descriptor}, {args.size} library views per object, {new['views']} test views")
    for name, r in (("distance matrix + argmin", old), ("exact search, streamed", new)):
        print(f"  {name:28s} {r['seconds']:7.1f} s   peak {r['peak_mb']:6.0f} MB   precision {r['precision']:.1%}")
    print(
        f"  speed-up {old['seconds'] / new['seconds']:.1f}x; same predictions: {same}; "
        f"largest relative distance difference {gap:.1e} (the matrix is float32)"
    )
    write(
        [
            (f"{args.table}, {args.descriptor}, {args.size} views: distance matrix", old["seconds"], "s"),
            ("the same: exact search, streamed", new["seconds"], "s"),
            ("peak of the distance matrix job", old["peak_mb"], "MB"),
            ("peak of the streamed search job", new["peak_mb"], "MB"),
            ("same predictions", float(same), "bool"),
        ]
    )


if __name__ == "__main__":
    main()
