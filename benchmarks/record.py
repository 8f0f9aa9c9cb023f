"""The benchmarks' numbers as tables: each script writes ``benchmarks/results/<script>.csv`` (figure, value, unit,
machine, commit, date), so that two runs can be diffed; ``benchmarks/summary.py`` writes them into the README."""

from __future__ import annotations

import datetime
import sys
from pathlib import Path

import pandas as pd

from heatdata.experiments.publish import commit, machine

RESULTS = Path(__file__).resolve().parent / "results"
COLUMNS = ["figure", "value", "unit", "machine", "commit", "date"]


def write(figures: list[tuple[str, float, str]], name: str | None = None) -> Path:
    """Write a benchmark's ``(figure, value, unit)`` rows, named after the running script unless ``name`` is given."""
    name = name or Path(sys.argv[0]).stem
    RESULTS.mkdir(exist_ok=True)
    table = pd.DataFrame(figures, columns=["figure", "value", "unit"]).assign(
        machine=machine(),
        commit=commit(RESULTS.parents[1], exclude=("benchmarks/results",)),
        date=datetime.date.today().isoformat(),
    )
    path = RESULTS / f"{name}.csv"
    table[COLUMNS].to_csv(path, index=False, float_format="%.6g")
    print(f"recorded: {path.relative_to(RESULTS.parents[1])}")
    return path
