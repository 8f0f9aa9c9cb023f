"""Time and memory of HBRD (thesis Alg. 8.1) on one rendered rump, against an exact dense heat.

The average young male MakeHuman body seen from behind at 1.2 m by the full-resolution
virtual Kinect (``heatdata.experiments.rump.rendered_rumps``), the rump kept within 1.5 times the
bones' box. Times ``rump_heat`` (both surfaces' heat from enough eigenpairs for 1e-8 at
the first time, eq. 5.2), then the same two heats from the dense Laplacian's whole spectrum,
and prints the largest difference of the descriptor and the peak RSS.

    .venv/bin/python benchmarks/bench_hbrd.py [--image-scale 1.0] [--extent 1.5]
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np
import scipy.linalg
from record import write

from heatdata.core.mesh import mesh_edges
from heatdata.core.spectrum import laplacian
from heatdata.experiments.rump import rendered_rumps
from heatdata.io.bodies import population
from heatdata.rump import rump_heat
from heatdata.views.view import kinect_intrinsics


def reference_heat(vertices: np.ndarray, edges: np.ndarray, source: int, times: np.ndarray) -> np.ndarray:
    """(K, n) temperatures after a unit pulse at ``source``, equilibrium 1, from the whole spectrum of the dense
    Laplacian (``scipy.linalg.eigh``): exact at every time. (``expm_multiply`` costs t ||L||: on this rump,
    ||L||_1 ~ 3e6 from its 2 mm edges, stepping through the 32 times ran over 20 min and was stopped.)"""
    values, vectors = scipy.linalg.eigh(laplacian(vertices, edges).toarray())
    return (np.exp(-np.outer(times, values)) * vectors[source]) @ vectors.T * len(vertices)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--image-scale", type=float, default=1.0)
    parser.add_argument("--extent", type=float, default=1.5)
    args = parser.parse_args()
    ((view, landmarks),) = rendered_rumps(population(1), noise=True, intrinsics=kinect_intrinsics(args.image_scale))
    start = time.perf_counter()
    heat = rump_heat(view.vertices, view.faces, landmarks, extent=args.extent)
    ours = time.perf_counter() - start
    edges = mesh_edges(heat.faces, len(heat.vertices))
    planar = heat.vertices * [1.0, 1.0, 0.0]
    start = time.perf_counter()
    difference = reference_heat(heat.vertices, edges, heat.center, heat.times) - reference_heat(
        planar, edges, heat.center, heat.times
    )
    reference = time.perf_counter() - start
    descriptor = difference[:, heat.path].max(axis=1)
    print(f"view: {view.n_vertices} vertices; rump: {len(heat.vertices)} vertices, {len(heat.times)} times")
    print(f"rump_heat (eigenpairs, both surfaces, whole Alg. 8.1): {ours:.2f} s")
    print(f"dense eigh heat of both surfaces (exact reference):    {reference:.2f} s")
    print(
        f"largest descriptor difference: {np.abs(descriptor - heat.descriptor).max():.2e} "
        f"(descriptor range {np.ptp(heat.descriptor):.3g})"
    )
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"peak RSS: {peak:.0f} MB")
    write(
        [
            (f"rump_heat, whole Alg. 8.1 ({len(heat.vertices)}-vertex rump)", ours, "s"),
            ("dense eigh reference", reference, "s"),
            ("largest descriptor difference", float(np.abs(descriptor - heat.descriptor).max()), "temperature"),
            ("peak RSS", peak, "MB"),
        ]
    )


if __name__ == "__main__":
    main()
