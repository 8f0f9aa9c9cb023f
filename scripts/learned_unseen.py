"""Objects a learned kind was not trained on: added to its library without retraining, or met as unknown objects.

    .venv/bin/python scripts/learned_unseen.py results/chairs_learned --held-out 10 \\
        --config config/experiments/chairs.yaml config/experiments/chairs_learned.yaml \\
        --out docs/results/chairs_learned_unseen.csv

A descriptor kind adds an object by describing its library views: rows, nothing else changes. A learned kind's
network knows only the objects it was trained on. Here the pointnet is trained on the library views of every
object but ``--held-out`` of them (evenly spread over the sorted names), as the workflow trains it, and then:

- **newcomers**: the held-out objects' library views are described by that network and added as rows, without
  retraining; the run's test views of every object are recognized against the whole library (``precision``), and
  those of the newcomers alone (``precision_newcomers``);
- **open set**: the held-out objects are left out of the library; their test views should be answered unknown
  by the library's calibrated confidence (:func:`heatdata.recognition.open_set.open_set_scores`, one fold), its
  threshold set from the library's own unknown answers and, beside it, from its own known answers (a learned
  kind's default; :func:`heatdata.recognition.open_set.threshold_sides`).

The run's descriptor kinds are measured on the same fold from its table (their rows do not depend on which objects
a library holds; their specs come from the run's ``--config`` files). ``add_seconds`` is what adding one object
costs each kind without retraining: describing the first newcomer's library views, one process, warm; retraining
the learned kind costs its training time beside it (``train_seconds``, and the peak memory of this process).
Rendered views, not real sensor data.
"""

from __future__ import annotations

import argparse
import resource
import time
from pathlib import Path

import pandas as pd
import yaml

from heatdata.descriptors import DescriptorSpec, describe
from heatdata.experiments.config import descriptor_specs
from heatdata.experiments.describe import describe_library_and_tests, fit_view_tables
from heatdata.io.tables import read_table
from heatdata.log import setup_logging
from heatdata.recognition.evaluate import classify, library_subset, own_time_scale
from heatdata.recognition.open_set import threshold_sides
from heatdata.views.frames import frame_to_views


def held_out_objects(objects: list[str], count: int) -> list[str]:
    """``count`` of the sorted ``objects``, evenly spread (every len/count-th)."""
    names = sorted(objects)
    return [names[int(k * len(names) / count)] for k in range(count)]


def measured(table: pd.DataFrame, descriptor: str, size: int, unseen: list[str]) -> dict:
    """Closed-set precision over every test view and the newcomers', and the open-set summary of the ``unseen``
    fold, for one descriptor's rows at ``size`` library views per object."""
    rows = own_time_scale(table[table["descriptor"] == descriptor])
    library = library_subset(rows[rows["split"] == "train"], size)
    tests = rows[rows["split"] == "test"]
    answers = classify(pd.concat([library, tests], ignore_index=True), descriptor)
    newcomers = answers["object"].isin(unseen)
    return {
        "precision": float(answers["correct"].mean()),
        "precision_newcomers": float(answers.loc[newcomers, "correct"].mean()),
        **threshold_sides(library, tests, rows["kind"].iloc[0], folds=[unseen]),
    }


def describe_seconds(views: list, spec: DescriptorSpec) -> float:
    """Seconds to describe ``views`` with ``spec`` (after one view, so that imports and compilation are not counted)."""
    describe(views[0], [spec])
    start = time.perf_counter()
    for view in views:
        describe(view, [spec])
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", type=Path, help="a run's results folder (views/, descriptors.parquet)")
    parser.add_argument("--held-out", type=int, default=10, help="objects the network is not trained on (10)")
    parser.add_argument("--size", type=int, default=8, help="library views per object (8)")
    parser.add_argument("--color", nargs="+", default=["rgb", "none"], help="the pointnets' colour options")
    parser.add_argument("--steps", type=int, help="training steps (default the kind's)")
    parser.add_argument("--config", type=Path, nargs="+", required=True, help="the run's config files, in order")
    parser.add_argument("--out", type=Path, required=True, help="the table to write (.csv)")
    args = parser.parse_args()
    setup_logging()
    table, _ = read_table(args.run / "descriptors.parquet")
    frames = [read_table(path)[0] for path in sorted((args.run / "views").glob("*.parquet"))]
    unseen = held_out_objects([f["object"].iloc[0] for f in frames], args.held_out)
    print(f"{len(frames)} objects, {len(unseen)} held out: {', '.join(unseen)}")
    config: dict = {}
    for path in args.config:
        config.update(yaml.safe_load(path.read_text()))
    newcomer = next(f for f in frames if f["object"].iloc[0] == unseen[0])
    newcomer = frame_to_views(library_subset(newcomer[newcomer["split"] == "train"], args.size))
    out = []
    for spec in descriptor_specs(config):
        if spec.impl.learned or spec.name not in set(table["descriptor"]):
            continue
        out.append(
            {
                "descriptor": spec.name,
                "trained_on": "",
                **measured(table, spec.name, args.size, unseen),
                "add_seconds": round(describe_seconds(newcomer, spec), 2),
                "train_seconds": float("nan"),
            }
        )
        print(out[-1])
    for color in args.color:
        options = {"color": color, "train_views": args.size} | ({"steps": args.steps} if args.steps else {})
        spec = DescriptorSpec("pointnet", **options)
        start = time.perf_counter()
        spec = fit_view_tables([f for f in frames if f["object"].iloc[0] not in unseen], spec)
        trained = time.perf_counter() - start
        described = describe_library_and_tests(frames, spec, args.size)
        out.append(
            {
                "descriptor": spec.name,
                "trained_on": f"{len(frames) - len(unseen)} objects",
                **measured(described, spec.name, args.size, unseen),
                "add_seconds": round(describe_seconds(newcomer, spec), 2),
                "train_seconds": round(trained, 1),
            }
        )
        print(out[-1])
    memory = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    frame = pd.DataFrame(out).assign(peak_gb=round(memory, 2), held_out=len(unseen))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    frame.round(4).to_csv(args.out, index=False)
    print(frame.to_string(index=False))
    print(f"peak memory {memory:.2f} GB")


if __name__ == "__main__":
    main()
