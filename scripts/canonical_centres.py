"""Which segment centre the canonical frame should face (eq. 2.8, 2.3.3): an ablation on a run's rendered views.

Every view is described in the camera frame turned to face "the centre of the segmented depth image"
(``View.canonical_rotation``); the ``"center"`` source is the vertex nearest the turned optical axis and the
boundary's polar frame is centred there. This script describes a run's library views (``--size`` per object) and
its test views (every ``--step``-th) with the centre-source kinds, once per definition of that centre, and scores
them by the workflow's protocol (the nearest library view):

- ``camera axis``: no turn, the rendered camera's own axis. The renderer aims it at the model's bounding-box centre,
  a point fixed to the object that a segmentation of a real frame cannot know: what every view had before the
  canonical frame;
- ``points' centroid``: the mean of the view's vertices;
- ``mean pixel``: the ray through the mean of the vertices' pixels;
- ``3D box``: the centre of the vertices' bounding box;
- ``image box``: the ray through the centre of the pixels' bounding box, once;
- ``image box, fixed point``: the turn after which the image's bounding box is centred (heatdata's).

    .venv/bin/python scripts/canonical_centres.py results --out docs/results/canonical_centres.csv

Rendered views, not real sensor data. One row per centre and descriptor.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import fields
from functools import cached_property
from pathlib import Path

import numpy as np
import pandas as pd

from heatdata.core.geometry import rotation_between
from heatdata.descriptors import DescriptorSpec
from heatdata.descriptors.rows import descriptor_rows
from heatdata.io.tables import read_table
from heatdata.recognition.evaluate import classify, library_subset
from heatdata.views.frames import frame_to_views
from heatdata.views.view import View

AXIS = np.array([0.0, 0.0, 1.0])
SPECS = [DescriptorSpec("pvhk", 64, "center", "polar"), DescriptorSpec("c-pvhk", 64, "center", "polar", "c3")]


def ray(view: View, pixel: np.ndarray) -> np.ndarray:
    k = view.intrinsics
    return np.array([(pixel[0] - k["cx"]) / k["fx"], (pixel[1] - k["cy"]) / k["fy"], 1.0])


def facing(centre):
    """A View whose canonical frame faces ``centre(view)`` (a direction), or the camera's axis for None."""

    class Turned(View):
        @cached_property
        def canonical_rotation(self) -> np.ndarray:
            return np.eye(3) if centre is None else rotation_between(centre(self), AXIS)

    return Turned


CENTRES = {
    "camera axis": facing(None),
    "points' centroid": facing(lambda v: v.vertices.mean(axis=0)),
    "mean pixel": facing(lambda v: ray(v, v.pixels.mean(axis=0))),
    "3D box": facing(lambda v: (v.vertices.min(axis=0) + v.vertices.max(axis=0)) / 2),
    "image box": facing(lambda v: ray(v, (v.pixels.min(axis=0) + v.pixels.max(axis=0)) / 2)),
    "image box, fixed point": View,
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="a run's results folder (its views/)")
    parser.add_argument("--size", type=int, default=8, help="library views per object (default 8)")
    parser.add_argument("--step", type=int, default=2, help="every step-th test view (default 2)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    frames = []
    for path in sorted((args.run / "views").glob("*.parquet")):
        table, _ = read_table(path)
        frames += [
            library_subset(table[table["split"] == "train"], args.size),
            table[table["split"] == "test"][:: args.step],
        ]
    frame = pd.concat(frames, ignore_index=True)
    views = frame_to_views(frame)
    rows = []
    for name, kind in CENTRES.items():
        tic = time.perf_counter()
        turned = [kind(**{f.name: getattr(v, f.name) for f in fields(View)}) for v in views]
        table = descriptor_rows(turned, frame[["split", "seed"]], SPECS)
        for spec in SPECS:
            predictions = classify(table, spec.name)
            rows.append(
                {
                    "centre": name,
                    "descriptor": spec.name,
                    "library_size": args.size,
                    "test_views": len(predictions),
                    "precision": float(predictions["correct"].mean()),
                }
            )
            print(f"{name:24s} {spec.name:28s} {rows[-1]['precision']:.3f} ({time.perf_counter() - tic:.0f} s)")
    pd.DataFrame(rows).to_csv(args.out, index=False)


if __name__ == "__main__":
    main()
