"""The README's "Using the library" example runs as written, from the repository root."""

import os
import re
import subprocess
import sys

import pytest
from conftest import ROOT


def readme_example() -> str:
    text = (ROOT / "README.md").read_text()
    section = text[text.index("## Using the library") :]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


@pytest.mark.slow
def test_the_using_the_library_example_runs_as_written(tmp_path):
    script = tmp_path / "example.py"
    script.write_text(readme_example())
    env = dict(os.environ, MPLBACKEND="Agg")
    run = subprocess.run([sys.executable, str(script)], cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr[-3000:]
    assert "recognized as coffee-cup" in run.stdout
    assert "from 20 sources: coffee-cup" in run.stdout
    assert re.search(r"compact library of the coffee cup: candidate \[(\d+, ){7}\d+\] of each view", run.stdout)
    assert "three stops: coffee-cup (particles), coffee-cup (exhaustive)" in run.stdout
    assert re.search(r"stitched: [12] loop pair\(s\), 0 open", run.stdout)
    back = re.search(r"read back from the depth PNG: (\d+) of (\d+) vertices", run.stdout)
    assert back and abs(int(back.group(1)) - int(back.group(2))) <= 0.02 * int(back.group(2))
    assert re.search(r"a real face scan: \d{5} vertices; \(64,\)", run.stdout)
    assert "HBRD: (32,) values" in run.stdout
