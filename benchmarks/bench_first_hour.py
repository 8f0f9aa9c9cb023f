"""The times a new user meets in the first hour, as the README and the guide state them: the main job on the
embedded objects with its report, the smoke run, the library guide's tour and the README's example.

    .venv/bin/python benchmarks/bench_first_hour.py            # a quiet machine
    .venv/bin/python benchmarks/bench_first_hour.py --busy 2   # beside two CPU-bound processes (a shared machine)

Each run goes to a fresh results folder under a temporary directory (nothing of ``results/`` is reused; the main
job's goes to ``--results`` when given, which must not exist), from the repository's working tree with its
``.venv``. The peak memory is the largest of any one job's (the workflow runs
one process per job). ``--busy N`` keeps N processes spinning on the CPU for the whole measurement, as another
user's job would; the figures are recorded as ``bench_first_hour_busy``. The setup (``scripts/setup.sh``: pip's
downloads, a few minutes the first time) is not timed here: it depends on the network.
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from record import write

ROOT = Path(__file__).resolve().parents[1]
SNAKEMAKE = str(Path(sys.executable).parent / "snakemake")


def _spin() -> None:
    while True:
        pass


def timed(command: list[str], cwd: Path) -> float:
    """Wall seconds of ``command``, which must succeed."""
    start = time.perf_counter()
    done = subprocess.run(command, cwd=cwd, capture_output=True, text=True, check=False,
                          env=dict(os.environ, MPLBACKEND="Agg"))  # fmt: skip
    if done.returncode:
        raise SystemExit(f"{' '.join(command)} failed:\n{(done.stdout + done.stderr)[-3000:]}")
    return time.perf_counter() - start


def python_block(path: Path, after: str) -> str:
    """The first ```python block of ``path`` after the heading ``after`` (as tests/test_readme.py reads it)."""
    text = path.read_text()
    return re.search(r"```python\n(.*?)```", text[text.index(after) :], re.S).group(1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--busy", type=int, default=0, help="CPU-bound processes beside the measurement")
    parser.add_argument("--results", type=Path, help="the main job's results folder, kept (default: a temporary one)")
    args = parser.parse_args()
    if args.results is not None and args.results.exists():
        parser.error(f"{args.results} exists: the main job is timed from fresh results")
    spinners = [multiprocessing.Process(target=_spin, daemon=True) for _ in range(args.busy)]
    for spinner in spinners:
        spinner.start()
    figures = []
    try:
        with tempfile.TemporaryDirectory() as folder:
            work = Path(folder)
            main_results = args.results or work / "main"  # relative to the repository, where snakemake runs
            seconds = timed([SNAKEMAKE, "--cores", "2", "--config", f"results={main_results}"], ROOT)
            figures.append(("the main job (snakemake --cores 2), fresh results", seconds, "s"))
            report = timed([SNAKEMAKE, "--cores", "2", "--config", f"results={main_results}", "--report",
                            str(main_results / "report.html")], ROOT)  # fmt: skip
            figures.append(("its report (snakemake --report)", report, "s"))
            figures.append(("the quick start's run: the main job and its report", seconds + report, "s"))
            peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
            figures.append(("the largest job's peak memory", peak, "MB"))
            smoke = timed([SNAKEMAKE, "--cores", "2", "--configfile", "config/experiments/smoke.yaml", "--config",
                           f"results={work / 'smoke'}"], ROOT)  # fmt: skip
            figures.append(("the smoke run (config/experiments/smoke.yaml)", smoke, "s"))
            tour = work / "tour.py"
            tour.write_text(python_block(ROOT / "docs/guide/library.md", "# A tour of the library"))
            figures.append(("the library guide's tour (python, a fresh process)", timed([sys.executable, str(tour)],
                                                                                    ROOT), "s"))  # fmt: skip
    finally:
        for spinner in spinners:
            spinner.terminate()
    for figure, value, unit in figures:
        print(f"{figure}: {value:.1f} {unit}")
    write(figures, name="bench_first_hour_busy" if args.busy else None)


if __name__ == "__main__":
    main()
