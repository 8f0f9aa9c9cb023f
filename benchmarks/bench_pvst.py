"""Speed of PVST and FT-PVHK against PVHK on one view, and PVST's accuracy (thesis 5.4, Alg. 5.3).

Speed: one rendered view of an embedded object (about 5,000 vertices by default),
source rule ``center`` (an interior source, as the PVST needs), polar sampling, 64
samples, one thread; the methods run round-robin from views whose mesh structure
(edges, boundary loop, components) is known, and each keeps its best time:

* ``pvhk``: lambda_2 + the heat at t_s = 1/lambda_2 (the baseline);
* ``ft_pvhk``: the heat at a fixed time (the object's time scale), no lambda_2;
* ``ft_pvhk + part_weights``: what the workflow computes per FT-PVHK (16+ eigenpairs);
* ``pvst``: lambda_2 for t_final = 10/lambda_2, then heat models over the window;
* ``pvhk + pvst in one describe``: what the workflow does, sharing the factorization
  and lambda_2.

Accuracy: the PVST crossing time of every boundary vertex against a dense reference on
a smaller rendered view (dense ``eigh`` of the Laplacian; the first crossing located on
4,000 log-spaced times and refined by ``brentq`` to 1e-16), for the ``center`` source
and for the ``closest`` source (often near the outline: a window of 10^4-10^6 in t).

    .venv/bin/python benchmarks/bench_pvst.py [--object beer-mug] [--distance 1.15] [--repeat 20]
"""

from __future__ import annotations

import argparse
import logging
from pathlib import Path

import numpy as np
from bench_pvhk import interleaved_best, prepared  # run as a script: benchmarks/ is on sys.path
from record import write
from scipy.optimize import brentq
from threadpoolctl import threadpool_limits

import heatdata as hd
from heatdata.descriptors import heat_operator, source_vertex

ROOT = Path(__file__).resolve().parents[1]


def render(name: str, distance: float) -> hd.View:
    catalog = hd.read_catalog(ROOT / "data/models/catalog.csv")
    model = hd.load_catalog_model(catalog[catalog["object"] == name].iloc[0])
    return hd.render_view(model, azimuth=30.0, elevation=30.0, distance=distance, seed=0)


def dense_crossings(view: hd.View, source: int, threshold: float, t_end: float) -> np.ndarray:
    """First crossing of ``threshold`` at each boundary vertex from a dense eigendecomposition."""
    L = heat_operator(view).L.toarray()
    values, vectors = np.linalg.eigh(L)
    n = len(L)
    grid = np.geomspace(t_end * 1e-12, t_end, 4000)
    decay = np.exp(-np.outer(grid, values))
    out = np.full(len(view.boundary), np.nan)
    for k, i in enumerate(view.boundary):
        coefficients = n * vectors[i] * vectors[source]
        above = decay @ coefficients >= threshold
        if not above.any() or above[0]:
            continue
        first = int(np.argmax(above))
        out[k] = brentq(
            lambda t, c=coefficients: c @ np.exp(-values * t) - threshold, grid[first - 1], grid[first], xtol=1e-16
        )
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--object", default="beer-mug")
    parser.add_argument("--distance", type=float, default=1.15)
    parser.add_argument("--repeat", type=int, default=20)
    parser.add_argument("--accuracy-object", default="plastic-cup")
    args = parser.parse_args()
    logging.disable(logging.WARNING)
    view = render(args.object, args.distance)
    t_fixed = 1.0 / hd.pvhk(view, 64, "center", sampling="polar").lambda2
    with threadpool_limits(1):
        ready = prepared(view)
        best = interleaved_best(
            {
                "pvhk": lambda: hd.pvhk(ready, 64, "center", sampling="polar"),
                "ft_pvhk": lambda: hd.ft_pvhk(ready, t_fixed, 64, "center", sampling="polar"),
                "ft_pvhk + part_weights": lambda: hd.describe(
                    ready, [hd.DescriptorSpec("ft-pvhk", 64, "center", "polar")], times=[t_fixed]
                ),
                "pvst": lambda: hd.pvst(ready, 64, source="center", sampling="polar"),
                "pvhk + pvst in one describe": lambda: hd.describe(
                    ready,
                    [
                        hd.DescriptorSpec("pvhk", 64, "center", "polar"),
                        hd.DescriptorSpec("pvst", 64, "center", "polar"),
                    ],
                ),
            },
            args.repeat,
        )
    times = {name: seconds for name, (seconds, _) in best.items()}
    print(
        f"speed: {args.object} at {args.distance} m, {view.n_vertices} vertices, {len(view.boundary)} boundary "
        f"vertices; source center, polar, 64 samples; one thread; best of {args.repeat}"
    )
    for name, seconds in times.items():
        print(f"  {name:28s} {seconds * 1e3:7.1f} ms  {seconds / times['pvhk']:4.2f}x pvhk")
    added = times["pvhk + pvst in one describe"] - times["pvhk"]
    print(
        f"  a PVST next to a PVHK (shared factorization and lambda_2) adds {added * 1e3:.1f} ms, "
        f"{added / times['pvhk']:.2f}x pvhk"
    )

    figures = [(f"{name}, {view.n_vertices}-vertex view", seconds * 1e3, "ms") for name, seconds in times.items()]
    figures += [("PVST / PVHK", times["pvst"] / times["pvhk"], "x"), ("a PVST beside a PVHK adds", added * 1e3, "ms")]

    small = render(args.accuracy_object, 1.0)
    print(f"accuracy: {args.accuracy_object} at 1.0 m, {small.n_vertices} vertices, every boundary vertex")
    for rule in ("center", "closest"):
        d = hd.pvst(small, samples=None, source=rule)
        source = source_vertex(small, rule)
        if small.n_components > 1:
            raise SystemExit("the accuracy view must be one connected component")
        exact = dense_crossings(small, source, 0.75, d.time)
        both = np.isfinite(exact) & np.isfinite(d.values)
        relative = np.abs(d.values[both] - exact[both]) / exact[both]
        gap = np.min(np.linalg.norm(small.vertices[small.boundary] - small.vertices[source], axis=1))
        print(
            f"  source {rule:8s} (gap {gap * 1e3:.1f} mm): window {np.nanmin(exact):.2e}..{d.time:.2e}; "
            f"max relative error {relative.max():.1e} over {both.sum()} vertices; NaN in heatdata "
            f"{int(np.isnan(d.values).sum())}, in the reference {int(np.isnan(exact).sum())}"
        )
        figures.append((f"PVST crossing times, source {rule}: largest relative error", relative.max(), "relative"))
    write(figures)


if __name__ == "__main__":
    main()
