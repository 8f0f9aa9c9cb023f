"""Object precision when the descriptor values meet the MHD on another scale (issue 17; thesis eq. 3.1).

Eq. 3.1 compares the curves ``(i/M, z_i)``: a value difference and a shift along the boundary are traded in
the units of ``z`` (temperatures with equilibrium = 1 for the PVHK, times in m^2 for the PVST; the thesis's
Fig. 5.11 plots both on the same scales). Multiplying the values by ``k < 1`` makes shifts dearer, so the
nearest point of the other curve is at the same index more often (``k -> 0`` is the pointwise L1 distance);
``k > 1`` makes the comparison more tolerant of shifts. The PVST's times span three orders of magnitude on a
chair view, so ``log10`` compares them on a log scale (the thesis searches its times on one, Alg. 5.3, but
compares the times themselves). It reads a run's descriptor table (nothing is described again) and writes
one row per descriptor, transform and library size:

    .venv/bin/python scripts/value_scales.py results/chairs/descriptors.parquet \\
        --descriptor pvhk/polar/center/64 pvst/polar/interior/64/T0.75 \\
        --transform x1 x0.3 x0.1 x0.01 log10 log10x0.3 --out docs/results/chairs_value_scales.csv

Transforms: ``x<k>`` multiplies the values by k (``x1``: the workflow's MHD); ``log10x<k>`` takes k
log10(values), for kinds whose values are positive. ``--leave-one-out`` adds, for kinds that are not
time-scaled, the precision of each library view against all the other library views (``library_size`` 0):
a way to choose a transform without looking at the test views.
"""

import argparse
import re
import time

import numpy as np
import pandas as pd

from heatdata.core.distances import mhd_matrix
from heatdata.descriptors import kind_of
from heatdata.errors import HeatdataError
from heatdata.experiments.publish import print_precision
from heatdata.io.tables import read_table
from heatdata.log import setup_logging
from heatdata.recognition.evaluate import CLASSIFY_COLUMNS, TIME_SCALED_COLUMNS, evaluate_library_sizes


def transformed(values: pd.Series, transform: str, name: str) -> pd.Series:
    """The ``values`` column of descriptor ``name`` under ``transform`` (``x<k>``, ``log10`` or ``log10x<k>``)."""
    match = re.fullmatch(r"(log10)?(?:x([0-9.eE+-]+))?", transform)
    if not transform or not match:
        raise HeatdataError(f"unknown transform {transform!r} (use x<k>, log10 or log10x<k>)")
    log, k = match.group(1), float(match.group(2) or 1.0)
    if log:
        if any(np.nanmin(v) <= 0 for v in values):
            raise HeatdataError(f"{name}: {transform} needs positive values")
        return values.map(lambda v: k * np.log10(np.asarray(v)))
    return values.map(lambda v: k * np.asarray(v))


def leave_one_out(table: pd.DataFrame) -> float:
    """Object precision of each described library view against all the other library views (eq. 3.1)."""
    library = table[(table["split"] == "train") & table["values"].map(lambda v: bool(np.all(np.isfinite(v))))]
    distances = mhd_matrix(np.stack(library["values"].to_numpy()), np.stack(library["values"].to_numpy()))
    np.fill_diagonal(distances, np.inf)
    objects = library["object"].to_numpy()
    return float(np.mean(objects[distances.argmin(axis=1)] == objects))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("descriptors", help="descriptors.parquet of a workflow run")
    parser.add_argument("--descriptor", nargs="+", required=True, help="descriptor names")
    parser.add_argument("--transform", nargs="+", default=["x1", "x0.1", "log10"])
    parser.add_argument("--sizes", type=int, nargs="+", default=[40, 12, 8, 5])
    parser.add_argument(
        "--leave-one-out",
        action="store_true",
        help="add each transform's leave-one-out precision among the library views (library_size 0)",
    )
    parser.add_argument("--out", help="CSV to write")
    args = parser.parse_args()
    setup_logging()
    rows = []
    for name in args.descriptor:
        table, _ = read_table(
            args.descriptors, columns=[*CLASSIFY_COLUMNS, *TIME_SCALED_COLUMNS], filters=[("descriptor", "==", name)]
        )
        for transform in args.transform:
            start = time.perf_counter()
            try:
                values = transformed(table["values"], transform, name)
            except HeatdataError as exc:
                if "positive" not in str(exc):
                    raise
                print(f"skipped: {exc}", flush=True)  # e.g. log10 of FT-PVHK temperatures, which reach 0
                continue
            predictions = evaluate_library_sizes(table.assign(values=values), name, args.sizes)
            for size, group in predictions.groupby("library_size"):
                rows.append(
                    {
                        "descriptor": name,
                        "transform": transform,
                        "library_size": size,
                        "precision": round(float(group["correct"].mean()), 4),
                    }
                )
            if args.leave_one_out and not kind_of(table["kind"].iloc[0]).time_scaled:
                rows.append(
                    {
                        "descriptor": name,
                        "transform": transform,
                        "library_size": 0,
                        "precision": round(leave_one_out(table.assign(values=values)), 4),
                    }
                )
            print(f"{name} {transform}: {time.perf_counter() - start:.0f} s", flush=True)
    table = pd.DataFrame(rows)
    print_precision(table, ["descriptor", "transform"], args.out, sort=False)


if __name__ == "__main__":
    main()
