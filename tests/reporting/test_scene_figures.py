"""What the scenes page draws: a posed model's outline, the known/unknown curve, and the page around them."""

import io

import numpy as np
import pandas as pd
import trimesh
from PIL import Image

import heatdata as hd
from heatdata.recognition.pose import sample_surface
from heatdata.reporting.figures.scenes import Mark, known_curve, legend_lines, overlay_image, pose_outline
from heatdata.reporting.pages import scenes_page


def test_a_posed_models_outline_rings_where_it_projects():
    box = trimesh.creation.box(extents=(0.2, 0.2, 0.2))
    surface = sample_surface(np.asarray(box.vertices), np.asarray(box.faces))
    pose = np.eye(4)
    pose[:3, 3] = [0.0, 0.0, 1.0]  # a 20 cm cube 1 m in front of the camera, on its axis
    k = hd.kinect_intrinsics()
    outline = pose_outline(pose, surface, k)
    rows, cols = np.nonzero(outline)
    half = 0.1 * k["fx"] / 0.9  # the near face's half width in pixels
    assert abs(cols.min() - (k["cx"] - half)) < 6 and abs(cols.max() - (k["cx"] + half)) < 6
    assert not outline[int(k["cy"]), int(k["cx"])]  # a ring: the inside is not drawn
    behind = pose.copy()
    behind[2, 3] = -1.0
    assert not pose_outline(behind, surface, k).any()  # behind the camera: nothing
    picture = np.asarray(overlay_image(np.zeros((480, 640, 3), np.uint8), [Mark(None, (0, 0, 1, 1), "", outline)]))
    assert (picture[outline] > 0).any(axis=1).all()


def test_the_overlay_has_a_legend_of_what_its_marks_show():
    found = Mark(None, (10, 10, 60, 60), "1 beer-mug (0.91)")
    assert legend_lines([found]) == [
        "tint and box: an object found on the table: its number, and its name (confidence) where named"
    ]
    outline = np.zeros((480, 640), bool)
    outline[100, 100:200] = True
    marks = [found, Mark(None, (100, 100, 200, 200), "2 unknown [milk-carton]", outline)]
    assert [line.split(":")[0] for line in legend_lines(marks)] == ["tint and box", "unknown", "[name]", "outline"]
    picture = np.asarray(overlay_image(np.zeros((480, 640, 3), np.uint8), marks))
    corner = picture[400:, :320]
    assert (corner > 128).all(axis=2).sum() > 300  # the legend's white text, bottom left
    assert not np.asarray(overlay_image(np.zeros((480, 640, 3), np.uint8), [])).any()  # nothing found: no legend


def scores():
    rows = []
    for number, (truth, correct, verified, confidence) in enumerate(
        [("a", True, True, 0.9), ("b", True, True, 0.3), ("c", False, True, 0.2), ("", False, False, 0.8)]
    ):
        rows.append(
            {
                "detection": number,
                "truth": truth,
                "correct": correct,
                "verified": verified,
                "confidence": confidence,
                "threshold": 0.25,
            }  # fmt: skip
        )
    return pd.DataFrame(rows)


def test_the_known_curve_is_a_picture_and_the_page_shows_it_with_the_pose_columns():
    png = known_curve(scores())
    picture = Image.open(io.BytesIO(png))
    assert picture.format == "PNG" and picture.size[0] > 400
    summary = pd.DataFrame(
        [
            {
                "descriptor": "hgd", "scenes": 2, "objects": 3, "recall": 1.0, "segments": 4, "false_segments": 0.25,
                "named": 3, "naming": 2 / 3, "named_occluded": 0, "naming_occluded": np.nan, "named_sure": 1 / 3,
                "mistakes_unknown": 0.5, "median_seconds": 0.3, "p90_seconds": 0.4, "posed": 2, "pose_add_s": 1.0,
                "pose_translation": 0.004, "pose_rotation": 1.25, "pose_seconds": 0.02,
            }
        ]
    )  # fmt: skip
    settings = {"count": 2, "objects": [1, 4], "table": [1.2, 0.8], "distance": [0.8, 1.5], "elevation": [20, 50],
                "sensor": "kinect"}  # fmt: skip
    page = scenes_page(summary, pd.DataFrame(), {}, settings, "hgd", png)
    assert "0.40 cm" in page and "1.2 deg" in page and "20 ms" in page and "100.0%" in page
    assert "Known or unknown" in page and "data:image/png;base64," in page
    assert "Known or unknown" not in scenes_page(summary, pd.DataFrame(), {}, settings, "hgd")


def test_labels_of_neighbouring_objects_do_not_cover_each_other(monkeypatch):
    from PIL import ImageDraw

    drawn = []
    original = ImageDraw.ImageDraw.rectangle

    def record(self, xy, *args, **kwargs):
        if kwargs.get("fill") == (0, 0, 0):
            drawn.append(tuple(int(v) for v in xy))
        return original(self, xy, *args, **kwargs)

    monkeypatch.setattr(ImageDraw.ImageDraw, "rectangle", record)
    marks = [Mark(None, (100, 100, 180, 200), "1 beer-mug (0.91)"), Mark(None, (90, 95, 120, 160), "2 plastic-cup")]
    overlay_image(np.zeros((480, 640, 3), np.uint8), marks)
    first, second = drawn[:2]  # the two labels (the legend's box comes last)
    assert not (first[0] < second[2] and second[0] < first[2] and first[1] < second[3] and second[1] < first[3])
