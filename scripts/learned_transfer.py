"""Objects of another class: a learned kind's network trained on one run's objects, describing another run's.

    .venv/bin/python scripts/learned_transfer.py results/household_learned --weights results/chairs_learned \\
        --out docs/results/household_learned_transfer.csv

A user with a network trained on chairs adds a mug. Here the pointnets that ``--weights`` (a run's results
folder) trained on its own library views (``fitted/pointnet*.npz``, 8 views per object) describe every view of
``run``'s objects, none of which they were trained on: the library of ``--size`` views per object and the test
views. Measured on the run's test views, for those networks, the run's own networks and its descriptor kinds:

- ``precision``: closed set, every object in the library;
- ``auroc``, ``known_kept_<side>``, ``unknown_rejected_<side>``: the open set, each object left out of the
  library in turn, its threshold set from the library's own unknown or known answers
  (:func:`heatdata.recognition.open_set.threshold_sides`). Only a network trained on none of the run's objects is
  measured here honestly; the run's own networks are left out of it (empty).

Rendered views, not real sensor data.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import pandas as pd

from heatdata.descriptors import DescriptorSpec, file_name, kind_of
from heatdata.experiments.describe import describe_library_and_tests, load_fitted
from heatdata.io.tables import read_table
from heatdata.log import setup_logging
from heatdata.recognition.evaluate import classify, library_subset, own_time_scale
from heatdata.recognition.open_set import threshold_sides


def measured(rows: pd.DataFrame, descriptor: str, size: int, open_set: bool) -> dict:
    """Closed-set precision and, with ``open_set``, the leave-one-object-out summary of one descriptor's rows."""
    rows = own_time_scale(rows[rows["descriptor"] == descriptor])
    library = library_subset(rows[rows["split"] == "train"], size)
    tests = rows[rows["split"] == "test"]
    answers = classify(pd.concat([library, tests], ignore_index=True), descriptor)
    out = {"precision": float(answers["correct"].mean())}
    return out | (threshold_sides(library, tests, rows["kind"].iloc[0]) if open_set else {})


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", type=Path, help="the results folder of the objects described (views/, descriptors)")
    parser.add_argument("--weights", type=Path, required=True, help="the results folder whose networks describe")
    parser.add_argument("--size", type=int, default=8, help="library views per object (8)")
    parser.add_argument("--color", nargs="+", default=["rgb", "none"], help="the pointnets' colour options")
    parser.add_argument("--out", type=Path, required=True, help="the table to write (.csv)")
    args = parser.parse_args()
    setup_logging()
    table, _ = read_table(args.run / "descriptors.parquet")
    out = []
    for descriptor, kind in table[["descriptor", "kind"]].drop_duplicates().itertuples(index=False):
        learned = kind_of(kind).learned
        trained_on = "the run's objects" if learned else ""
        out.append(
            {"descriptor": descriptor, "trained_on": trained_on, **measured(table, descriptor, args.size, not learned)}
        )
        print(out[-1])
    frames = [read_table(path)[0] for path in sorted((args.run / "views").glob("*.parquet"))]
    for color in args.color:
        spec = DescriptorSpec("pointnet", color=color, train_views=args.size)
        weights = args.weights / "fitted" / f"{file_name(spec.name)}.npz"
        (spec,) = load_fitted([spec], {spec.name: weights})
        start = time.perf_counter()
        described = describe_library_and_tests(frames, spec, args.size)
        seconds = time.perf_counter() - start
        out.append(
            {
                "descriptor": spec.name,
                "trained_on": str(args.weights),
                **measured(described, spec.name, args.size, True),
            }
        )
        print(out[-1], f"described in {seconds:.0f} s")
    frame = pd.DataFrame(out).assign(library_size=args.size)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    frame.round(4).to_csv(args.out, index=False)
    print(frame.to_string(index=False))


if __name__ == "__main__":
    main()
