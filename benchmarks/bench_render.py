"""Rendering + meshing time per view, and the time and peak memory of a large view's PVHK.

    .venv/bin/python benchmarks/bench_render.py [--repeat 20]

Rendering is timed for every embedded object at 1 m (best of ``--repeat``, one
thread). The large-view part renders the tall speaker close enough for ~20,000
vertices and reports the process's peak resident memory before and after its PVHK
(``ru_maxrss``; run it in a fresh process).
"""

from __future__ import annotations

import argparse
import logging
import resource
import time
from pathlib import Path

from record import write
from threadpoolctl import threadpool_limits

import heatdata as hd

ROOT = Path(__file__).resolve().parents[1]


def peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=20)
    args = parser.parse_args()
    logging.disable(logging.WARNING)
    catalog = hd.read_catalog(ROOT / "data/models/catalog.csv")
    models = {row["object"]: hd.load_catalog_model(row) for _, row in catalog.iterrows()}
    with threadpool_limits(1):
        large = hd.render_view(models["speaker-tall"], 30.0, 30.0, 0.85, seed=0)
        before = peak_mb()
        start = time.perf_counter()
        hd.pvhk(large, 64)
        large_seconds = time.perf_counter() - start
        after = peak_mb()
        print(f"{'object':15s} {'vertices':>8s} {'render+mesh ms':>15s}")
        worst, figures = 0.0, []
        for name, model in models.items():
            best = float("inf")
            for k in range(args.repeat):
                tic = time.perf_counter()
                view = hd.render_view(model, 30.0 + k, 30.0, 1.0, seed=k)
                best = min(best, time.perf_counter() - tic)
            worst = max(worst, best)
            print(f"{name:15s} {view.n_vertices:8d} {best * 1e3:15.1f}")
            figures.append((f"render and mesh {name} ({view.n_vertices} vertices)", best * 1e3, "ms"))
    print(f"slowest object: {worst * 1e3:.1f} ms per view (best of {args.repeat})")
    print(
        f"large view: {large.n_vertices} vertices, PVHK {large_seconds * 1e3:.0f} ms; "
        f"peak RSS {before:.0f} MB before, {after:.0f} MB after (+{after - before:.0f} MB)"
    )
    figures += [
        ("render and mesh, slowest object", worst * 1e3, "ms"),
        (f"PVHK of a {large.n_vertices}-vertex view", large_seconds * 1e3, "ms"),
        ("peak RSS added by that PVHK", after - before, "MB"),
        ("peak RSS after it", after, "MB"),
    ]
    write(figures)


if __name__ == "__main__":
    main()
