"""Time and memory of select_sources (the LP of thesis 6.3 by column generation) against the DP.

One object with 40 views x 250 candidate sources (2.5M edges), edge costs the mean
absolute difference between random smooth 16-sample curves of consecutive views.

    .venv/bin/python benchmarks/bench_select_sources.py [--views 40] [--candidates 250]
"""

import argparse
import logging
import resource
import time

import numpy as np
from record import write

from heatdata.recognition.compact import cyclic_dp, select_sources


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--views", type=int, default=40)
    parser.add_argument("--candidates", type=int, default=250)
    args = parser.parse_args()
    logging.basicConfig(level=logging.DEBUG, format="%(message)s")
    for noisy in ("cvxpy", "__cvxpy__", "matplotlib", "trimesh"):
        logging.getLogger(noisy).setLevel(logging.WARNING)
    rng = np.random.default_rng(0)
    curves = [np.cumsum(rng.normal(size=(args.candidates, 16)), axis=1) for _ in range(args.views)]
    costs = [
        np.abs(curves[i][:, None, :] - curves[(i + 1) % args.views][None, :, :]).mean(axis=2) for i in range(args.views)
    ]
    tic = time.perf_counter()
    _, lp = select_sources(costs)
    lp_seconds = time.perf_counter() - tic
    lp_peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # before the DP's (n0, n, n) tensors
    tic = time.perf_counter()
    _, dp = cyclic_dp(costs)
    dp_seconds = time.perf_counter() - tic
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(
        f"{args.views} views x {args.candidates} candidates: LP {lp_seconds:.1f} s, DP {dp_seconds:.2f} s, "
        f"relative difference {abs(lp - dp) / dp:.1e}, peak RSS {lp_peak:.0f} MB after the LP, {peak:.0f} MB "
        "after the DP"
    )
    write(
        [
            (f"{args.views} views x {args.candidates} candidates: LP", lp_seconds, "s"),
            ("the same: dynamic program", dp_seconds, "s"),
            ("relative difference LP - DP", abs(lp - dp) / dp, "relative"),
            ("peak RSS after the LP", lp_peak, "MB"),
        ]
    )


if __name__ == "__main__":
    main()
