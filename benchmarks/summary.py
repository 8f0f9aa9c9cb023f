"""Write the benchmarks' recorded figures (``benchmarks/results/*.csv``) into ``benchmarks/README.md``.

The section between the README's ``<!-- recorded:start -->`` and ``<!-- recorded:end -->`` lines is made by this
script, so it always says what the CSV files say; ``tests/test_benchmarks.py`` checks that it does.

    .venv/bin/python benchmarks/summary.py
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

HERE = Path(__file__).resolve().parent
README = HERE / "README.md"
START, END = "<!-- recorded:start -->", "<!-- recorded:end -->"


def command(name: str) -> str:
    """The command that writes ``results/<name>.csv``."""
    if name.startswith("bench_compact_lp_"):
        return f".venv/bin/python benchmarks/bench_compact_lp.py config/experiments/{name[17:]}.yaml"
    if name == "bench_recognize":
        return ".venv/bin/python benchmarks/bench_recognize.py results/chairs_library"
    if name == "bench_recognize_view":
        return ".venv/bin/python benchmarks/bench_recognize_view.py results/hgd_budget"
    if name == "bench_first_hour_busy":
        return ".venv/bin/python benchmarks/bench_first_hour.py --busy 2"
    if name == "bench_classify":
        return ".venv/bin/python benchmarks/bench_classify.py results/descriptors.parquet"
    return f".venv/bin/python benchmarks/{name}.py"


def section() -> str:
    """The README's recorded section, from every CSV of ``benchmarks/results``."""
    parts = [
        START,
        "## Recorded figures (made by `benchmarks/summary.py` from `benchmarks/results/*.csv`)",
        "",
        "Each script writes its figures to `benchmarks/results/<script>.csv` (figure, value, unit, machine, commit,",
        "date); diff two of them to see a regression. The sections after this one keep the history and the reasons.",
    ]
    for path in sorted((HERE / "results").glob("*.csv")):
        table = pd.read_csv(path, dtype={"value": float})
        first = table.iloc[0]
        parts += [
            "",
            f"### `{path.stem}`",
            "",
            f"`{command(path.stem)}`: {first['date']}, commit {first['commit']}, {first['machine']}",
            "",
            "| figure | value | unit |",
            "|---|---|---|",
            *(f"| {row.figure} | {row.value:.4g} | {row.unit} |" for row in table.itertuples()),
        ]
    return "\n".join([*parts, END])


def updated(text: str) -> str:
    """``text`` (the README) with its recorded section made anew (added after the title if it has none)."""
    if START in text:
        before, rest = text.split(START, 1)
        return before + section() + rest.split(END, 1)[1]
    title, rest = text.split("\n", 1)
    return f"{title}\n\n{section()}\n{rest}"


if __name__ == "__main__":
    README.write_text(updated(README.read_text()))
    print(f"{README.relative_to(HERE.parent)}: the recorded section written from {HERE.name}/results")
