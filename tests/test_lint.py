"""The house rules, run with the tests: ruff (lint and format), mypy and import-linter, all clean."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent
SOURCES = ["heatdata", "tests", "scripts", "benchmarks", "workflow/scripts", "examples", "docs/conf.py"]


@pytest.mark.parametrize(
    "command",
    [
        ["ruff", "check", *SOURCES],
        ["ruff", "format", "--check", *SOURCES],
        ["mypy"],  # the packages and settings of [tool.mypy] in pyproject.toml
        ["lint-imports"],  # the layers of [tool.importlinter]
    ],
    ids=["ruff-check", "ruff-format", "mypy", "lint-imports"],
)
def test_the_tree_is_clean(command):
    result = subprocess.run([str(BIN / command[0]), *command[1:]], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 0, (result.stdout + result.stderr)[-3000:]


def test_a_stage_importing_a_later_one_breaks_the_layers(tmp_path):
    """The contract is not a formality: core importing from reporting is refused."""
    package = tmp_path / "heatdata"
    for path in (ROOT / "heatdata").rglob("*.py"):
        target = package / path.relative_to(ROOT / "heatdata")
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(path.read_text())
    (package / "core" / "mesh.py").write_text(
        (package / "core" / "mesh.py").read_text() + "\nfrom heatdata.reporting import pages  # noqa\n"
    )
    (tmp_path / "pyproject.toml").write_text((ROOT / "pyproject.toml").read_text())
    result = subprocess.run(
        [str(BIN / "lint-imports"), "--no-cache"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env={"PYTHONPATH": str(tmp_path), "PATH": str(BIN)},
    )
    assert result.returncode == 1 and "heatdata.core.mesh -> heatdata.reporting.pages" in result.stdout
