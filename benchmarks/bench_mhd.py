"""Search speed of the modified Hausdorff distance (eq. 3.1) over a large library: the exact search
(``heatdata.core.distances.nearest_mhd``) beside the distance matrix it replaces (``mhd_matrix`` + argmin).

    .venv/bin/python benchmarks/bench_mhd.py [--library 100000] [--queries 20]

Library descriptors are smooth random curves of 64 samples shaped like PVHKs
(values about 1 +- 0.3). ``--queries`` queries are searched against all of them, then 100
queries against 560 (the demo's library size), each way in one run, one thread; the answers
are checked to be the same items.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from record import write
from threadpoolctl import threadpool_limits

from heatdata.core.distances import mhd_matrix, nearest_mhd


def curves(rng: np.random.Generator, n: int) -> np.ndarray:
    x = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    return 1 + 0.3 * rng.uniform(0.2, 1, (n, 1)) * np.sin(np.outer(rng.uniform(1, 4, n), x) + rng.uniform(0, 6, (n, 1)))


def per_pair(function, queries: np.ndarray, library: np.ndarray) -> tuple[float, np.ndarray]:
    start = time.perf_counter()
    index = function(queries, library)
    return (time.perf_counter() - start) / (len(queries) * len(library)), index


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--library", type=int, default=100_000)
    parser.add_argument("--queries", type=int, default=20)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    large = curves(rng, args.library)
    nearest_mhd(large[:1], large[:2])  # compile (or load the cached kernel) outside the timing
    methods = {
        "mhd_matrix + argmin": lambda q, lib: np.argmin(mhd_matrix(q, lib), axis=1),
        "nearest_mhd": lambda q, lib: nearest_mhd(q, lib)[0],
    }
    figures = []
    with threadpool_limits(1):
        for name, (queries, library) in {
            f"{args.queries} x {args.library}": (curves(rng, args.queries), large),
            "100 x 560": (curves(rng, 100), large[:560]),
        }.items():
            times = {method: per_pair(f, queries, library) for method, f in methods.items()}
            (t0, i0), (t1, i1) = times.values()
            print(
                f"{name}: mhd_matrix {t0 * 1e6:.2f} us/pair, nearest_mhd {t1 * 1e6:.3f} us/pair, "
                f"{t0 / t1:.1f}x; same items: {bool(np.array_equal(i0, i1))}"
            )
            figures += [
                (f"{name}: mhd_matrix", t0 * 1e6, "us per pair"),
                (f"{name}: nearest_mhd", t1 * 1e6, "us per pair"),
                (f"{name}: speed-up", t0 / t1, "x"),
            ]
    write(figures)


if __name__ == "__main__":
    main()
