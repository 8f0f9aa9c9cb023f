"""Poses and verification on a run's rendered test views: how right the poses are, and what verification adds to
the confidence when each object is left out of the library in turn (:mod:`heatdata.experiments.poses`).

    .venv/bin/python scripts/poses.py results --library results/libraries/hgd_color=hue-saturation-40.parquet \\
        --views-per-object 20 --out docs/results/poses_household.csv \\
        --open-set-out docs/results/open_set_verified_household.csv

``--whole`` renders the test views again from the run's models with every connected piece kept (as a scene's
segment keeps them), where a run of ``views.components: largest`` (the thesis's protocol) keeps the largest piece of
each: verification then sees the whole object the sensor saw (the run's ``catalog.csv`` names the models).

Rendered views, not real sensor data. One row per library in each table, with the wall time.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import pandas as pd

from heatdata.experiments.poses import (
    evenly,
    pose_scores,
    pose_summary,
    verified_open_set,
    verified_open_set_summary,
)
from heatdata.io.tables import read_table
from heatdata.log import setup_logging
from heatdata.recognition.library import load_library
from heatdata.views.frames import frame_to_views


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", type=Path, help="a run's results folder (views/)")
    parser.add_argument("--library", type=Path, required=True, help="a library file with surface samples")
    parser.add_argument("--views-per-object", type=int, default=20, help="test views per object (default 20)")
    parser.add_argument("--out", type=Path, required=True, help="the pose table to write (.csv)")
    parser.add_argument("--open-set-out", type=Path, required=True, help="the verified open-set table (.csv)")
    parser.add_argument("--whole", action="store_true", help="render the test views again, every piece kept")
    args = parser.parse_args()
    setup_logging()
    library = load_library(args.library)
    views = []
    for obj in library.objects:
        frame, run = read_table(args.run / "views" / f"{obj}.parquet", filters=[("split", "==", "test")])
        chosen = evenly(frame_to_views(frame), args.views_per_object)
        views += _whole(args.run, obj, chosen, frame, run["views"]) if args.whole else chosen
    start = time.perf_counter()
    poses = pose_summary(pose_scores(library, views))
    row = {"descriptor": library.descriptor, "size": library.library_size, **poses}
    row["seconds"] = round(time.perf_counter() - start, 1)
    print(", ".join(f"{k} {v:.3f}" if isinstance(v, float) else f"{k} {v}" for k, v in row.items()))
    start = time.perf_counter()
    opened = verified_open_set_summary(verified_open_set(library, views))
    other = {"descriptor": library.descriptor, "size": library.library_size, **opened}
    other["seconds"] = round(time.perf_counter() - start, 1)
    print(", ".join(f"{k} {v:.3f}" if isinstance(v, float) else f"{k} {v}" for k, v in other.items()))
    for path, table in ((args.out, row), (args.open_set_out, other)):
        path.parent.mkdir(parents=True, exist_ok=True)
        pd.DataFrame([table]).to_csv(path, index=False)


def _whole(run: Path, obj: str, views: list, frame: pd.DataFrame, settings: dict) -> list:
    """``views`` rendered again as the run rendered them (angle, distance, noise seed, sensor, image size), every
    connected piece kept."""
    from heatdata.io.catalog import load_catalog_model, read_catalog
    from heatdata.views.render import render_view
    from heatdata.views.view import kinect_intrinsics

    row = read_catalog(run / "catalog.csv").set_index("object").loc[obj].to_dict()
    model = load_catalog_model({**row, "object": obj})
    seeds = frame.set_index("view_id")["seed"]
    return [
        render_view(
            model, v.azimuth, v.elevation, v.distance, noise=settings["noise"], seed=int(seeds[v.view_id]),
            sensor=settings.get("sensor"), intrinsics=kinect_intrinsics(settings.get("image_scale", 1.0)),
            components="all", view_id=v.view_id,
        )
        for v in views
    ]  # fmt: skip


if __name__ == "__main__":
    main()
