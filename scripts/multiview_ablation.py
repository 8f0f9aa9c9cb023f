"""Ablation of the similarity bootstrap (thresholds, newcomers) and the appearance model's alpha (thesis 4.3, 4.4.6).

Reads a multi-view run's descriptor table (``snakemake --configfile config/experiments/multiview.yaml``),
rebuilds its library, similarity and ambiguous starts as the rule does, and runs the
trials for each alpha, (sigma_min, tau_boot) pair and newcomer rule (their starting
weight and place, :class:`heatdata.recognition.multiview.filters.ParticleFilter`) with fewer repetitions (Fig. 4.8b).
Prints and writes a CSV of accuracy, identification and degrees travelled per policy and
particle count.

    .venv/bin/python scripts/multiview_ablation.py [--results results/multiview] [--repetitions 3] \\
        [--out docs/results/multiview_ablation.csv]
"""

from __future__ import annotations

import argparse
import itertools
import time

import pandas as pd

from heatdata.experiments.multiview import ambiguous_starts, multiview_trials, split_tests, trial_summary
from heatdata.io.tables import read_table
from heatdata.recognition.evaluate import library_subset
from heatdata.recognition.multiview.appearance import learn_similarity


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--results", default="results/multiview")
    parser.add_argument("--descriptor", default="pvhk/polar/center/64")
    parser.add_argument("--library-views", type=int, nargs="+", default=[24])
    parser.add_argument("--repetitions", type=int, default=3)
    parser.add_argument("--particles", type=int, nargs="+", default=[10, 100])
    parser.add_argument("--sigma", type=float, nargs="+", default=[0.05, 0.2, 0.5], help="sigma_min values")
    parser.add_argument("--tau", type=float, nargs="+", default=[0.1, 0.5, 0.9], help="tau_boot values")
    parser.add_argument(
        "--alpha",
        nargs="+",
        default=["learned"],
        help="alpha values; learned: per view, from the similarity views (the default)",
    )
    parser.add_argument(
        "--newcomer",
        nargs="+",
        default=["mean"],
        choices=["mean", "least"],
        help="the weight re-populated particles start at",
    )
    parser.add_argument(
        "--repopulate",
        nargs="+",
        default=["cell"],
        choices=["cell", "view"],
        help="where in its label a re-populated particle starts",
    )
    parser.add_argument("--policies", nargs="+", default=["fixed", "active"], choices=["fixed", "active"])
    parser.add_argument("--starts", type=int, default=3)
    parser.add_argument("--max-degrees", type=float, default=720.0)
    parser.add_argument("--out")
    args = parser.parse_args()
    rows, _ = read_table(f"{args.results}/descriptors.parquet", filters=[("descriptor", "==", args.descriptor)])
    similar, tests = split_tests(rows[rows["split"] == "test"])
    alphas = [None if a == "learned" else float(a) for a in args.alpha]
    tables = []
    for size, alpha in itertools.product(args.library_views, alphas):
        library = library_subset(rows, size)
        similarity = learn_similarity(library, similar, alpha=alpha)
        starts = ambiguous_starts(library, tests, args.starts)
        for sigma, tau, newcomer, place in itertools.product(args.sigma, args.tau, args.newcomer, args.repopulate):
            start = time.perf_counter()
            trials = multiview_trials(
                library,
                similarity,
                tests,
                starts,
                particles=args.particles,
                bootstraps=("similarity",),
                policies=tuple(args.policies),
                exhaustive=False,
                repetitions=args.repetitions,
                max_degrees=args.max_degrees,
                filter_options={
                    "sigma_min": sigma,
                    "tau_boot": tau,
                    "alpha": alpha,
                    "newcomer": newcomer,
                    "repopulate": place,
                },
            )
            summary = trial_summary(trials.assign(library_views=size))
            tables.append(
                summary.assign(
                    alpha="learned" if alpha is None else alpha,
                    sigma_min=sigma,
                    tau_boot=tau,
                    newcomer=newcomer,
                    repopulate=place,
                )
            )
            print(
                f"{size} views, alpha {alpha}, sigma_min {sigma}, tau_boot {tau}, newcomer {newcomer} at the "
                f"{place}: {len(trials)} runs in {time.perf_counter() - start:.0f} s"
            )
    table = pd.concat(tables, ignore_index=True)
    shown = table[
        [
            "library_views",
            "alpha",
            "sigma_min",
            "tau_boot",
            "newcomer",
            "repopulate",
            "policy",
            "particles",
            "accuracy",
            "identified",
            "degrees",
            "stops",
        ]
    ].round(3)
    print(shown.to_string(index=False))
    if args.out:
        shown.to_csv(args.out, index=False)


if __name__ == "__main__":
    main()
