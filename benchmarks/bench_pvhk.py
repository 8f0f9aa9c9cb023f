"""Speed of one PVHK (spectrum + descriptor) against the naive eigen-solve, and its accuracy.

Renders one view of an embedded object (about 5,000 vertices by default), then times
on one thread (threadpoolctl):

* naive: Laplacian + ``scipy.sparse.linalg.eigsh(L, k=30, sigma=-shift)`` (SuperLU
  shift-invert, as the thesis's eigs call) + eq. 2.9 at the boundary;
* heatdata ``pvhk(method="eigen", modes=16|30)``: ARPACK with a CHOLMOD factor;
* heatdata ``pvhk(method="krylov")`` (the default): lambda_2 by Lanczos and the heat by
  shift-invert Krylov projection, one CHOLMOD factorization.

Every time includes the work done from a fresh ``View`` (edges, boundary, Laplacian).
The reference is ``expm_multiply`` (exact up to its own tolerance) at t = 1/lambda_2.

    .venv/bin/python benchmarks/bench_pvhk.py [--object beer-mug] [--distance 1.15] [--repeat 7]
"""

from __future__ import annotations

import argparse
import json
import logging
import resource
import time
from pathlib import Path

import numpy as np
import scipy.sparse.linalg as sla
from threadpoolctl import threadpool_limits

import heatdata as hd
from heatdata.spectrum import laplacian

ROOT = Path(__file__).resolve().parents[1]


def fresh(view: hd.View) -> hd.View:
    return hd.View(vertices=view.vertices, faces=view.faces, colors=view.colors, intrinsics=view.intrinsics)


def naive(view: hd.View, source: int) -> np.ndarray:
    v = fresh(view)
    L = laplacian(v.vertices, v.edges)
    shift = 1e-6 * L.diagonal().mean()
    values, vectors = sla.eigsh(L, k=30, sigma=-shift)
    boundary = v.boundary
    t = 1.0 / values[1]
    temps = (vectors[boundary] * np.exp(-values * t)) @ vectors[source] * v.n_vertices
    return hd.sample_boundary(v, boundary, temps, 64)[0]


def reference(view: hd.View, source: int) -> np.ndarray:
    v = fresh(view)
    L = laplacian(v.vertices, v.edges)
    t = 1.0 / hd.lambda2(hd.HeatOperator(L))
    pulse = np.zeros(v.n_vertices)
    pulse[source] = 1.0
    temps = sla.expm_multiply(-t * L, pulse) * v.n_vertices
    return hd.sample_boundary(v, v.boundary, temps[v.boundary], 64)[0]


def best_time(function, repeat: int) -> tuple[float, np.ndarray]:
    best, result = np.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        result = function()
        best = min(best, time.perf_counter() - start)
    return best, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--object", default="beer-mug")
    parser.add_argument("--distance", type=float, default=1.15)
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--out", type=Path, default=None, help="write the numbers as JSON")
    args = parser.parse_args()
    logging.disable(logging.WARNING)
    catalog = hd.read_catalog(ROOT / "data/models/catalog.csv")
    model = hd.load_catalog_model(catalog[catalog["object"] == args.object].iloc[0])
    view = hd.render_view(model, azimuth=30.0, elevation=30.0, distance=args.distance, seed=0)
    source = hd.source_vertex(view, "closest")
    with threadpool_limits(1):
        exact = reference(view, source)
        rows = {}
        rows["naive eigsh k=30 (SuperLU)"] = best_time(lambda: naive(view, source), args.repeat)
        for modes in (16, 30):
            rows[f"heatdata eigen k={modes} (CHOLMOD)"] = best_time(
                lambda: hd.pvhk(fresh(view), 64, method="eigen", modes=modes).values, args.repeat)
        rows["heatdata krylov (default)"] = best_time(lambda: hd.pvhk(fresh(view), 64).values, args.repeat)
    base = rows["naive eigsh k=30 (SuperLU)"][0]
    print(f"view: {args.object} at {args.distance} m, {view.n_vertices} vertices, "
          f"{len(view.boundary)} boundary vertices; one thread; best of {args.repeat}")
    print(f"{'method':34s} {'ms':>8s} {'speed-up':>9s} {'max |error|':>12s}")
    report = {"vertices": view.n_vertices, "methods": {}}
    for name, (seconds, values) in rows.items():
        error = float(np.max(np.abs(values - exact)))
        print(f"{name:34s} {seconds * 1e3:8.1f} {base / seconds:9.1f} {error:12.2e}")
        report["methods"][name] = {"ms": seconds * 1e3, "speedup": base / seconds, "max_error": error}
    report["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"peak RSS of this process: {report['peak_rss_mb']:.0f} MB")
    if args.out:
        args.out.write_text(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
