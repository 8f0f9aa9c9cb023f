"""Every documented workflow run, dry-run as documented and then run small through to its report page
(:mod:`heatdata.experiments.documented_runs`): CI runs this after the tests.

    .venv/bin/python scripts/documented_runs.py                      # all of them, into results/documented_runs/
    .venv/bin/python scripts/documented_runs.py --only chairs smoke  # some, by name
    .venv/bin/python scripts/documented_runs.py --list               # their names and config files

Each run's small results go to ``<out>/<name>/`` (its report is ``report.html`` there); ``<out>/runs.csv`` is
the table of every run's times. Exits 1 when any run fails, after trying the others.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import time
from pathlib import Path

import pandas as pd

from heatdata.experiments.documented_runs import ROOT, documented_runs, run_small


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", nargs="+", metavar="NAME", help="run only these (names as --list prints them)")
    parser.add_argument("--list", action="store_true", help="print the documented runs and stop")
    parser.add_argument("--out", type=Path, default=ROOT / "results" / "documented_runs", help="results folder")
    parser.add_argument("--keep", action="store_true", help="keep each run's small results (default: report only)")
    args = parser.parse_args(argv)

    runs = documented_runs()
    if args.list:
        for run in runs:
            print(f"{run.name:<70} {' '.join(run.configs)}  ({run.where})")
        return 0
    if args.only:
        unknown = sorted(set(args.only) - {r.name for r in runs})
        if unknown:
            parser.error(f"no documented run {', '.join(unknown)} (--list names them)")
        runs = [r for r in runs if r.name in args.only]
    args.out.mkdir(parents=True, exist_ok=True)
    rows, start = [], time.perf_counter()
    for number, run in enumerate(runs, 1):
        out = (args.out / run.name).resolve()
        shutil.rmtree(out, ignore_errors=True)
        outcome = run_small(run, out)
        seconds = [s for s in (outcome.dry_seconds, outcome.run_seconds, outcome.report_seconds) if s is not None]
        print(f"[{number}/{len(runs)}] {run.name}: {'ok' if outcome.ok else 'FAILED'} in {sum(seconds):.0f} s"
              f" ({outcome.jobs or 0} jobs; {time.perf_counter() - start:.0f} s so far)", flush=True)  # fmt: skip
        if not outcome.ok:
            print(f"    {' '.join(run.configs)}\n    " + outcome.error.replace("\n", "\n    "), flush=True)
        if outcome.ok and not args.keep:  # the report page holds the run; its tables and views are not needed
            for child in out.iterdir():
                if child.name not in ("report.html", "summary.md"):
                    shutil.rmtree(child) if child.is_dir() else child.unlink()
        rows.append({
            "run": run.name, "configs": " ".join(run.configs), "documented": run.where, "ok": outcome.ok,
            "dry_run_s": outcome.dry_seconds, "small_run_s": outcome.run_seconds, "report_s": outcome.report_seconds,
            "jobs": outcome.jobs, "error": outcome.error.splitlines()[-1] if outcome.error else "",
        })  # fmt: skip
    table = pd.DataFrame(rows)
    table.to_csv(args.out / "runs.csv", index=False, float_format="%.1f")
    failed = table[~table["ok"]]
    print(f"{len(table) - len(failed)} of {len(table)} documented runs ran small through to their report in "
          f"{time.perf_counter() - start:.0f} s; the times: {args.out / 'runs.csv'}")  # fmt: skip
    return 1 if len(failed) else 0


if __name__ == "__main__":
    sys.exit(main())
