"""Nearest-descriptor searches of ch. 6 on rendered views: what an L1 shortlist keeps of the MHD's nearest.

Alg. 6.1 (a test view's nearest library descriptor over its candidate sources) computes
the exact MHD only for the (candidate, library) pairs nearest in L1. rho of Alg. 6.3
(each library candidate's distance to the nearest candidate of another object) uses the
L1 norm itself. This measures, on three embedded household objects (8 library views x
250 candidates each, PVHK, polar, 64 samples) and 12 test views:

* for Alg. 6.1, how often the shortlist finds the same nearest library descriptor as the
  full search;
* for rho, what the full MHD search costs, and where the MHD's nearest ranks in L1 order
  (why rho is not a shortlisted MHD).

    .venv/bin/python benchmarks/bench_nearest_mhd.py [--shortlist 16 64]
"""

import argparse
import time

import numpy as np
import pandas as pd
from record import write
from scipy.spatial.distance import cdist

import heatdata as hd
from heatdata.core.distances import mhd_matrix, nearest_pair_mhd
from heatdata.experiments.describe import candidate_rows
from heatdata.experiments.views import render_views, view_plan

OBJECTS = ["coffee-cup", "beer-mug", "plastic-cup"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shortlist", type=int, nargs="+", default=[16, 64])
    args = parser.parse_args()
    catalog = hd.read_catalog("data/models/catalog.csv")
    spec = hd.DescriptorSpec(kind="pvhk", samples=64, source="center", sampling="polar")
    frames = []
    for obj in OBJECTS:
        plan = view_plan([obj], 8, 4)
        views = render_views(hd.load_catalog_model(catalog[catalog["object"] == obj].iloc[0]), plan)
        frames.append(candidate_rows(views, plan, spec, library_count=250, test_count=250))
    table = pd.concat(frames, ignore_index=True)
    table = table[table["source_rule"] == "candidates"]
    library = table[table["split"] == "train"]
    lib_values = np.stack(library["values"].to_numpy())
    tests = table[table["split"] == "test"]
    same = dict.fromkeys(args.shortlist, 0)
    tic = time.perf_counter()
    figures = []
    for _, rows in tests.groupby("view_id"):
        candidates = np.stack(rows["values"].to_numpy())
        best = nearest_pair_mhd(candidates, lib_values, shortlist=None)
        for shortlist in args.shortlist:
            same[shortlist] += nearest_pair_mhd(candidates, lib_values, shortlist=shortlist).index == best.index
    count = tests["view_id"].nunique()
    print(
        f"Alg. 6.1: {count} test views x 250 candidates against {len(lib_values)} library descriptors "
        f"({time.perf_counter() - tic:.0f} s)"
    )
    for shortlist, hits in same.items():
        print(f"  shortlist {shortlist}: the same nearest library descriptor for {hits} of {count} test views")
        figures.append((f"Alg. 6.1, L1 shortlist of {shortlist}: the MHD's nearest kept", hits / count, "share"))
    queries = np.stack(library.loc[library["object"] == OBJECTS[0], "values"].to_numpy())
    others = np.stack(library.loc[library["object"] != OBJECTS[0], "values"].to_numpy())
    tic = time.perf_counter()
    full = mhd_matrix(queries, others)
    seconds = time.perf_counter() - tic
    l1 = cdist(queries, others, "cityblock")
    rank = (l1 < l1[np.arange(len(queries)), full.argmin(axis=1)][:, None]).sum(axis=1)
    print(
        f"rho: {len(queries)} candidates of {OBJECTS[0]} against {len(others)} of the others: full MHD search "
        f"{seconds:.1f} s ({seconds / full.size * 1e6:.1f} us per pair); L1 search "
        f"{time.perf_counter() - tic - seconds:.2f} s"
    )
    print(
        f"  rank of the MHD's nearest in L1 order: median {np.median(rank):.0f}, 90th percentile "
        f"{np.percentile(rank, 90):.0f}, max {rank.max()}; within the first 64 for {np.mean(rank < 64):.0%}"
    )
    figures += [
        ("rho: full MHD search", seconds / full.size * 1e6, "us per pair"),
        ("rho: the MHD's nearest within the first 64 in L1 order", float(np.mean(rank < 64)), "share"),
    ]
    write(figures)


if __name__ == "__main__":
    main()
