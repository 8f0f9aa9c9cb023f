"""Descriptors of one view from 250 candidate sources (thesis 6.2.1): one spectrum against one solve per source.

Beer mug (embedded), one view at 30 deg azimuth and elevation, 1 m, 250 candidate sources
by mesh simplification, 64 polar samples, one thread. Baseline: ``describe`` with one
spec per source (a Krylov heat solve each on a shared factorization).

    .venv/bin/python benchmarks/bench_candidate_descriptors.py
"""

import time

import numpy as np
from record import write
from threadpoolctl import threadpool_limits

import heatdata as hd
from heatdata.descriptors.sources import candidate_descriptors, candidate_sources


def timed(function):
    tic = time.perf_counter()
    out = function()
    return out, time.perf_counter() - tic


def main() -> None:
    catalog = hd.read_catalog("data/models/catalog.csv")
    view = hd.render_view(
        hd.load_catalog_model(catalog[catalog["object"] == "beer-mug"].iloc[0]), 30.0, 30.0, 1.0, seed=0
    )
    sources = candidate_sources(view, 250)
    pvhk = hd.DescriptorSpec(kind="pvhk", sampling="polar")
    with threadpool_limits(1):
        spectral, spectral_s = timed(lambda: candidate_descriptors(view, sources, pvhk))
        krylov, krylov_s = timed(
            lambda: hd.describe(
                view, [hd.DescriptorSpec(kind="pvhk", sampling="polar", source=int(s)) for s in sources]
            )
        )
        _, pvst_s = timed(
            lambda: candidate_descriptors(view, sources, hd.DescriptorSpec(kind="pvst", sampling="polar"))
        )
    error = max(np.abs(a.values - b.values).max() for a, b in zip(spectral, krylov, strict=True))
    print(
        f"{view.n_vertices} vertices, 250 sources: PVHK from one spectrum {spectral_s:.2f} s, one Krylov solve "
        f"per source {krylov_s:.2f} s ({krylov_s / spectral_s:.0f}x), max difference {error:.1e}; "
        f"PVST (a heat model per source) {pvst_s:.1f} s"
    )
    write(
        [
            (f"250 candidate PVHKs of a {view.n_vertices}-vertex view, one spectrum", spectral_s, "s"),
            ("the same, one Krylov solve per source", krylov_s, "s"),
            ("largest difference between the two", error, "temperature"),
            ("250 candidate PVSTs (a heat model per source)", pvst_s, "s"),
        ]
    )


if __name__ == "__main__":
    main()
