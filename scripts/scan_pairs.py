"""Pairs of real range scans joined by ``heatdata stitch``'s rule from random starting motions, scored against the
scanner's true poses (:mod:`heatdata.experiments.scan_pairs`).

    .venv/bin/python scripts/scan_pairs.py ../shared/realdata/bunny --conf ../shared/realdata/bunny/bun.conf \\
        --pair bun000.ply bun180.ply --pair bun045.ply bun315.ply --starts 5 --free-space 0 30 100 \\
        --out docs/results/scan_pairs.csv
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import pandas as pd

from heatdata.experiments.scan_pairs import pair_trials, read_conf, read_pair
from heatdata.log import setup_logging


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", type=Path, help="the scans (NAME.ply or NAME.ply.xz)")
    parser.add_argument("--conf", type=Path, required=True, help="the scanner's poses (a Stanford .conf file)")
    parser.add_argument("--pair", nargs=2, action="append", required=True, metavar=("FIRST", "SECOND"))
    parser.add_argument("--starts", type=int, default=5, help="random starting motions a pair (default 5)")
    parser.add_argument(
        "--free-space",
        type=float,
        nargs="+",
        default=[None],
        metavar="WEIGHT",
        help="JASNOM's free-space weights, each tried on every pair (default: the stitch's)",
    )
    parser.add_argument("--out", type=Path, required=True, help="one row a trial (CSV)")
    args = parser.parse_args()
    setup_logging()
    begin = time.perf_counter()
    conf = read_conf(args.conf)
    rows = []
    for names in args.pair:
        (first, second), truth = read_pair(args.folder, tuple(names), conf)
        pair = f"{Path(names[0]).stem}+{Path(names[1]).stem}"
        for weight in args.free_space:
            trials = pair_trials(first, second, truth, pair, args.starts, free_space=weight)
            rows += [dataclasses.asdict(t) for t in trials]
    trials = pd.DataFrame(rows)
    trials.round(6).to_csv(args.out, index=False)
    trials["within 5 deg and 2%"] = (trials["rotation_error"] <= 5) & (trials["translation_error"] <= 0.02)
    trials["within 2 deg and 1%"] = (trials["rotation_error"] <= 2) & (trials["translation_error"] <= 0.01)
    trials["weight"] = trials["free_space"].fillna(-1)  # registered pairs have none
    summary = trials.groupby(["pair", "method", "weight"]).agg(
        trials=("start", "size"),
        within_5deg_2pct=("within 5 deg and 2%", "sum"),
        within_2deg_1pct=("within 2 deg and 1%", "sum"),
        median_degrees=("rotation_error", "median"),
        median_translation=("translation_error", "median"),
        median_seconds=("seconds", "median"),
    )
    print(summary.round(4).to_string())
    print(f"{len(trials)} trials in {time.perf_counter() - begin:.0f} s; {args.out}")


if __name__ == "__main__":
    main()
