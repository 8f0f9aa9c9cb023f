"""Time of the compact-library LP (Alg. 6.3, select_sources) on real costs, against the DP, case by case.

Builds the candidate descriptors of a compact config's objects as the workflow does (Sweet Home 3D models,
the config's views, ``compact.library_candidates`` sources per library view; test views are not needed)
and selects the sources of every (object, library size, alpha) with the LP and with the DP
(``heatdata.recognition.compact.cyclic_dp``), each in a child process with a time limit, and compares the optima.
Needs Debian's sweethome3d-furniture.

    .venv/bin/python benchmarks/bench_compact_lp.py config/experiments/compact_chairs.yaml [--timeout 600]
"""

import argparse
import logging
import multiprocessing
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
import yaml
from record import write
from threadpoolctl import threadpool_limits

from heatdata.descriptors import DescriptorSpec
from heatdata.experiments.describe import candidate_view_table
from heatdata.experiments.views import render_object_views
from heatdata.io.sh3f import extract_sh3f_model, sh3f_catalogs
from heatdata.recognition.compact import (
    combined_costs,
    consecutive_costs,
    cyclic_dp,
    other_object_distances,
    select_sources,
)
from heatdata.recognition.evaluate import library_subset

log = logging.getLogger("bench_compact_lp")


def candidate_table(config: dict, folder: Path) -> pd.DataFrame:
    """Library-view candidate rows of every object of ``config`` (a compact config over config/config.yaml)."""
    sh3f = config["sh3f"]
    catalog = sh3f_catalogs(
        sh3f["files"], name_pattern=sh3f.get("names"), label=sh3f.get("label"), exclude_pattern=sh3f.get("exclude")
    )
    if config.get("objects"):
        catalog = catalog[catalog["object"].isin(config["objects"])]
    views = {**config["views"], "test": 0}
    compact = config["compact"]
    tables = []
    for row in catalog.to_dict("records"):
        tic = time.perf_counter()
        row["path"] = str(extract_sh3f_model(row["archive"], row["file"], folder))
        frame = render_object_views(row, views)
        tables.append(
            candidate_view_table(
                frame,
                DescriptorSpec.from_dict(compact["descriptor"]),
                library_count=compact["library_candidates"],
                test_count=0,
            )
        )
        log.info("%s: %d views, candidates in %.1f s", row["object"], len(frame), time.perf_counter() - tic)
    return pd.concat(tables, ignore_index=True)


def problems(table: pd.DataFrame, sizes: list[int], alphas: list[float]):
    """(object, size, alpha, edge costs) as :func:`heatdata.experiments.compact.compact_libraries` builds them."""
    multi = table[table["source_rule"] == "candidates"]
    for size in sizes:
        subset = library_subset(multi, size)
        stacked = {
            obj: [np.stack(g["values"].to_numpy()) for _, g in rows.groupby("azimuth", sort=True)]
            for obj, rows in subset.groupby("object")
        }
        rho = other_object_distances(stacked)
        for obj, views in stacked.items():
            consecutive = consecutive_costs(views)
            for alpha in alphas:
                yield obj, size, alpha, consecutive if alpha == 1.0 else combined_costs(consecutive, rho[obj], alpha)


def warm_up() -> None:
    """Import cvxpy and load the compiled kernels before the children fork, so that no solve pays for them."""
    rng = np.random.default_rng(0)
    select_sources([rng.random((3, 3)) for _ in range(3)], name="warm-up")


def _timed(solver, costs, queue) -> None:
    with threadpool_limits(1):
        tic = time.perf_counter()
        _, cost = solver(costs)
        queue.put((time.perf_counter() - tic, cost))


def run(solver, costs, timeout: float) -> tuple[float, float]:
    """(seconds, optimum) of ``solver`` in a child process; (nan, nan) once it runs past ``timeout``."""
    queue = multiprocessing.get_context("fork").Queue()
    child = multiprocessing.get_context("fork").Process(target=_timed, args=(solver, costs, queue))
    child.start()
    child.join(timeout)
    if child.is_alive():
        child.kill()
        child.join()
        return np.nan, np.nan
    return queue.get()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("config", help="a compact config, e.g. config/experiments/compact_chairs.yaml")
    parser.add_argument("--timeout", type=float, default=600.0, help="seconds per solve before it is stopped")
    parser.add_argument("--sizes", type=int, nargs="+", help="library sizes (default: the config's)")
    args = parser.parse_args()
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    logging.getLogger("heatdata").setLevel(logging.ERROR)  # each view's repairs and sampling notes
    defaults = yaml.safe_load(Path("config/config.yaml").read_text())
    config = {**defaults, **yaml.safe_load(Path(args.config).read_text())}
    with tempfile.TemporaryDirectory() as folder:
        table = candidate_table(config, Path(folder))
    sizes = args.sizes or config["library_sizes"]
    warm_up()
    print(
        f"{args.config}: {table['object'].nunique()} objects, {config['compact']['library_candidates']} "
        f"candidates per view; LP and DP, one thread, limit {args.timeout:.0f} s a solve"
    )
    print(f"{'object':<44} {'size':>4} {'alpha':>5} {'LP s':>8} {'DP s':>7} {'difference':>10}")
    worst, count = 0.0, 0
    for obj, size, alpha, costs in problems(table, sizes, config["compact"]["alphas"]):
        lp_seconds, lp = run(lambda c, name=obj: select_sources(c, name=name), costs, args.timeout)
        dp_seconds, dp = run(cyclic_dp, costs, args.timeout)
        lp_text = f"{lp_seconds:8.2f}" if np.isfinite(lp_seconds) else f"{'>' + format(args.timeout, '.0f'):>8}"
        difference = abs(lp - dp) / max(1.0, abs(dp))
        print(f"{obj:<44} {size:>4} {alpha:>5g} {lp_text} {dp_seconds:7.2f} {difference:10.1e}", flush=True)
        worst = max(worst, lp_seconds if np.isfinite(lp_seconds) else np.inf)
        count += difference < 1e-9
    print(f"slowest LP: {worst:.2f} s")
    write(
        [(f"{args.config}: slowest LP", worst, "s"), ("selections whose LP optimum equals the DP's", count, "count")],
        name=f"bench_compact_lp_{Path(args.config).stem}",
    )


if __name__ == "__main__":
    main()
