"""Where a complex object's information goes, step by step (issue 28; thesis ch. 5, 3.6.1).

The ESF, fed a run's rendered views, tells the chairs apart far more often than the heat kinds do, so the
views carry the information; this script measures which step of the heat descriptors' pipeline loses it.
Each variant keeps everything but one step as the workflow has it (the view's largest component, the
PVHK's image-centre source, polar sampling, 64 samples, t_s = 1/lambda_2, the MHD of eq. 3.1), and is
scored by the workflow's protocol: the nearest library view among ``n`` per object evenly spaced in azimuth
(:func:`heatdata.recognition.evaluate.library_subset`), over the run's test views (every ``--test-every``-th):

- **the view**: how much "keep the largest component" drops (vertices, components), read from each
  view's ``repairs``; the whole views are measured by the workflow itself (``views.components: all``);
- **the boundary**: one loop or all of them, the temperatures at their vertices as a histogram, and the
  ESF fed the boundary's points alone;
- **the signature**: the curve at other times and at three at once; the same samples holding the loop's
  own geometry instead of a temperature (its 3D distance to its centroid, over the largest); the heat field
  over the whole surface (area-weighted histograms of log10 T at 0.3, 1 and 3 / lambda_2) from one source
  and from 16 spread by farthest-point sampling; the same joined with each vertex's distance to the source;
  and that distance alone;
- **the distance**: the PVHK curve under eq. 3.1, the pointwise L1 and an alignment-free L1 (sorted values).

    .venv/bin/python scripts/complex_ablation.py results/chairs_12 --out docs/results/chairs_12_steps.csv
    .venv/bin/python scripts/complex_ablation.py --plot docs/results/chairs_12_steps.csv \
        docs/results/household_steps.csv --figure docs/images/complex_steps.png   # the figure, from the tables

Heat is exact (the shift-invert Krylov model of :func:`heatdata.core.spectrum.heat_model`). One row per
variant and library size; the run's views stay as rendered (not real sensor data).
"""

from __future__ import annotations

import argparse
import re
import time
from multiprocessing import Pool
from pathlib import Path

import numpy as np
import pandas as pd
from threadpoolctl import threadpool_limits

from heatdata.core.distances import chi_square_matrix, mhd_matrix
from heatdata.core.mesh import boundary_loops
from heatdata.core.spectrum import heat_model
from heatdata.descriptors import ViewWork, sample_boundary, source_vertex
from heatdata.descriptors.esf import esf_histogram
from heatdata.errors import HeatdataError
from heatdata.io.tables import read_table
from heatdata.log import setup_logging
from heatdata.recognition.evaluate import library_subset
from heatdata.views.frames import frame_to_views

SAMPLES = 64
CURVE_TIMES = (0.5, 1.0, 2.0)  # x 1/lambda_2: the PVHK's t_s and one octave either side
FIELD_TIMES = (0.3, 1.0, 3.0)  # x 1/lambda_2, for the whole-surface distributions
SOURCES = 16
LOG_T = np.linspace(-4.0, 2.0, 17)  # bins of log10 T (equilibrium = 1)
RADII = np.linspace(0.0, 1.0, 33)  # bins of distance / the view's largest source distance
JOINT = (np.linspace(0.0, 1.0, 9), np.linspace(-4.0, 2.0, 9))
VALUES = np.linspace(0.0, 1.5, 17)  # bins of boundary temperatures
KEPT = re.compile(r"kept the largest of (\d+) components \((\d+) of (\d+) vertices\)")

#: (step, variant, feature, distance): what each row measures
VARIANTS = [
    ("view", "largest component, as rendered (ESF)", "esf", "chi2"),
    ("boundary", "ESF of the outer loop's points", "esf_outer", "chi2"),
    ("boundary", "ESF of every loop's points", "esf_loops", "chi2"),
    ("boundary", "PVHK values on the outer loop, as a histogram", "values_outer", "chi2"),
    ("boundary", "PVHK values on every loop, as a histogram", "values_loops", "chi2"),
    ("signature", "PVHK at t_s = 1/lambda_2 (the workflow's)", "curve_1", "mhd"),
    ("signature", "no heat: the loop's 3D distance to its centroid, at the same samples", "radius", "mhd"),
    ("signature", "PVHK at 0.5 / lambda_2", "curve_0.5", "mhd"),
    ("signature", "PVHK at 2 / lambda_2", "curve_2", "mhd"),
    ("signature", "PVHK at all three times (MHDs summed)", "curve_all", "mhd"),
    ("signature", "heat over the whole surface, 1 source (interior)", "field_1", "chi2"),
    ("signature", f"heat over the whole surface, {SOURCES} sources", "field_many", "chi2"),
    ("signature", f"heat x distance to the source, {SOURCES} sources", "joint_many", "chi2"),
    ("signature", f"distance to the source alone (no heat), {SOURCES} sources", "radii_many", "chi2"),
    ("distance", "PVHK curve, pointwise L1", "curve_1", "l1"),
    ("distance", "PVHK curve, sorted values L1 (alignment-free)", "sorted_1", "l1"),
]


def vertex_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(n,) a third of the area of each vertex's triangles, summing to 1."""
    area = 0.5 * np.linalg.norm(
        np.cross(vertices[faces[:, 1]] - vertices[faces[:, 0]], vertices[faces[:, 2]] - vertices[faces[:, 0]]), axis=1
    )
    per_vertex = np.bincount(faces.ravel(), np.repeat(area / 3.0, 3), len(vertices))
    return per_vertex / per_vertex.sum()


def farthest_points(points: np.ndarray, count: int, start: int) -> np.ndarray:
    """(count,) vertex indices spread by farthest-point sampling from ``start``."""
    chosen, gap = [start], np.linalg.norm(points - points[start], axis=1)
    for _ in range(count - 1):
        chosen.append(int(np.argmax(gap)))
        gap = np.minimum(gap, np.linalg.norm(points - points[chosen[-1]], axis=1))
    return np.array(chosen)


def histogram(values: np.ndarray, bins: np.ndarray, weights: np.ndarray | None = None) -> np.ndarray:
    return np.histogram(np.clip(values, bins[0], bins[-1]), bins, weights=weights)[0].astype(np.float64)


def features(view, samples: int = SAMPLES, triplets: int = 20000) -> dict:
    """Every variant's feature of one (connected) view: curves of ``samples``, ESFs of ``triplets``."""
    work = ViewWork(view)
    op = work.operator(view, None)
    t_s = 1.0 / work.lambda2(op)
    x, outer = view.vertices, view.boundary
    loops = np.concatenate([loop for loop in boundary_loops(view.faces, view.planar) if len(loop) >= 3])
    out = {
        "esf": esf_histogram(x, triplets=triplets),
        "esf_outer": esf_histogram(x[outer], triplets=triplets),
        "esf_loops": esf_histogram(x[loops], triplets=triplets),
        "loops": len(loops) / len(outer),
    }
    centre = source_vertex(view, "center")
    curve_times = np.array(CURVE_TIMES) * t_s
    temps = heat_model(op, centre, curve_times, check_every=8)(curve_times)  # (3, n)
    for c, row in zip(CURVE_TIMES, temps, strict=True):
        out[f"curve_{c:g}"] = sample_boundary(view, outer, row[outer], samples, "polar")[0]
    radius = np.linalg.norm(x[outer] - x[outer].mean(axis=0), axis=1)
    out["radius"] = sample_boundary(view, outer, radius / radius.max(), samples, "polar")[0]
    out["curve_all"] = np.concatenate([out[f"curve_{c:g}"] for c in CURVE_TIMES])
    out["sorted_1"] = np.sort(out["curve_1"])
    out["values_outer"] = histogram(temps[1, outer], VALUES)
    out["values_loops"] = histogram(temps[1, loops], VALUES)
    area = vertex_areas(x, view.faces)
    sources = farthest_points(x, SOURCES, source_vertex(view, "interior"))
    field_times = np.array(FIELD_TIMES) * t_s
    field = np.stack(
        [
            np.log10(np.clip(heat_model(op, int(s), field_times, check_every=8)(field_times), 1e-4, None))
            for s in sources
        ]
    )  # (sources, times, n)
    radii = np.linalg.norm(x[None, :, :] - x[sources][:, None, :], axis=2)
    radii /= radii.max()
    weights = np.broadcast_to(area, radii.shape).ravel()
    out["field_1"] = np.concatenate([histogram(field[0, k], LOG_T, area) for k in range(len(FIELD_TIMES))])
    out["field_many"] = np.concatenate(
        [histogram(field[:, k].ravel(), LOG_T, weights) for k in range(len(FIELD_TIMES))]
    )
    out["joint_many"] = np.concatenate(
        [
            np.histogram2d(radii.ravel(), np.clip(field[:, k].ravel(), -4.0, 2.0), JOINT, weights=weights)[0].ravel()
            for k in range(len(FIELD_TIMES))
        ]
    )
    out["radii_many"] = histogram(radii.ravel(), RADII, weights)
    return out


def object_features(args: tuple[Path, int, int, int]) -> list[dict]:
    """The features of one object's library views and every ``test_every``-th test view."""
    path, test_every, samples, triplets = args
    frame = read_table(path)[0]
    test = frame[frame["split"] == "test"]
    frame = pd.concat([frame[frame["split"] == "train"], test.iloc[::test_every]])
    rows = []
    with threadpool_limits(1):
        for view, split, repairs in zip(frame_to_views(frame), frame["split"], frame["repairs"], strict=True):
            kept = next(filter(None, map(KEPT.search, repairs)), None)
            components, share = (int(kept[1]), int(kept[2]) / int(kept[3])) if kept else (1, 1.0)
            rows.append(
                dict(
                    object=view.object_id,
                    view_id=view.view_id,
                    split=split,
                    azimuth=view.azimuth,
                    components=components,
                    vertex_share=share,
                    **features(view, samples, triplets),
                )
            )
    return rows


def distances(queries: np.ndarray, library: np.ndarray, how: str, samples: int) -> np.ndarray:
    if how == "chi2":
        return chi_square_matrix(queries / queries.sum(1, keepdims=True), library / library.sum(1, keepdims=True))
    if how == "l1":
        return np.abs(queries[:, None, :] - library[None, :, :]).sum(axis=2)
    if queries.shape[1] > samples:  # several curves of ``samples`` each: eq. 3.1 per curve, summed
        return sum(
            mhd_matrix(queries[:, k : k + samples], library[:, k : k + samples])
            for k in range(0, queries.shape[1], samples)
        )
    return mhd_matrix(queries, library)


def precision(table: pd.DataFrame, feature: str, how: str, size: int, samples: int) -> float:
    tests, library = table[table["split"] == "test"], library_subset(table, size)
    d = distances(np.stack(tests[feature].to_numpy()), np.stack(library[feature].to_numpy()), how, samples)
    return float(np.mean(library["object"].to_numpy()[d.argmin(axis=1)] == tests["object"].to_numpy()))


def plot(tables: list[str], figure: str, size: int = 8) -> None:
    """Horizontal bars: each variant's precision at ``size`` library views, one colour per table."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    frames = [pd.read_csv(t) for t in tables]
    frames = [f[f["library_size"] == size] for f in frames]
    keys = list(zip(frames[0]["step"], frames[0]["variant"], strict=True))
    labels = [f"{step}: {variant}" for step, variant in keys]
    fig, ax = plt.subplots(figsize=(11, 0.38 * len(labels) + 1.4))
    height = 0.8 / len(frames)
    for k, (table, frame) in enumerate(zip(tables, frames, strict=True)):
        values = frame.set_index(["step", "variant"])["precision"].reindex(keys)  # a variant it lacks: no bar
        ax.barh(np.arange(len(labels)) + k * height, values, height, label=Path(table).stem)
    ax.set_yticks(np.arange(len(labels)) + 0.4 - height / 2, labels, fontsize=8)
    ax.invert_yaxis()
    ax.set_xlim(0, 125)  # room for the legend right of the bars
    ax.set_xticks(range(0, 101, 20))
    ax.set_xlabel(f"object precision (%), {size} library views per object")
    ax.set_title("Where a complex object's information goes (rendered views, not real sensor data)", fontsize=10)
    ax.grid(axis="x", alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(figure, dpi=110)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", nargs="?", help="a workflow run's results folder (its views/*.parquet are read)")
    parser.add_argument("--plot", nargs="+", metavar="CSV", help="draw --figure from these tables instead")
    parser.add_argument("--figure", help="PNG to draw with --plot")
    parser.add_argument("--test-every", type=int, default=3, help="every n-th test view of each object (3: 40 of 120)")
    parser.add_argument("--sizes", type=int, nargs="+", default=[5, 8, 12, 40])
    parser.add_argument("--samples", type=int, default=SAMPLES, help="samples per PVHK curve")
    parser.add_argument("--triplets", type=int, default=20000, help="random point triplets per ESF")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", help="CSV to write")
    args = parser.parse_args()
    if args.plot:
        if not args.figure:
            parser.error("--plot needs --figure")
        plot(args.plot, args.figure)
        return
    if not args.run or not args.out:
        parser.error("give a run's results folder and --out (or --plot with --figure)")
    setup_logging()
    paths = sorted(Path(args.run, "views").glob("*.parquet"))
    if not paths:
        raise SystemExit(f"complex_ablation: no views in {args.run}/views (run its render jobs first)")
    start = time.perf_counter()
    jobs = [(path, args.test_every, args.samples, args.triplets) for path in paths]
    with Pool(args.jobs) as pool:
        table = pd.DataFrame([row for rows in pool.imap(object_features, jobs) for row in rows])
    seconds = time.perf_counter() - start
    print(f"{len(table)} views of {len(paths)} objects described in {seconds:.0f} s")
    summary = (
        f"largest component: median {table['vertex_share'].median():.1%} of the vertices kept "
        f"(least {table['vertex_share'].min():.1%}), median {table['components'].median():g} components; "
        f"all loops are {table['loops'].median():.2f}x the outer loop's vertices"
    )
    rows = [dict(step="view", variant=summary, library_size=0, precision=np.nan)]
    for step, variant, feature, how in VARIANTS:
        for size in args.sizes:
            try:
                rows.append(
                    dict(
                        step=step,
                        variant=variant,
                        distance=how,
                        library_size=size,
                        precision=round(100 * precision(table, feature, how, size, args.samples), 1),
                    )
                )
            except HeatdataError as exc:
                raise SystemExit(f"complex_ablation: {exc}") from None
        print(f"{step:9s} {variant:60s} " + " ".join(f"{r['precision']:5.1f}" for r in rows[-len(args.sizes) :]))
    pd.DataFrame(rows).assign(views=len(table), seconds=round(seconds)).to_csv(args.out, index=False)
    print(summary)


if __name__ == "__main__":
    main()
