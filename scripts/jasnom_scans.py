"""JASNOM on two scans rendered from opposite sides (issue 14): alignment, stitching and recognition.

Each embedded model is rendered by the virtual Kinect standing (azimuth 0, elevation
+``--elevation``) and flipped (azimuth 180, elevation -``--elevation``), the thesis's
acquisition of 7.5, each view in its own camera frame; the camera poses give the true
motion. Per object:

- **Alignment**: ``heatdata.stitch.align`` on the views' longest boundaries (their
  silhouettes, cut where the depth jumps), with and without the crossing penalty:
  rotation and translation errors; the RMS gap between the boundaries at the true motion
  (best shift, as a fraction of the object's size), and J1 there against J1 at the
  optimum found: when the optimum is lower than the truth, the cost itself prefers the
  wrong pose (the boundaries are not one curve), which no search can fix.
- **Stitching**, twice: at JASNOM's alignment (beta 1), and at the true motion
  (registered cameras, ``stitch(..., motion=)``), which isolates the strip from the
  alignment. Watertight and consistently wound (trimesh); distances from the stitched
  surface to the original's (mean, and the symmetric Hausdorff), as fractions of the size.
- **Recognition**: a PVHK library of every original (``--library`` views at elevation 30,
  1 m, the default run's camera); test views rendered from the originals, from the
  registered stitches and from JASNOM's, at azimuths between the library's, with fresh
  noise: object precision of each.

Rendered views, not real sensor data.

    .venv/bin/python scripts/jasnom_scans.py [--azimuth 0] [--elevation 45] [--out docs/results/jasnom_scans.csv] \
        [--precision-out docs/results/jasnom_scans_precision.csv]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import pandas as pd
import trimesh
from scipy.spatial.transform import Rotation

from heatdata.catalog import embedded_catalog, load_catalog_model, read_catalog
from heatdata.dataset import render_views, view_plan
from heatdata.descriptors import DescriptorSpec, describe
from heatdata.errors import HeatdataError
from heatdata.log import progress
from heatdata.mesh import surface_distances
from heatdata.models import Model
from heatdata.recognition import nearest_neighbours
from heatdata.render import render_view
from heatdata.stitch import align, alignment_at, boundary, resample_loop, stitch, transformed

SPEC = DescriptorSpec("pvhk", 64, "center", "polar")  # the default run's primary descriptor


def view_model(view, name: str, label: str) -> Model:
    return Model.untextured(name, view.vertices, view.faces, view.colors[view.faces], label=label)


def rotation_error(found: np.ndarray, truth: np.ndarray) -> float:
    return float(np.degrees((Rotation.from_matrix(found) * Rotation.from_matrix(truth).inv()).magnitude()))


def stitched_row(model: Model, original: Model, size: float, prefix: str) -> dict:
    mesh = trimesh.Trimesh(model.vertices, model.faces, process=False)
    there, back = surface_distances((model.vertices, model.faces), (original.vertices, original.faces))
    return {f"{prefix}_watertight": bool(mesh.is_watertight), f"{prefix}_winding": bool(mesh.is_winding_consistent),
            f"{prefix}_mean_distance": float(there.mean()) / size,
            f"{prefix}_hausdorff": float(max(there.max(), back.max())) / size}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--azimuth", type=float, default=0.0,
                        help="of the standing scan; the flipped one is 180 degrees round (default 0)")
    parser.add_argument("--elevation", type=float, default=45.0)
    parser.add_argument("--distance", type=float, default=3.0, help="scan camera distance in object sizes")
    parser.add_argument("--samples", type=int, default=128)
    parser.add_argument("--library", type=int, default=12, help="library views per original (default 12)")
    parser.add_argument("--test", type=int, default=24, help="test views per model (default 24)")
    parser.add_argument("--out")
    parser.add_argument("--precision-out", help="write the per-object precision table here")
    args = parser.parse_args()
    begin = time.perf_counter()
    catalog = read_catalog(embedded_catalog())
    plan = view_plan(list(catalog["object"]), n_train=args.library, n_test=args.test)
    rows, library, queries = [], [], []
    for _, row in progress(list(catalog.iterrows()), desc="scan pairs", unit="object"):
        obj = row["object"]
        model = load_catalog_model(row)
        size = float(np.linalg.norm(model.extents))
        standing = render_view(model, args.azimuth, args.elevation, args.distance * size, seed=1)
        flipped = render_view(model, args.azimuth + 180.0, -args.elevation, args.distance * size, seed=2)
        truth = np.linalg.inv(standing.pose) @ flipped.pose  # the flipped camera's frame in the standing one's
        first, second = view_model(standing, f"{obj}/standing", obj), view_model(flipped, f"{obj}/flipped", obj)
        mine = plan[plan["object"] == obj]
        library += [(obj, d) for d in describe_views(model, mine[mine["split"] == "train"])]
        queries += [("original", obj, d) for d in describe_views(model, mine[mine["split"] == "test"])]
        try:
            b1, b2 = boundary(first), boundary(second)
        except HeatdataError as error:
            rows.append({"object": obj, "error": str(error)})
            continue
        at_truth = alignment_at(b1, b2, truth[:3, :3], truth[:3, 3], beta=0.0, samples=args.samples)
        result = {"object": obj, "size": size, "loops": f"{b1.loops}/{b2.loops}",
                  "boundary_ratio": max(b1.length, b2.length) / min(b1.length, b2.length),
                  "gap_at_truth": float(np.sqrt(at_truth.edge_cost)) * rms_radius(b1, args.samples) / size,
                  "j1_at_truth": at_truth.edge_cost, "error": ""}
        for beta in (1.0, 0.0):
            found = align(b1, b2, beta=beta, samples=args.samples)
            result[f"rotation_error_deg_beta{beta:g}"] = rotation_error(found.rotation, truth[:3, :3])
            result[f"translation_error_beta{beta:g}"] = float(np.linalg.norm(found.translation - truth[:3, 3])) / size
            result[f"j1_found_beta{beta:g}"] = found.edge_cost
        to_world = standing.pose  # the standing camera's frame -> the model's
        for prefix, motion in (("registered", truth), ("jasnom", None)):
            try:
                joined = stitch(first, second, motion=motion, name=f"{obj}+{prefix}").model
            except HeatdataError as error:
                result[f"{prefix}_error"] = str(error)
                continue
            joined = transformed(joined, to_world[:3, :3], to_world[:3, 3])
            result.update(stitched_row(joined, model, size, prefix))
            try:
                queries += [(prefix, obj, d) for d in describe_views(joined, mine[mine["split"] == "test"])]
            except HeatdataError as error:
                result[f"{prefix}_error"] = f"rendering: {error}"
        rows.append(result)
    table = pd.DataFrame(rows)
    precision = recognition(library, queries)
    ok = table[table["error"] == ""]
    print(table.drop(columns=["error"]).round(3).to_string(index=False))
    for beta in ("1", "0"):
        aligned = (ok[f"rotation_error_deg_beta{beta}"] <= 2) & (ok[f"translation_error_beta{beta}"] <= 0.01)
        print(f"beta {beta}: {aligned.mean():.1%} of {len(ok)} pairs within 2 deg and 1%; the optimum's J1 below the "
              f"truth's in {(ok[f'j1_found_beta{beta}'] < ok['j1_at_truth']).mean():.1%}")
    print(f"median gap at the true motion {ok['gap_at_truth'].median():.1%} of the size")
    for prefix in ("registered", "jasnom"):
        done = ok.dropna(subset=[f"{prefix}_watertight"])
        closed = (done[f"{prefix}_watertight"] & done[f"{prefix}_winding"]).mean()
        print(f"{prefix}: {len(done)} of {len(ok)} stitched, watertight and consistently wound {closed:.1%}, median "
              f"mean distance {done[f'{prefix}_mean_distance'].median():.2%}, median Hausdorff "
              f"{done[f'{prefix}_hausdorff'].median():.1%}")
    print(precision.round(3).to_string())
    print(f"{time.perf_counter() - begin:.0f} s in all")
    if args.out:
        table.round(6).to_csv(args.out, index=False)
    if args.precision_out:
        precision.round(6).to_csv(args.precision_out)


def rms_radius(b, samples: int) -> float:
    """J1's scale (heatdata.stitch): the RMS distance of the resampled boundary from its centroid."""
    x = resample_loop(b.points, samples)[0]
    return float(np.sqrt(np.mean(np.sum((x - x.mean(axis=0)) ** 2, axis=1))))


def describe_views(model: Model, plan: pd.DataFrame) -> list:
    return [describe(view, [SPEC])[0] for view in render_views(model, plan)]


def recognition(library: list, queries: list) -> pd.DataFrame:
    """Object precision per object (rows) of the test views of each source (columns), and over all objects."""
    labels = np.array([obj for obj, _ in library])
    frame = pd.DataFrame([{"source": source, "object": obj} for source, obj, _ in queries])
    nearest = nearest_neighbours([d for _, _, d in queries], [d for _, d in library])
    frame["correct"] = labels[nearest.index] == frame["object"].to_numpy()
    table = frame.pivot_table(index="object", columns="source", values="correct", aggfunc="mean")
    table.loc["all objects"] = frame.groupby("source")["correct"].mean()
    table.loc["test views"] = frame.groupby("source").size()
    return table[[c for c in ("original", "registered", "jasnom") if c in table.columns]]


if __name__ == "__main__":
    main()
