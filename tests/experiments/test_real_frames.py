"""Labelled real frames scored per category (heatdata.experiments.real_frames) and the workflow's section that
scores the folders a config names: on the vendored mOSD frame, and off without one."""

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT
from test_workflow import snakemake, tiny_config

from heatdata.errors import ConfigError
from heatdata.experiments.real_frames import (
    by_category,
    mosd_category,
    mosd_objects,
    read_labelled_frames,
    real_frame_folders,
    score_folder,
    worst_frames,
)

MOSD = ROOT / "tests" / "data" / "mosd"


def test_mosd_names_and_labels_say_the_category_and_the_objects():
    assert [mosd_category(n) for n in ("learn0", "learn20", "learn30", "learn44", "test50", "test60", "x1")] == [
        "boxes", "stacked", "occluded", "cylinders", "mixed", "complex", "other",
    ]  # fmt: skip
    # 1-9 the table, 10 k + j part j of object k: two parts of object 3 are one object
    assert mosd_objects(np.array([[0, 1, 9, 20], [21, 30, 31, 45]])).tolist() == [[0, 0, 0, 2], [2, 3, 3, 4]]


def test_a_folder_of_the_real_frame_is_read_and_scored():
    (frame,) = read_labelled_frames(MOSD)
    assert frame.name == "learn20" and frame.category == "stacked" and frame.depth.shape == (480, 640)
    assert np.isnan(frame.depth).any() and set(np.unique(frame.truth)) == {0, 2, 3}
    scores = score_folder(MOSD)
    assert scores[["frame", "objects", "found", "leftovers", "of_nothing"]].values.tolist() == [["learn20", 2, 2, 0, 0]]


def test_categories_sum_their_frames_and_the_worst_frames_miss_most():
    scores = pd.DataFrame(
        {
            "frame": ["a", "b", "c", "d"],
            "category": ["boxes", "boxes", "mixed", "mixed"],
            "objects": [4, 2, 5, 5],
            "found": [4, 1, 5, 3],
            "segments": [5, 2, 6, 4],
            "leftovers": [1, 0, 1, 0],
            "of_nothing": [0, 1, 0, 1],
            "seconds": [0.1, 0.3, 0.2, 0.4],
        }
    )
    table = by_category(scores).set_index("category")
    assert table.loc["boxes", "found_share"] == pytest.approx(5 / 6)
    assert table.loc["all", "objects"] == 16 and table.loc["all", "leftovers_per_object"] == pytest.approx(2 / 16)
    assert table.loc["mixed", "of_nothing_share"] == pytest.approx(1 / 10)
    assert table.loc["all", "median_seconds"] == pytest.approx(0.25)
    assert worst_frames(scores, 2)["frame"].tolist() == ["b", "d"]  # half missed, then 2 of 5 missed


def test_a_bad_folder_of_real_frames_is_a_config_error(tmp_path):
    with pytest.raises(ConfigError, match="no such folder"):
        real_frame_folders([str(tmp_path / "nowhere")])
    with pytest.raises(ConfigError, match="no intrinsics.json"):
        real_frame_folders([str(tmp_path)])
    (tmp_path / "intrinsics.json").write_text("{}")
    (tmp_path / "a.depth.png").write_bytes(b"")
    with pytest.raises(ConfigError, match="without <name>.labels.png"):
        real_frame_folders([str(tmp_path)])
    with pytest.raises(ConfigError, match="two folders named 'mosd'"):
        real_frame_folders([str(MOSD), str(MOSD)])


@pytest.mark.slow
@pytest.mark.workflow
def test_the_workflow_scores_the_real_frames_a_config_names(tmp_path):
    config = tiny_config(real_frames={"folders": [str(MOSD)]})
    off = snakemake(tmp_path / "off", tiny_config(), "--dry-run")
    assert off.returncode == 0 and "segment_real_frames" not in off.stdout  # off by default: no ../shared needed
    result = snakemake(tmp_path / "on", config, "results/figures/real_frames.html")
    assert result.returncode == 0, result.stderr[-3000:]
    summary = pd.read_csv(tmp_path / "on" / "results" / "real_frames" / "summary.csv")
    assert summary[["folder", "category", "objects", "found"]].values.tolist() == [
        ["mosd", "stacked", 2, 2],
        ["mosd", "all", 2, 2],
    ]
    page = (tmp_path / "on" / "results" / "figures" / "real_frames.html").read_text()
    assert "Objects found, by category" in page and "worst frames of mosd" in page and "data:image/png" in page
    assert "issue" not in page.lower()
