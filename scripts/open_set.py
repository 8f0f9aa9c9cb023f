"""Open-set evaluation of a run's libraries: each object left out in turn, the run's test views answered as known
or unknown by the library's calibrated confidence (:mod:`heatdata.recognition.open_set`).

    .venv/bin/python scripts/open_set.py results --size 40 8 --out docs/results/open_set_household.csv
    .venv/bin/python scripts/open_set.py results --size 40 8 --threshold 0.5 --out ...  # one threshold for all

Rendered views, not real sensor data. One row per library file: AUROC, the share of known test views kept and of
unknown ones rejected at the default threshold, and the closed-set precision beside what the threshold costs.
Time-scaled kinds (the FT-PVHK) are left out: their test views are compared per time scale. So is a learned kind,
whose network was trained on every object (scripts/learned_unseen.py measures it on objects it has not seen).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import pandas as pd

from heatdata.descriptors import kind_of
from heatdata.io.tables import read_table
from heatdata.recognition.evaluate import own_time_scale
from heatdata.recognition.library import load_library
from heatdata.recognition.open_set import open_set_scores, open_set_summary


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", type=Path, help="a run's results folder (descriptors.parquet, libraries/)")
    parser.add_argument("--size", type=int, nargs="+", default=[40], help="library sizes (default 40)")
    parser.add_argument("--threshold", type=float, help="one threshold for every library (default: each one's own)")
    parser.add_argument("--out", type=Path, required=True, help="the table to write (.csv)")
    args = parser.parse_args()
    descriptors, _ = read_table(args.run / "descriptors.parquet")
    tests = own_time_scale(descriptors[descriptors["split"] == "test"])
    rows = []
    for size in args.size:
        for path in sorted((args.run / "libraries").glob(f"*-{size}.parquet")):
            library = load_library(path)
            if kind_of(library.spec.kind).time_scaled:
                print(f"{path.name}: a time-scaled kind, left out")
                continue
            if kind_of(library.spec.kind).learned:  # its network has seen every object it would leave out
                print(f"{path.name}: a learned kind, trained on every object: see scripts/learned_unseen.py")
                continue
            start = time.perf_counter()
            own = tests[tests["descriptor"] == library.descriptor]
            scores = open_set_scores(library.views, own, library.spec.kind, args.threshold)
            summary = open_set_summary(scores)
            seconds = time.perf_counter() - start
            threshold = "own" if args.threshold is None else args.threshold
            rows.append(
                {
                    "descriptor": library.descriptor,
                    "size": size,
                    "threshold": threshold,
                    **summary,
                    "seconds": round(seconds, 1),
                }
            )
            print(", ".join(f"{k} {v:.3f}" if isinstance(v, float) else f"{k} {v}" for k, v in rows[-1].items()))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    pd.DataFrame(rows).to_csv(args.out, index=False)


if __name__ == "__main__":
    main()
