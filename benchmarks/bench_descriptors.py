"""Time per ~5,000-vertex view of every descriptor kind, the baselines of thesis 3.6.1 beside the PVHK.

Renders one view of an embedded object (beer mug at 1.15 m: 5,125 vertices), then times
``hd.describe(view, [spec])`` for each available kind on one thread (threadpoolctl),
round-robin over the kinds and keeping each one's best of ``--repeat`` (the VM's speed
drifts by up to 1.5x), each on a fresh ``View`` so no kind profits from another's cached
work. SI-HKS is fitted on three other views of the object first (not timed); its time
is the description of one view with the fitted codebook. Peak RSS of the process is
printed at the end.

    .venv/bin/python benchmarks/bench_descriptors.py [--object beer-mug] [--distance 1.15] [--repeat 5]
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
SPECS = [
    hd.DescriptorSpec("pvhk", 64, "center", "polar"),
    hd.DescriptorSpec("pvst", 64, "interior", "polar"),
    hd.DescriptorSpec("si-hks"),
    hd.DescriptorSpec("fpfh"),
    hd.DescriptorSpec("vfh"),
    hd.DescriptorSpec("esf"),
    hd.DescriptorSpec("hgd"),
    hd.DescriptorSpec("hgd", color="hue-saturation"),
]


def fresh(view: hd.View) -> hd.View:
    return hd.View(vertices=view.vertices, faces=view.faces, colors=view.colors, intrinsics=view.intrinsics)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--object", default="beer-mug")
    parser.add_argument("--distance", type=float, default=1.15)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    catalog = hd.read_catalog(ROOT / "data" / "models" / "catalog.csv")
    model = hd.load_catalog_model(catalog[catalog["object"] == args.object].iloc[0])
    view = hd.render_view(model, 30.0, 30.0, args.distance, seed=0)
    specs = [s for s in SPECS if hd.DESCRIPTORS[s.kind] is None]
    for s in SPECS:
        if hd.DESCRIPTORS[s.kind] is not None:
            print(f"{s.name}: skipped, {hd.DESCRIPTORS[s.kind]}")
    with threadpool_limits(1):
        library = [hd.render_view(model, az, 30.0, args.distance, seed=k) for k, az in enumerate((90.0, 180.0, 270.0))]
        specs = [hd.fit_spec(s, library) for s in specs]
        best = {s.name: float("inf") for s in specs}
        for _ in range(args.repeat):
            for spec in specs:
                v = fresh(view)
                tic = time.perf_counter()
                hd.describe(v, [spec])
                best[spec.name] = min(best[spec.name], time.perf_counter() - tic)
    reference = best[specs[0].name]
    print(f"view: {args.object} at {args.distance} m, {view.n_vertices} vertices; one thread; best of {args.repeat}")
    print(f"{'descriptor':30s} {'ms':>9s} {'x PVHK':>8s}")
    for name, seconds in best.items():
        print(f"{name:30s} {1e3 * seconds:9.1f} {seconds / reference:8.1f}")
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"peak RSS {peak:.0f} MB")
    figures = [(f"{name}, {view.n_vertices}-vertex view", 1e3 * seconds, "ms") for name, seconds in best.items()]
    write([*figures, ("peak RSS", peak, "MB")])


if __name__ == "__main__":
    main()
