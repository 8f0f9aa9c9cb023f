"""Recognition scored on real frames with boxes (heatdata.experiments.real_recognition): which box each detection
belongs to, and what counts as right for a known object, an unknown one and a detection of nothing."""

import json

import pandas as pd
import pytest

from heatdata.errors import ConfigError
from heatdata.experiments.real_recognition import BoxTruth, frame_files, read_box_truth, score_scene, summary
from heatdata.recognition.answers import Detection, Match, Recognition, SceneRecognition


def detection(bbox, nearest, known=True):
    match = Match(nearest, "thing", 0.01, 0.0, 30.0, "v")
    answer = Recognition("hgd", [match], confidence=1.0 if known else 0.0, threshold=0.5)
    return Detection(answer, (0.0, 0.0, 1.0), 100, bbox)


TRUTH = BoxTruth(
    known={"can": (100, 100, 200, 200), "box": (300, 100, 400, 200)},
    unknown=[(0, 300, 100, 400), (200, 300, 300, 400)],
    unscored={"lookalike": (500, 300, 600, 400)},
)


def test_each_box_is_right_when_named_or_answered_unknown_as_it_should_be():
    scene = SceneRecognition(
        "hgd",
        [
            detection((110, 110, 190, 210), "can"),  # 9/10 of it in the can's box: the can, named right
            detection((290, 100, 390, 200), "can"),  # the box's, named wrong
            detection((10, 310, 90, 390), "can", known=False),  # an unknown object answered unknown
            detection((210, 310, 290, 390), "box"),  # an unknown object named
            detection((510, 310, 590, 390), "box"),  # the lookalike: not scored
            detection((400, 0, 450, 50), "can", known=False),  # of nothing, unknown: fine
            detection((450, 0, 500, 50), "box"),  # of nothing, named
        ],
        None,
    )
    rows = score_scene("f", scene, TRUTH).set_index(["kind", "truth"])
    assert rows.loc[("known", "can"), "right"] and not rows.loc[("known", "box"), "right"]
    assert rows.loc[("known", "box"), "nearest"] == "can"
    assert rows.loc[("unknown", "unknown-0"), "right"] and not rows.loc[("unknown", "unknown-1"), "right"]
    assert rows.loc[("unscored", "lookalike"), "answers"] == "box"
    nothing = rows.loc["nothing"]
    assert len(nothing) == 2 and nothing["right"].tolist() == [True, False]
    measured = summary(rows.reset_index().assign(seconds=0.5))
    assert {k: measured[k] for k in ("known", "known_right", "unknown", "unknown_right", "nothing_named")} == {
        "known": 2, "known_right": 1, "unknown": 2, "unknown_right": 1, "nothing_named": 1,
    }  # fmt: skip
    assert measured["frames"] == 1 and measured["median_seconds"] == 0.5


def test_a_missed_object_is_wrong_when_known_and_right_when_unknown():
    rows = score_scene("f", SceneRecognition("hgd", [], None), TRUTH)
    assert rows.groupby("kind")["right"].sum().to_dict() == {"known": 0, "unknown": 2, "unscored": 1}
    assert (rows["detections"] == 0).all()


def test_a_detection_that_no_box_holds_half_of_is_of_nothing():
    scene = SceneRecognition("hgd", [detection((150, 100, 320, 200), "box")], None)  # 29% in the can, 12% in the box
    rows = score_scene("f", scene, TRUTH).set_index("truth")
    assert rows.loc["can", "detections"] == 0 and rows.loc["", "kind"] == "nothing" and not rows.loc["", "right"]


def test_truth_files_and_frame_folders_are_read_or_refused_in_one_line(tmp_path):
    (tmp_path / "truth.json").write_text(
        json.dumps({"frames": {"000001": {"known": {"can": [1, 2, 3, 4]}, "not_in_models": [[0, 0, 5, 5]]}}})
    )
    truth = read_box_truth(tmp_path / "truth.json")
    assert truth["000001"] == BoxTruth({"can": (1, 2, 3, 4)}, [(0, 0, 5, 5)], {})
    for text, message in (
        ('{"frame": {}}', "KeyError"),
        ('{"frames": {"a": {"known": {"x": [3, 2, 1, 4]}}}}', "u0 < u1"),
    ):
        (tmp_path / "bad.json").write_text(text)
        with pytest.raises(ConfigError, match=f"bad.json: not a truth file of boxes .*{message}"):
            read_box_truth(tmp_path / "bad.json")
    with pytest.raises(ConfigError, match="no <name>-depth.png frames"):
        frame_files(tmp_path)
    (tmp_path / "000001-depth.png").write_bytes(b"")
    with pytest.raises(ConfigError, match="no colour image 000001-color.png"):
        frame_files(tmp_path)
    (tmp_path / "000001-color.png").write_bytes(b"")
    assert [name for name, _, _ in frame_files(tmp_path)] == ["000001"]
    assert isinstance(summary(pd.DataFrame(columns=["frame", "kind", "right", "seconds"]))["median_seconds"], float)
