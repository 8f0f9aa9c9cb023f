"""Time and memory of JASNOM (thesis ch. 7) on two halves with 2,000-vertex boundaries.

A latitude-longitude ellipsoid with 2,000 segments round its equator, cut there by a plane
(``heatdata.jasnom.cuts.split_model``), one half moved by a rigid motion, then ``stitch``
with the default 128 boundary samples (256 coarse candidates, then refinement of the best
few over six degrees of freedom). Prints the time of the boundary extraction, of the
search and of the whole call, the poses evaluated, the errors against the truth, and
the peak RSS.

    .venv/bin/python benchmarks/bench_stitch.py [--segments 2000]
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np
from record import write
from scipy.spatial.transform import Rotation

from heatdata.io.models import Model, transformed
from heatdata.jasnom.boundary import boundary
from heatdata.jasnom.cuts import split_model
from heatdata.jasnom.seam import stitch


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--segments", type=int, default=2000)
    parser.add_argument("--rings", type=int, default=32)
    parser.add_argument("--samples", type=int, default=128)
    args = parser.parse_args()
    theta = np.pi * np.arange(1, args.rings) / args.rings  # latitudes; an even count puts one on the equator
    phi = 2 * np.pi * np.arange(args.segments) / args.segments
    ring = np.column_stack(
        [
            np.outer(np.sin(theta), np.cos(phi)).ravel(),
            np.outer(np.sin(theta), np.sin(phi)).ravel(),
            np.repeat(np.cos(theta), args.segments),
        ]
    )
    vertices = np.vstack([[0.0, 0.0, 1.0], ring, [0.0, 0.0, -1.0]]) * [0.1, 0.08, 0.06]
    s, last = args.segments, len(theta) - 1
    j = np.arange(s)
    faces = [np.column_stack([np.zeros(s, int), 1 + j, 1 + (j + 1) % s])]
    for i in range(last):
        a, b = 1 + i * s + j, 1 + i * s + (j + 1) % s
        faces += [np.column_stack([a, a + s, b]), np.column_stack([b, a + s, b + s])]
    faces.append(np.column_stack([np.full(s, len(vertices) - 1), 1 + last * s + (j + 1) % s, 1 + last * s + j]))
    faces = np.vstack(faces).astype(np.int64)
    model = Model.untextured("ellipsoid", vertices, faces, (0.5, 0.5, 0.5))
    a, b = split_model(model, [0.0, 0.0, 1.0])
    motion = Rotation.from_rotvec([0.4, -0.9, 0.2])
    b = transformed(b, motion.as_matrix(), [0.2, 0.1, -0.1])
    start = time.perf_counter()
    first, second = boundary(a), boundary(b)
    boundaries = time.perf_counter() - start
    start = time.perf_counter()
    result = stitch(a, b, samples=args.samples)
    total = time.perf_counter() - start
    found = result.alignment
    print(
        f"halves of {len(a.vertices)} and {len(b.vertices)} vertices, boundaries of {len(first.loop)} and "
        f"{len(second.loop)} vertices, {args.samples} samples"
    )
    print(f"boundaries and their normals: {boundaries:.2f} s (both)")
    print(
        f"search (align): {found.seconds:.2f} s, {found.candidates} poses evaluated; rotation error "
        f"{Rotation.from_matrix(found.rotation @ motion.as_matrix()).magnitude():.2e} rad"
    )
    print(f"stitch, in all: {total:.2f} s")
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"peak RSS {peak:.0f} MB")
    write(
        [
            ("boundaries and their normals (both)", boundaries, "s"),
            ("search (align)", found.seconds, "s"),
            ("stitch, in all", total, "s"),
            ("rotation error", Rotation.from_matrix(found.rotation @ motion.as_matrix()).magnitude(), "rad"),
            ("peak RSS", peak, "MB"),
        ]
    )


if __name__ == "__main__":
    main()
