"""Ablation: what the canonical frame did to multi-view recognition (thesis ch. 4) with the C-PVHK from the
``center`` source.

The canonical frame (``View.canonical_rotation``, eq. 2.8) turns the camera to face the segment's image box before
the ``center`` source and the boundary's planar frame are taken. Before it, both were taken in the camera's own
frame, whose axis the renderer aims at the model's centre. This script renders the multi-view experiment's views
once (``config/experiments/multiview.yaml``: the three cups and mugs and the two speakers), describes them twice,
in each frame, and runs the experiment's trials (:func:`heatdata.experiments.multiview.multiview_experiment`) on
each; it also counts where the ``center`` source lands on the object, as the distance between the two frames'
sources.

    .venv/bin/python scripts/multiview_canonical.py --repetitions 10 --out docs/results/multiview_canonical.csv
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np
import pandas as pd
import yaml
from snakemake.utils import validate

import heatdata as hd
from heatdata.descriptors.boundary import source_vertex
from heatdata.descriptors.rows import descriptor_rows
from heatdata.experiments.multiview import multiview_experiment, trial_summary
from heatdata.experiments.views import render_views, view_plan
from heatdata.views.view import View

ROOT = Path(__file__).resolve().parents[1]
DESCRIPTOR = {"kind": "c-pvhk", "samples": 64, "source": "center", "sampling": "polar", "color_map": "sat-hue",
              "clock": "shape"}  # fmt: skip


def run_config(path: str) -> dict:
    """config/config.yaml with the experiment's keys over it, checked and completed by the workflow's schema."""
    config = yaml.safe_load((ROOT / "config/config.yaml").read_text())
    for key, value in yaml.safe_load((ROOT / path).read_text()).items():
        config[key] = (
            {**config[key], **value} if isinstance(value, dict) and isinstance(config.get(key), dict) else value
        )
    validate(config, str(ROOT / "workflow/schemas/config.schema.yaml"), set_default=True)
    return config


def camera_frame(view: View) -> np.ndarray:
    """The frame before the canonical one: the camera's own (no turn)."""
    return np.eye(3)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--config", default="config/experiments/multiview.yaml")
    parser.add_argument("--repetitions", type=int, default=10, help="runs per start view and setting")
    parser.add_argument("--out", type=Path)
    args = parser.parse_args()
    config = run_config(args.config)
    settings = {**config["multiview"], "repetitions": args.repetitions}
    spec = hd.DescriptorSpec.from_dict(DESCRIPTOR)
    catalog = {row["object"]: row for row in hd.read_catalog(hd.embedded_catalog()).to_dict("records")}
    views_config = config["views"]
    start = time.perf_counter()
    views, plans = [], []
    for obj in config["objects"]:
        plan = view_plan([obj], views_config["train"], views_config["test"], elevation=views_config["elevation"],
                         distance=views_config["distance"], seed=views_config["seed"])  # fmt: skip
        views.append(render_views(hd.load_catalog_model(catalog[obj]), plan, noise=views_config["noise"]))
        plans.append(plan)
    print(f"rendered {sum(map(len, views))} views in {time.perf_counter() - start:.0f} s", flush=True)
    canonical = View.canonical_rotation
    tables, moved = [], []
    for frame in ("canonical", "camera"):
        if frame == "camera":
            View.canonical_rotation = property(camera_frame)  # type: ignore[assignment,method-assign]
        try:
            fresh = [[dataclasses.replace(v) for v in vs] for vs in views]  # no description cached from the other frame
            rows = pd.concat([descriptor_rows(vs, plan, [spec]) for vs, plan in zip(fresh, plans)], ignore_index=True)
            moved.append([v.vertices[source_vertex(v, "center")] for vs in fresh for v in vs])
            tic = time.perf_counter()
            trials, _ = multiview_experiment(rows, spec.name, settings)
        finally:
            View.canonical_rotation = canonical  # type: ignore[method-assign]
        summary = trial_summary(trials).assign(frame=frame)
        tables.append(summary)
        print(f"{frame} frame: {len(trials)} runs in {time.perf_counter() - tic:.0f} s", flush=True)
    shift = np.linalg.norm(np.array(moved[0]) - np.array(moved[1]), axis=1)
    print(f"the 'center' source moved between the frames by {np.median(shift) * 1000:.1f} mm (median), "
          f"{np.percentile(shift, 90) * 1000:.1f} mm (90th percentile)")  # fmt: skip
    table = pd.concat(tables, ignore_index=True)
    shown = table.pivot_table(index=["library_views", "policy", "bootstrap", "particles"], columns="frame",
                              values="accuracy").reset_index()  # fmt: skip
    print(shown.round(3).to_string(index=False))
    if args.out:
        table.round(4).to_csv(args.out, index=False)


if __name__ == "__main__":
    main()
