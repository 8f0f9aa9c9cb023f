"""Why a kind names objects in scenes worse than it names centred test views: an ablation on a scenes run.

A scenes run (``config/experiments/scenes.yaml``) recognizes each scene's segments with every library. This script
takes the first ``--scenes`` of its scenes and names each unoccluded object inside the frame (with at least 1,000
readings) again, one factor at a time:

1. ``segmented``: the nearest object of the segment that matches the object (mask IoU >= 0.5), without a pose;
2. ``true mask``: the object's own pixels in the same frame (the truth), its largest connected piece;
3. ``true mask, noise profile, 30 deg, 1 m``: the same scene rendered again without the Kinect's other effects and
   with the camera at the library's elevation and distance (the objects where they were);
4. ``true mask, the camera turned to face the object``: the same scene from the same place, the camera turned (not
   moved) to aim at the object's centre: what the canonical frame undoes;
5. ``true mask, the camera facing the object at 30 deg and 1 m``: each object alone on the table, seen from the
   scene camera's azimuth at the library's elevation and distance, aimed at its centre as the library's views are;
6. ``segmented, posed and verified``: the run's answer for that segment, whose candidates are posed in turn until one
   explains it (what the workflow and ``heatdata recognize`` answer).

    .venv/bin/python scripts/scene_ablation.py results/scenes_run --scenes 30 --out docs/results/scenes_ablation.csv

Rendered scenes, not real sensor data. One row per factor and descriptor.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import pandas as pd

from heatdata.experiments.scenes import (
    MIN_OBJECT_PIXELS,
    OCCLUDED,
    object_pose,
    plan_scene,
    read_scene,
    render_planned_scene,
    room,
    score_scene,
)
from heatdata.io.catalog import load_catalog_model, read_catalog
from heatdata.io.tables import read_table
from heatdata.recognition.library import load_library
from heatdata.views.depth import view_from_depth
from heatdata.views.render import Placement, camera_pose, render_scene
from heatdata.views.view import kinect_intrinsics


def named(library, depth, rgb, intrinsics, mask) -> str:
    """The library's answer for the pixels ``mask`` of a frame (its largest piece, as a captured mask's view)."""
    return library.recognize(view_from_depth(depth, intrinsics, rgb, mask), k=1, pose=False).best.object


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="a scenes run's results folder")
    parser.add_argument("--scenes", type=int, default=30, help="the first this many scenes (default 30)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    tables = [read_table(path) for path in sorted((args.run / "scenes" / "detections").glob("*.parquet"))]
    detections = pd.concat([table for table, _ in tables])
    settings, size = tables[0][1]["scenes"], tables[0][1]["library_size"]
    libraries = {
        name: load_library(args.run / "libraries" / f"{name.replace('/', '_')}-{size}.parquet")
        for name in detections["descriptor"].unique()
    }
    catalog = read_catalog(args.run / "catalog.csv").set_index("object")
    frames = sorted((args.run / "scenes" / "frames").glob("scene-*[0-9].png"))[: args.scenes]
    answers: list[dict] = []
    tic = time.perf_counter()
    for path in frames:
        depth, rgb, intrinsics, labels, truth = read_scene(path)
        plan = truth["plan"]
        models = {o["object"]: load_catalog_model({**catalog.loc[o["object"]].to_dict(), "object": o["object"]})
                  for o in plan["objects"]}  # fmt: skip
        fixed = {**settings, "sensor": "noise", "elevation": [30.0, 30.0], "distance": [1.0, 1.0]}
        again = _render(plan, models, fixed)
        turned = _turned(plan, models, settings, np.asarray(truth["camera"]))
        nearest = {
            name: score_scene(
                library.recognize_scene(depth, intrinsics, rgb, pose=False).detections, labels, depth, truth
            )
            for name, library in libraries.items()
        }
        for number, item in enumerate(truth["objects"], 1):
            if item["pixels"] < MIN_OBJECT_PIXELS or item["occluded"] > OCCLUDED or item["cut"]:
                continue
            spot = plan["objects"][number - 1]
            alone = _facing(models[item["object"]], spot, plan, settings)
            for name, library in libraries.items():
                mine = detections[(detections["descriptor"] == name) & (detections["scene"] == truth["scene"])]
                found = mine[mine["truth"] == item["object"]]
                plain = nearest[name][nearest[name]["truth"] == item["object"]]
                rows = {
                    "segmented": plain["object"].iloc[0] if len(plain) else "",
                    "true mask": named(library, depth, rgb, intrinsics, (labels == number) & np.isfinite(depth)),
                    "true mask, noise profile, 30 deg, 1 m": named(library, *again[:3], again[3] == number),
                    "true mask, the camera turned to face the object": named(library, *turned[number - 1]),
                    "true mask, the camera facing the object at 30 deg and 1 m": named(library, *alone),
                    "segmented, posed and verified": found["object"].iloc[0] if len(found) else "",
                }
                answers += [
                    {"factor": factor, "descriptor": name, "object": item["object"], "answer": answer}
                    for factor, answer in rows.items()
                ]
        print(f"{path.stem}: {len(answers)} answers ({time.perf_counter() - tic:.0f} s)", flush=True)
    table = pd.DataFrame(answers)
    table["correct"] = table["object"] == table["answer"]
    summary = (
        table.groupby(["factor", "descriptor"], sort=False)["correct"].agg(objects="size", naming="mean").reset_index()
    )
    summary.to_csv(args.out, index=False)
    print(summary.to_string(index=False))


def _render(plan: dict, models: dict, settings: dict):
    """The plan's scene rendered with ``settings``: the objects where they were (the same draws), the camera drawn
    from the settings' ranges; depth, colour, intrinsics and labels (object ``i`` is ``i + 1``)."""
    moved = plan_scene(list(models.values()), settings, int(plan["scene"].split("-")[1]))
    frame, truth = render_planned_scene(moved, models, settings)
    furniture = len(frame.names) - len(truth["objects"])
    labels = np.where(frame.labels >= furniture, frame.labels - furniture + 1, 0)
    return frame.depth, frame.rgb, frame.intrinsics, labels * np.isfinite(frame.depth)


def _turned(plan: dict, models: dict, settings: dict, camera: np.ndarray) -> list:
    """Each object of the scene, the camera where it stood, turned to aim at the object's centre: depth, colour,
    intrinsics and the object's mask, per object."""
    placements = [*room(*settings["table"], plan["wall_gap"])]
    centres = []
    for spot in plan["objects"]:
        model = models[spot["object"]]
        pose = object_pose(model, spot["x"], spot["z"], spot["yaw"])
        placements.append(Placement(model, pose))
        centres.append(pose[:3, :3] @ model.center + pose[:3, 3])
    furniture = len(placements) - len(centres)
    frames = []
    for number, centre in enumerate(centres):
        away = camera[:3, 3] - centre
        distance = float(np.linalg.norm(away))
        elevation = float(np.degrees(np.arcsin(away[1] / distance)))
        azimuth = float(np.degrees(np.arctan2(away[0], away[2])))
        aimed = camera_pose(centre, azimuth, elevation, distance)
        frame = render_scene(placements, aimed, intrinsics=kinect_intrinsics(settings["image_scale"]),
                             sensor=settings["sensor"], seed=plan["seed"])  # fmt: skip
        mask = (frame.labels == furniture + number) & np.isfinite(frame.depth)
        frames.append((frame.depth, frame.rgb, frame.intrinsics, mask))
    return frames


def _facing(model, spot: dict, plan: dict, settings: dict):
    """One object alone on the table, the camera at the scene's azimuth, 30 deg and 1 m, aimed at its centre."""
    pose = object_pose(model, spot["x"], spot["z"], spot["yaw"])
    centre = pose[:3, :3] @ model.center + pose[:3, 3]
    camera = camera_pose(centre, plan["camera"]["azimuth"], 30.0, 1.0)
    placements = [*room(*settings["table"], plan["wall_gap"]), Placement(model, pose)]
    frame = render_scene(placements, camera, intrinsics=kinect_intrinsics(), sensor="noise", seed=plan["seed"])
    mask = (frame.labels == len(placements) - 1) & np.isfinite(frame.depth)
    return frame.depth, frame.rgb, frame.intrinsics, mask


if __name__ == "__main__":
    main()
