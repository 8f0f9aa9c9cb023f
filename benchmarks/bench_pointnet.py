"""The learned kind's costs on this machine: a training step, a whole training run, describing a view.

The pointnet (default options, colour) is trained for ``--steps`` steps on 8 library views of three embedded
household objects, as :func:`heatdata.fit_spec` trains it (batches of 32 views of 1,024 points, on JAX's default
device), and then describes a view (numpy). The default 3,000 steps take ``3,000 x`` the step time; the chairs'
fits in the workflow are recorded in ``results/chairs_learned/benchmarks/fit/`` (docs/guide/learned.md).

    .venv/bin/python benchmarks/bench_pointnet.py [--steps 300]
"""

import argparse
import logging
import resource
import time

from record import write

import heatdata as hd
from heatdata.experiments.views import render_views, view_plan
from heatdata.views.view import kinect_intrinsics

OBJECTS = ["coffee-cup", "beer-mug", "plastic-cup"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=300)
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    catalog = hd.read_catalog("data/models/catalog.csv")
    views = []
    for obj in OBJECTS:
        model = hd.load_catalog_model(catalog[catalog["object"] == obj].iloc[0])
        views += render_views(model, view_plan([obj], 8, 0), intrinsics=kinect_intrinsics(0.5))
    start = time.perf_counter()
    spec = hd.fit_spec(hd.DescriptorSpec("pointnet", steps=args.steps), views)
    training = time.perf_counter() - start
    hd.describe(views[0], [spec])
    start = time.perf_counter()
    for view in views:
        hd.describe(view, [spec])
    describing = (time.perf_counter() - start) / len(views)
    memory = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**10
    figures = [
        (f"training, {args.steps} steps of 32 views x 1,024 points (compilation included)", training, "s"),
        ("a training step", 1000 * training / args.steps, "ms"),
        ("3,000 steps (the default) at that rate", 3000 * training / args.steps / 60, "min"),
        ("describing a view (numpy)", 1000 * describing, "ms"),
        ("peak memory of the process", memory, "MB"),
    ]
    for figure, value, unit in figures:
        print(f"{figure}: {value:.1f} {unit}")
    write(figures, name="bench_pointnet")


if __name__ == "__main__":
    main()
