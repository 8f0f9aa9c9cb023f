"""How long Snakemake takes to plan the default run over a large catalogue: `snakemake -n` on synthetic catalogues.

A catalogue of N objects is the embedded one's 14 rows repeated under new names (`plastic-cup-00014`, ...), each
pointing at the same model files (linked into a temporary folder beside the catalogue), so the DAG is that of N real
objects while nothing is rendered. Each size is planned once in a fresh process, with the default config
(`config/config.yaml`: 4 library sizes, 7 descriptors, 6 scenes), and timed from outside; the peak memory is the
planning process's.

    .venv/bin/python benchmarks/bench_dag.py --objects 1000 10000
"""

from __future__ import annotations

import argparse
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd
from record import write

ROOT = Path(__file__).resolve().parents[1]


def synthetic_catalog(folder: Path, objects: int) -> Path:
    """A catalogue of ``objects`` rows in ``folder``: the embedded rows again and again under numbered names."""
    embedded = pd.read_csv(ROOT / "data/models/catalog.csv", keep_default_na=False)
    for model in {Path(file).parts[0] for file in embedded["file"]}:
        (folder / model).symlink_to(ROOT / "data/models" / model)
    rows = embedded.iloc[[k % len(embedded) for k in range(objects)]].copy()
    rows["object"] = [f"{name}-{k:05d}" for k, name in enumerate(rows["object"])]
    path = folder / "catalog.csv"
    rows.to_csv(path, index=False)
    return path


def plan(objects: int) -> tuple[float, int, float]:
    """Seconds to plan, the number of jobs and the planner's peak memory (MB) for ``objects`` objects."""
    with tempfile.TemporaryDirectory() as folder:
        catalog = synthetic_catalog(Path(folder), objects)
        command = [
            *(sys.executable, "-m", "snakemake", "-n", "--quiet", "rules", "--cores", "2"),
            *("--configfile", "config/config.yaml"),
            *("--config", f"catalog={catalog}", f"results={folder}/results"),
        ]
        start = time.perf_counter()
        done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
        seconds = time.perf_counter() - start
    if done.returncode:
        raise SystemExit(f"snakemake -n failed on {objects} objects:\n{done.stdout[-2000:]}{done.stderr[-2000:]}")
    jobs = int(re.search(r"^total\s+(\d+)", done.stdout, re.MULTILINE).group(1))
    memory = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 2**10
    return seconds, jobs, memory


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, nargs="+", default=[1000, 10000], help="catalogue sizes (1000 10000)")
    args = parser.parse_args()
    figures = []
    for objects in args.objects:
        seconds, jobs, memory = plan(objects)
        print(f"{objects} objects: {jobs} jobs planned in {seconds:.1f} s, peak {memory:.0f} MB (so far)")
        figures += [
            (f"snakemake -n, {objects:,} objects: wall time", seconds, "s"),
            (f"snakemake -n, {objects:,} objects: jobs", jobs, "jobs"),
            (f"snakemake -n, {objects:,} objects: peak memory of the planners so far", memory, "MB"),
        ]
    write(figures, name="bench_dag")


if __name__ == "__main__":
    main()
