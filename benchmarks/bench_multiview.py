"""Time of one particle-filter step (Alg. 4.1) and of one active-policy choice, on a synthetic library.

8 objects x 13 library views x 2 descriptors per view (64 samples, PVHK kind: the MHD of
eq. 3.1), a similarity learned from an independent set of the same size, 100 particles,
two observations per stop. The step includes the appearance model's distances from the
stop's observations to every library descriptor, the propagation, the update and the
bootstrap; best of ``--repeat`` on one thread. Beside it, one step of the exhaustive filter
(every object at every degree) and one active-policy choice. Peak RSS at the end.

    .venv/bin/python benchmarks/bench_multiview.py [--objects 8] [--views 13] [--particles 100] [--repeat 50]
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np
import pandas as pd
from record import write
from threadpoolctl import threadpool_limits

from heatdata.recognition.multiview.appearance import learn_similarity
from heatdata.recognition.multiview.filters import ExhaustiveFilter, ParticleFilter


def synthetic(objects: int, views: int, seed: int) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    shapes = np.cumsum(np.random.default_rng(0).normal(0, 0.05, (objects, 64)), axis=1)
    angles = np.arange(views) * 360.0 / views
    return pd.DataFrame(
        [
            {
                "object": f"object-{o}",
                "azimuth": a,
                "kind": "pvhk",
                "values": 1 + shapes[o] + 0.05 * np.cos(np.radians(a)) + rng.normal(0, 0.01, 64),
            }
            for o in range(objects)
            for a in angles
            for _ in range(2)
        ]
    )


def best(function, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times) * 1e3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=8)
    parser.add_argument("--views", type=int, default=13)
    parser.add_argument("--particles", type=int, default=100)
    parser.add_argument("--repeat", type=int, default=50)
    args = parser.parse_args()
    library = synthetic(args.objects, args.views, 1)
    similarity = learn_similarity(library, synthetic(args.objects, args.views, 2))
    observations = list(synthetic(args.objects, args.views, 3)["values"][:2])
    with threadpool_limits(1):
        f = ParticleFilter(library, similarity, particles=args.particles, seed=0)
        step = best(lambda: f.step(observations, 360.0 / args.views), args.repeat)
        move = best(lambda: f.best_move((-90, -45, -15, 15, 45, 90)), args.repeat)
        exact = ExhaustiveFilter(f.model)
        exhaustive = best(lambda: exact.step(observations, 360.0 / args.views), args.repeat)
    print(
        f"{args.objects} objects x {args.views} views x 2 descriptors, {args.particles} particles, one thread, "
        f"best of {args.repeat}"
    )
    print(f"filter step (2 observations): {step:.2f} ms")
    print(f"best_move over 6 candidate steps: {move:.2f} ms")
    print(f"exhaustive filter step ({len(exact.object)} hypotheses, 1 deg apart): {exhaustive:.2f} ms")
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"peak RSS {peak:.0f} MB")
    write(
        [
            (f"particle filter step, {args.particles} particles, 2 observations", step, "ms"),
            ("best_move over 6 candidate steps", move, "ms"),
            (f"exhaustive filter step, {len(exact.object)} hypotheses", exhaustive, "ms"),
            ("peak RSS", peak, "MB"),
        ]
    )


if __name__ == "__main__":
    main()
