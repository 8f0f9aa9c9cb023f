"""The segmenter on a real Kinect frame (mOSD learn20, vendored under its BSD licence: two boxes, one standing on the
other), read as a user's sensor gives it: a depth PNG with intrinsics, and the PCD that PCL wrote."""

import json
from pathlib import Path

import numpy as np
from PIL import Image

from heatdata.cli import main
from heatdata.frames.clouds import read_frame_grid
from heatdata.segmentation.score import score_segmentation
from heatdata.segmentation.segment import label_image, segment_points

MOSD = Path(__file__).parents[1] / "data" / "mosd"


def truth():
    labels = np.asarray(Image.open(MOSD / "learn20.labels.png")).astype(np.int64)
    return np.where(labels >= 20, labels // 10, 0)  # mOSD: 10 k + j is part j of object k; below 20 the table


def test_stacked_boxes_on_a_real_table_are_two_segments_from_the_png_and_from_the_pcd():
    for frame in (
        read_frame_grid(MOSD / "learn20.depth.png", MOSD / "intrinsics.json", MOSD / "learn20.rgb.png"),
        read_frame_grid(MOSD / "learn20.pcd"),
    ):
        points, colors, intrinsics = frame
        found = segment_points(points, intrinsics, colors)
        score = score_segmentation(label_image(found, points.shape[:2]), truth())
        assert (score.objects, score.found, score.segments, score.leftovers, score.of_nothing) == (2, 2, 2, 0, 0)
        assert min(score.ious) > 0.9
        assert any(note.startswith("support plane") for note in found.notes)


def test_the_segment_command_writes_labels_an_overlay_and_json(tmp_path, capsys):
    out, overlay = tmp_path / "labels.png", tmp_path / "overlay.png"
    args = ["segment", str(MOSD / "learn20.depth.png"), "--intrinsics", str(MOSD / "intrinsics.json")]
    assert main([*args, "--rgb", str(MOSD / "learn20.rgb.png"), "-o", str(out), "--overlay", str(overlay)]) == 0
    labels = np.asarray(Image.open(out))
    assert labels.shape == (480, 640) and labels.dtype == np.uint16 and set(np.unique(labels)) == {0, 1, 2}
    assert score_segmentation(labels, truth()).found == 2
    assert Image.open(overlay).size == (640, 480)
    assert "2 object(s) in a 640x480 frame" in capsys.readouterr().out
    assert main([*args, "-o", str(out), "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert [s["label"] for s in printed["segments"]] == [1, 2]
    pixels = [s["pixels"] for s in printed["segments"]]
    assert pixels == sorted(pixels, reverse=True) and pixels == [int((labels == n).sum()) for n in (1, 2)]
    assert all(0.5 < s["centroid"][2] < 1.0 for s in printed["segments"])  # metres from the camera


def test_the_segment_command_says_what_is_wrong_in_one_line(tmp_path, caplog):
    assert main(["segment", str(MOSD / "learn20.depth.png"), "-o", str(tmp_path / "l.png")]) != 0
    (message,) = [r.getMessage() for r in caplog.records if r.levelname == "ERROR"]
    assert "a depth image needs --intrinsics" in message and "\n" not in message
    assert not (tmp_path / "l.png").exists()
