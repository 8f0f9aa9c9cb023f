"""The README's example and the library guide's tour run as written, from the repository root."""

import os
import re
import subprocess
import sys

import pytest
from conftest import ROOT


def python_block(path, after: str) -> str:
    """The first ```python block of ``path`` after the heading ``after``."""
    text = (ROOT / path).read_text()
    section = text[text.index(after) :]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def run(tmp_path, code: str) -> str:
    script = tmp_path / "example.py"
    script.write_text(code)
    env = dict(os.environ, MPLBACKEND="Agg")
    result = subprocess.run(
        [sys.executable, str(script)], cwd=ROOT, env=env, capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, result.stderr[-3000:]
    return result.stdout


@pytest.mark.slow
def test_the_readme_example_runs_as_written_in_fifteen_lines(tmp_path):
    code = python_block("README.md", "## The library")
    assert len(code.strip().splitlines()) <= 15
    assert "recognized as coffee-cup" in run(tmp_path, code)


@pytest.mark.slow
def test_the_library_tour_runs_as_written(tmp_path):
    out = run(tmp_path, python_block("docs/guide/library.md", "# A tour of the library"))
    assert "recognized as coffee-cup" in out
    assert "from 20 sources: coffee-cup" in out
    assert re.search(r"compact library of the coffee cup: candidate \[(\d+, ){7}\d+\] of each view", out)
    assert "three stops: coffee-cup (particles), coffee-cup (exhaustive)" in out
    assert re.search(r"stitched: [12] loop pair\(s\), 0 open", out)
    back = re.search(r"read back from the depth PNG: (\d+) of (\d+) vertices", out)
    assert back and abs(int(back.group(1)) - int(back.group(2))) <= 0.02 * int(back.group(2))
    assert re.search(r"a real face scan: \d{5} vertices; \(64,\)", out)
    assert "HBRD: (32,) values" in out
