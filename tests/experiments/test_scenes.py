"""The workflow's scenes: seeded plans of objects apart on a table, their truth, the files a capture is written as,
and the scores of detections against the truth."""

import json

import numpy as np
import pytest
import trimesh
from conftest import ROOT

import heatdata as hd
from heatdata.errors import ConfigError
from heatdata.experiments.config import run_scenes
from heatdata.experiments.scenes import (
    GAP,
    SCENE_DEFAULTS,
    choose_objects,
    pack_mask,
    plan_scene,
    read_scene,
    render_planned_scene,
    scene_summary,
    score_scene,
    unpack_mask,
    write_scene,
)
from heatdata.recognition.answers import Detection, Match, Recognition
from heatdata.segmentation.segment import segment_frame

OBJECTS = ["beer-mug", "milk-carton", "bread", "cupcake", "coffee-cup", "speaker-small"]


@pytest.fixture(scope="module")
def models():
    catalog = hd.read_catalog(ROOT / "data/models/catalog.csv")
    return {row["object"]: hd.load_catalog_model(row) for row in catalog.to_dict("records") if row["object"] in OBJECTS}


def test_a_scene_is_the_same_whatever_else_the_run_holds_and_its_objects_stand_apart(models):
    settings = {**SCENE_DEFAULTS, "objects": [3, 4]}
    for index in range(5):
        names = choose_objects(OBJECTS, settings, index)
        assert names == choose_objects(list(reversed(OBJECTS)), settings, index) and 3 <= len(names) <= 4
        plan = plan_scene([models[n] for n in names], settings, index)
        assert plan == plan_scene([models[n] for n in names], settings, index)
        spots = plan["objects"]
        for a in range(len(spots)):
            for b in range(a + 1, len(spots)):
                ra = 0.5 * np.hypot(*models[spots[a]["object"]].extents[[0, 2]])
                rb = 0.5 * np.hypot(*models[spots[b]["object"]].extents[[0, 2]])
                gap = np.hypot(spots[a]["x"] - spots[b]["x"], spots[a]["z"] - spots[b]["z"])
                assert gap >= ra + rb + GAP - 1e-9
        camera = plan["camera"]
        assert 0.8 <= camera["distance"] <= 1.5 and 20 <= camera["elevation"] <= 50
    singles = [choose_objects(OBJECTS, {**SCENE_DEFAULTS, "objects": [1, 1]}, k) for k in range(8)]
    assert all(len(one) == 1 for one in singles) and len({one[0] for one in singles}) > 1
    small_table = plan_scene([models["bread"], models["coffee-cup"]], {**SCENE_DEFAULTS, "table": [0.25, 0.25]}, 0)
    assert [o["object"] for o in small_table["objects"]] == ["coffee-cup"]
    assert small_table["left_out"] == [f"bread ({np.hypot(*models['bread'].extents[[0, 2]]):.2f} m across)"]
    crowded = plan_scene([models["beer-mug"], models["coffee-cup"]], {**SCENE_DEFAULTS, "table": [0.3, 0.3]}, 0)
    assert [o["object"] for o in crowded["objects"]] == ["beer-mug"]
    assert crowded["left_out"] == [f"coffee-cup ({np.hypot(0.1, 0.1):.2f} m across, no room beside the others)"]


def test_the_truth_matches_the_frame_and_the_files_read_back(models, tmp_path):
    settings = {**SCENE_DEFAULTS, "objects": [2, 2], "sensor": "ideal"}  # no flying pixel off the objects
    names = choose_objects(OBJECTS, settings, 3)
    plan = plan_scene([models[n] for n in names], settings, 3)
    frame, truth = render_planned_scene(plan, models, settings)
    assert [o["object"] for o in truth["objects"]] == names
    write_scene(frame, truth, tmp_path / "scene-003.png")
    depth, rgb, intrinsics, labels, read = read_scene(tmp_path / "scene-003.png")
    assert read == json.loads(json.dumps(truth)) and intrinsics == frame.intrinsics
    assert np.allclose(depth[np.isfinite(depth)], frame.depth[np.isfinite(frame.depth)], atol=6e-4)  # millimetres
    for number, item in enumerate(truth["objects"], 1):
        mine = (labels == number) & np.isfinite(depth)
        assert mine.sum() == item["pixels"] and item["visible"] >= item["pixels"]
        # the pose takes the model's vertices to the camera frame, where the object's readings are
        pose = np.asarray(item["pose"])
        model = models[item["object"]]
        corners = model.vertices @ pose[:3, :3].T + pose[:3, 3]
        points = hd.views.depth.back_project(depth, intrinsics)[mine]
        assert np.all(points.min(axis=0) >= corners.min(axis=0) - 0.02)
        assert np.all(points.max(axis=0) <= corners.max(axis=0) + 0.02)
    found = segment_frame(depth, intrinsics, rgb)
    assert np.allclose(found.plane, truth["plane"], atol=0.02)  # the table top, as RANSAC finds it
    frames = hd.experiments.captures.find_frames(tmp_path)  # the labels image is not a frame
    assert [f["name"] for f in frames] == ["scene-003"] and frames[0]["rgb"].endswith(".rgb.png")


def detection(mask, name, distance=0.1, confidence=0.9, pose=None):
    rows, cols = np.nonzero(mask)
    match = Match(name, "thing", distance, 30.0, 30.0, f"{name}/train/001")
    bbox = (int(cols.min()), int(rows.min()), int(cols.max()), int(rows.max()))
    answer = Recognition("hgd", [match], [], confidence, threshold=0.05, pose=pose)
    return Detection(answer, (0.0, 0.0, 1.0), int(mask.sum()), bbox, [], mask)


def test_detections_are_matched_by_mask_overlap_and_the_summary_counts_them():
    labels = np.zeros((40, 60), np.uint8)
    labels[5:15, 5:15] = 1  # object 1: 100 px
    labels[20:30, 20:40] = 2  # object 2: 200 px
    labels[30:35, 50:55] = 3  # object 3, missed
    depth = np.ones(labels.shape)
    truth = {
        "scene": "s",
        "objects": [
            {"object": "a", "label": "x", "pixels": 1200, "occluded": 0.0, "cut": False},
            {"object": "b", "label": "y", "pixels": 2000, "occluded": 0.3, "cut": False},
            {"object": "c", "label": "z", "pixels": 1500, "occluded": 0.0, "cut": False},
        ],
    }
    first = labels == 1
    second = labels == 2
    second[20:30, 35:40] = False  # IoU 150 / 200 = 0.75
    speck = np.zeros(labels.shape, bool)
    speck[0:3, 50:58] = True
    found = [detection(first, "a"), detection(second, "a", confidence=0.01), detection(speck, "a")]
    scores = score_scene(found, labels, depth, truth)
    assert scores["truth"].tolist() == ["a", "b", "", "c"] and scores["detection"].tolist() == [0, 1, 2, -1]
    assert scores["iou"].tolist()[:2] == [1.0, 0.75] and scores["correct"].tolist() == [True, False, False, False]
    for row in scores[scores["detection"] >= 0].itertuples():
        assert np.array_equal(unpack_mask(row.mask, row.bbox, labels.shape), [first, second, speck][row.detection])
    summary = scene_summary(scores.assign(descriptor="hgd", seconds=0.2, seconds_without_pose=0.1)).iloc[0]
    assert summary["objects"] == 3 and summary["recall"] == pytest.approx(2 / 3)
    assert summary["segments"] == 3 and summary["false_segments"] == pytest.approx(1 / 3)
    assert (summary["named"], summary["naming"]) == (1, 1.0)  # b is occluded: counted apart
    assert (summary["named_occluded"], summary["naming_occluded"]) == (1, 0.0)
    assert summary["named_sure"] == 1.0  # a, named right and sure
    assert summary["mistakes_unknown"] == 0.5  # b said unknown; the speck, matching nothing, named all the same
    assert scores["known"].tolist() == [True, False, True, False] and scores["confidence"].tolist()[1] == 0.01
    assert summary["median_seconds"] == 0.2
    empty = score_scene([], labels, depth, {"scene": "t", "objects": []})
    assert empty.empty and "truth" in empty.columns


def test_packed_masks_round_trip():
    rng = np.random.default_rng(0)
    mask = rng.random((48, 64)) < 0.3
    bbox = (5, 7, 40, 30)
    inside = np.zeros_like(mask)
    inside[7:31, 5:41] = mask[7:31, 5:41]
    assert np.array_equal(unpack_mask(pack_mask(inside, bbox), bbox, mask.shape), inside)


def test_the_scenes_config_is_checked_before_any_job():
    specs = [hd.DescriptorSpec("pvhk"), hd.DescriptorSpec("hgd", color="hue-saturation")]
    config = {
        "scenes": {**SCENE_DEFAULTS, "enabled": True, "descriptors": [], "library_size": None, "offaxis": 0},
        "library_sizes": [40, 8],
        "primary_descriptor": "hgd/color=hue-saturation",
    }
    plan = run_scenes(config, OBJECTS, specs)
    assert len(plan["scenes"]) == 6 and plan["size"] == 40 and plan["primary"] == "hgd/color=hue-saturation"
    assert plan["descriptors"] == [s.name for s in specs]
    off = run_scenes({**config, "scenes": {**config["scenes"], "enabled": False}}, OBJECTS, specs)
    assert off["scenes"] == {}
    furniture = {OBJECTS[0]: [0.9, 1.0, 0.6], OBJECTS[1]: [0.1, 0.2, 0.1]}  # a chair, a cup
    some = run_scenes(config, OBJECTS, specs, furniture)
    assert some["left_out"] == [OBJECTS[0]] and all(OBJECTS[0] not in objects for objects in some["scenes"].values())
    chairs = run_scenes(config, OBJECTS[:1], specs, furniture)
    assert chairs["scenes"] == {} and chairs["left_out"] == [OBJECTS[0]]
    bad = [
        ({"descriptors": ["esf"]}, "not among the run's descriptors"),
        ({"library_size": 12}, "not one of library_sizes"),
        ({"distance": [1.5, 0.8]}, "runs high to low"),
    ]
    for change, message in bad:
        with pytest.raises(ConfigError, match=message):
            run_scenes({**config, "scenes": {**config["scenes"], **change}}, OBJECTS, specs)


def test_a_posed_detection_is_scored_against_the_true_pose_and_a_rejected_one_is_unknown():
    from heatdata.recognition.pose import Pose, sample_surface, symmetry_turns

    box = trimesh.creation.box(extents=(0.2, 0.1, 0.3))
    surface = sample_surface(np.asarray(box.vertices), np.asarray(box.faces))
    labels = np.zeros((40, 60), np.uint8)
    labels[5:15, 5:15] = 1
    labels[20:30, 20:40] = 2
    truth_pose = np.eye(4)
    truth_pose[:3, 3] = [0.0, 0.0, 1.0]
    truth = {
        "scene": "s",
        "objects": [
            {"object": "a", "label": "x", "pixels": 1200, "occluded": 0.0, "cut": False, "pose": truth_pose.tolist()},
            {"object": "b", "label": "y", "pixels": 1200, "occluded": 0.0, "cut": False, "pose": truth_pose.tolist()},
        ],
    }
    near = truth_pose.copy()
    near[0, 3] += 0.01  # 1 cm off
    accepted = Pose("a", near, 1.0, 0.002, 1.0, 0.0, 0.0, True, True, 0.013)
    rejected = Pose("b", truth_pose, 1.0, 0.002, 0.5, 0.4, 0.0, True, False, 0.013)
    found = [detection(labels == 1, "a", pose=accepted), detection(labels == 2, "b", pose=rejected)]
    scores = score_scene(found, labels, np.ones(labels.shape), truth, {"a": (surface, symmetry_turns(surface))})
    a, b = scores.iloc[0], scores.iloc[1]
    assert a["posed"] == "a" and a["verified"] and a["known"] and a["translation_error"] == pytest.approx(0.01)
    assert a["add_s_ok"] and a["rotation_error"] == pytest.approx(0.0, abs=1e-6) and a["symmetric"]  # a half turn
    assert np.allclose(np.reshape(a["pose"], (4, 4)), near) and a["explained"] == 1.0
    assert not b["verified"] and not b["known"] and b["correct"]  # named right, but no pose explains it: unknown
    assert np.isnan(b["add_s"])  # b's surface was not given: its pose is not scored
    summary = scene_summary(scores.assign(descriptor="hgd", seconds=0.3, seconds_without_pose=0.1)).iloc[0]
    assert summary["posed"] == 1 and summary["pose_add_s"] == 1.0 and summary["pose_translation"] == pytest.approx(0.01)
    assert np.isnan(summary["pose_rotation"]) and summary["pose_seconds"] == pytest.approx(0.1)  # 0.2 s, 2 objects
