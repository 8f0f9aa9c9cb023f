"""Ablation of the similarity bootstrap's thresholds (sigma_min, tau_boot; thesis 4.4.6, Fig. 4.8b).

Reads a multi-view run's descriptor table (``snakemake --configfile config/multiview.yaml``),
rebuilds its library, similarity and ambiguous starts as the rule does, and runs the
trials for each (sigma_min, tau_boot) pair with fewer repetitions. Prints and writes a
CSV of accuracy and degrees travelled per policy and particle count.

    .venv/bin/python scripts/multiview_ablation.py [--results results/multiview] [--repetitions 3] \\
        [--out docs/results/multiview_ablation.csv]
"""

from __future__ import annotations

import argparse
import time

import pandas as pd

from heatdata.library import library_subset
from heatdata.multiview import ambiguous_starts, learn_similarity, multiview_trials, split_tests, trial_summary
from heatdata.tables import read_table


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--results", default="results/multiview")
    parser.add_argument("--descriptor", default="pvhk/polar/center/64")
    parser.add_argument("--library-views", type=int, default=24)
    parser.add_argument("--repetitions", type=int, default=3)
    parser.add_argument("--particles", type=int, nargs="+", default=[10, 100])
    parser.add_argument("--out")
    args = parser.parse_args()
    rows, _ = read_table(f"{args.results}/descriptors.parquet", filters=[("descriptor", "==", args.descriptor)])
    similar, tests = split_tests(rows[rows["split"] == "test"])
    library = library_subset(rows, args.library_views)
    similarity = learn_similarity(library, similar)
    starts = ambiguous_starts(library, tests, 3)
    tables = []
    for sigma in (0.05, 0.2, 0.5):
        for tau in (0.1, 0.5, 0.9):
            start = time.perf_counter()
            trials = multiview_trials(library, similarity, tests, starts, particles=args.particles,
                                      bootstraps=("similarity",), policies=("fixed", "active"),
                                      repetitions=args.repetitions, sigma_min=sigma, tau_boot=tau)
            summary = trial_summary(trials).assign(sigma_min=sigma, tau_boot=tau)
            tables.append(summary)
            print(f"sigma_min {sigma}, tau_boot {tau}: {len(trials)} runs in {time.perf_counter() - start:.0f} s")
    table = pd.concat(tables, ignore_index=True)
    shown = table[["sigma_min", "tau_boot", "policy", "particles", "accuracy", "degrees", "stops"]].round(3)
    print(shown.to_string(index=False))
    if args.out:
        shown.to_csv(args.out, index=False)


if __name__ == "__main__":
    main()
