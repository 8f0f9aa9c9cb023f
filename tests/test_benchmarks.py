"""The benchmarks record their figures as CSV, and the README's recorded section says what those files say."""

import ast
import sys

import pandas as pd
from conftest import ROOT

sys.path.insert(0, str(ROOT / "benchmarks"))
import record  # noqa: E402
import summary  # noqa: E402

SCRIPTS = sorted((ROOT / "benchmarks").glob("bench_*.py"))


def test_every_benchmark_writes_its_figures():
    for script in SCRIPTS:
        calls = [
            node
            for node in ast.walk(ast.parse(script.read_text()))
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "write"
        ]
        assert calls, f"{script.name} records nothing in benchmarks/results"


def test_every_recorded_file_has_the_columns_and_a_script():
    recorded = sorted((ROOT / "benchmarks/results").glob("*.csv"))
    assert recorded
    for path in recorded:
        table = pd.read_csv(path)
        assert list(table.columns) == record.COLUMNS, path.name
        assert len(table) and table["value"].notna().all(), path.name
        script = summary.command(path.stem).split()[1]
        assert (ROOT / script).is_file(), path.name


def test_the_readme_recorded_section_is_made_from_the_files():
    text = summary.README.read_text()
    assert summary.updated(text) == text, "run .venv/bin/python benchmarks/summary.py"


def test_write_records_the_machine_commit_and_date(tmp_path, monkeypatch):
    monkeypatch.setattr(record, "RESULTS", tmp_path)
    path = record.write([("a figure", 1.5, "ms")], name="bench_x")
    table = pd.read_csv(path)
    assert table[["figure", "value", "unit"]].values.tolist() == [["a figure", 1.5, "ms"]]
    assert "cores" in table["machine"][0] and table["commit"][0] and table["date"][0].startswith("20")
