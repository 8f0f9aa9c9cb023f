"""The README's example and the library guide's tour run as written."""

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


def run(tmp_path, code: str, cwd=ROOT) -> str:
    script = tmp_path / "example.py"
    script.write_text(code)
    env = dict(os.environ, MPLBACKEND="Agg")
    result = subprocess.run(
        [sys.executable, str(script)], cwd=cwd, env=env, capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, result.stderr[-3000:]
    return result.stdout


def main_job_library(folder, views: int = 8) -> dict:
    """What the README's example reads from the main job, built by the workflow's own steps: the primary
    descriptor's library file, here of the 14 embedded objects at ``views`` library views (the main job's has 40),
    and its scene 0; returns the scene's truth."""
    import pandas as pd
    import yaml

    import heatdata as hd
    from heatdata.descriptors.rows import descriptor_rows
    from heatdata.experiments.scenes import SCENE_DEFAULTS, choose_objects, render_scene_files
    from heatdata.experiments.views import render_views, view_plan
    from heatdata.recognition.library import build_library, write_library
    from heatdata.recognition.pose import sample_surface

    config = yaml.safe_load((ROOT / "config/config.yaml").read_text())
    (spec,) = [
        s
        for s in map(lambda d: hd.DescriptorSpec(**d), config["descriptors"])
        if s.name == config["primary_descriptor"]
    ]
    catalog = hd.read_catalog(hd.embedded_catalog())
    rows, surfaces = [], {}
    for model in map(hd.load_catalog_model, catalog.to_dict("records")):
        plan = view_plan([model.name], views, 2, elevation=30.0, distance=1.0, seed=0)
        rows.append(descriptor_rows(render_views(model, plan), plan, [spec]))
        surfaces[model.name] = sample_surface(model.vertices, model.faces)
    library, metadata = build_library(pd.concat(rows, ignore_index=True), spec, views, surfaces=surfaces)
    write_library(library, metadata, folder / "results/libraries" / f"{hd.descriptors.file_name(spec.name)}-40.parquet")
    scenes = {**SCENE_DEFAULTS, **config["scenes"]}  # and the main job's scene 0, as its rule scene writes it
    names = choose_objects(catalog["object"].tolist(), scenes, 0)
    rows = [{**row, "object": row["object"]} for row in catalog.to_dict("records") if row["object"] in names]
    return render_scene_files(rows, scenes, 0, folder / "results/scenes/frames/scene-000.png")


@pytest.mark.slow
def test_the_readme_example_runs_as_written_in_fifteen_lines(tmp_path):
    code = python_block("README.md", "## The library")
    assert len(code.strip().splitlines()) <= 15
    truth = main_job_library(tmp_path)
    out = run(tmp_path, code, cwd=tmp_path)
    assert "beer-mug seen from about" in out
    answers = re.findall(r"^(\S+) \(([\d.]+) sure\): (\[\[|\()", out, re.M)
    found = {name: start for name, _, start in answers}
    assert all(0 <= float(sure) <= 1 for _, sure, _ in answers)
    large = {o["object"] for o in truth["objects"] if o["pixels"] >= 1000}  # every large object found is there, named
    assert large and large <= set(found) <= {o["object"] for o in truth["objects"]} | {"unknown"}, out
    assert all(start == ("(" if name == "unknown" else "[[") for name, start in found.items()), out  # named: posed


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
