"""Check that two workflow runs wrote the same descriptor and prediction tables (all columns but timings).

Used to show that a refactor changes no number: run the default workflow before and after
(into two results folders) and compare.

    .venv/bin/python scripts/compare_runs.py results_before results_after
"""

from __future__ import annotations

import argparse
import filecmp
import sys
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq

TABLES = {
    "descriptors.parquet": ["view_id", "descriptor", "time_object"],
    "evaluation/predictions.parquet": ["descriptor", "library_size", "view_id"],
}


def same_column(a, b) -> bool:
    if len(a) and isinstance(a.iloc[0], (np.ndarray, list, type(None))):
        return all(
            (u is None) == (v is None)
            and (u is None or np.array_equal(np.asarray(u), np.asarray(v), equal_nan=np.asarray(u).dtype.kind == "f"))
            for u, v in zip(a, b, strict=True)
        )
    return a.reset_index(drop=True).equals(b.reset_index(drop=True))  # NaN where the other has NaN is equal


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("first", type=Path)
    parser.add_argument("second", type=Path)
    args = parser.parse_args()
    identical = True
    for name, key in TABLES.items():
        x, y = (
            pq.read_table(folder / name)
            .to_pandas()
            .drop(columns=["seconds"], errors="ignore")
            .sort_values(key)
            .reset_index(drop=True)
            for folder in (args.first, args.second)
        )
        differ = [c for c in x.columns if c not in y.columns or len(x) != len(y) or not same_column(x[c], y[c])]
        print(
            f"{name}: {len(x)} and {len(y)} rows; "
            + (f"columns differ: {differ}" if differ else "identical in every column but seconds")
        )
        identical &= not differ
    same = filecmp.cmp(args.first / "evaluation/precision.csv", args.second / "evaluation/precision.csv", shallow=False)
    print(f"evaluation/precision.csv: {'byte-identical' if same else 'differs'}")
    return 0 if identical and same else 1


if __name__ == "__main__":
    sys.exit(main())
