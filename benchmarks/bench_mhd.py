"""Search speed of the modified Hausdorff distance (eq. 3.1) over a large library.

    .venv/bin/python benchmarks/bench_mhd.py [--library 100000]

Library descriptors are smooth random curves of 64 samples shaped like PVHKs
(values about 1 +- 0.3); one query is searched against all of them, then 100 queries
against 560 (the demo's library size) to give the cost per pair.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from threadpoolctl import threadpool_limits

import heatdata as hd


def curves(rng: np.random.Generator, n: int) -> np.ndarray:
    x = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    return 1 + 0.3 * rng.uniform(0.2, 1, (n, 1)) * np.sin(np.outer(rng.uniform(1, 4, n), x) + rng.uniform(0, 6, (n, 1)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--library", type=int, default=100_000)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    library = curves(rng, args.library)
    with threadpool_limits(1):
        start = time.perf_counter()
        nn = hd.nearest_neighbours(curves(rng, 1), library)
        search = time.perf_counter() - start
        queries, small = curves(rng, 100), library[:560]
        start = time.perf_counter()
        hd.mhd_matrix(queries, small)
        per_pair = (time.perf_counter() - start) / (100 * 560)
    print(f"one query against {args.library} descriptors: {search:.2f} s (nearest: {nn.index[0]})")
    print(f"cost per pair (100 x 560): {per_pair * 1e6:.1f} us")


if __name__ == "__main__":
    main()
