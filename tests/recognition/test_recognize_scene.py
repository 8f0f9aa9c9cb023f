"""Recognizing a scene as a user meets it: objects on a table, off the image centre, one the library lacks, objects
touching, a bare table, an empty frame; through Library.recognize_scene and `heatdata recognize`."""

import json

import numpy as np
import pandas as pd
import pytest
import trimesh
from conftest import ROOT
from PIL import Image

import heatdata as hd
from heatdata.descriptors.rows import descriptor_rows
from heatdata.experiments.scenes import TABLE_HEIGHT, object_pose, room
from heatdata.experiments.views import render_views, view_plan
from heatdata.recognition.library import build_library, write_library
from heatdata.recognition.pose import pose_errors, sample_surface, symmetry_turns
from heatdata.views.render import Placement, camera_pose, render_scene

OBJECTS = ["milk-carton", "beer-mug", "bread"]
SPEC = hd.DescriptorSpec("hgd", color="hue-saturation")  # the default descriptor
FURNITURE = 3  # room(): table, wall, floor


@pytest.fixture(scope="module")
def models():
    catalog = hd.read_catalog(ROOT / "data/models/catalog.csv")
    return {row["object"]: hd.load_catalog_model(row) for row in catalog.to_dict("records") if row["object"] in OBJECTS}


@pytest.fixture(scope="module")
def library(models, tmp_path_factory):
    parts = []
    for obj, model in models.items():
        plan = view_plan([obj], 12, 2, elevation=30.0, distance=1.0, seed=0)
        parts.append(descriptor_rows(render_views(model, plan), plan, [SPEC]))
    sizes = {obj: model.extents.tolist() for obj, model in models.items()}
    surfaces = {obj: sample_surface(model.vertices, model.faces) for obj, model in models.items()}
    path = tmp_path_factory.mktemp("library") / "hgd-12.parquet"
    write_library(*build_library(pd.concat(parts, ignore_index=True), SPEC, 12, sizes=sizes, surfaces=surfaces), path)
    return hd.load_library(path)


def scene(objects, *, elevation=35.0, distance=1.1, seed=0):
    placements = [*room(1.2, 0.8, 0.05), *(Placement(m, object_pose(m, x, z, yaw)) for m, x, z, yaw in objects)]
    camera = camera_pose(np.array([0.0, TABLE_HEIGHT, 0.0]), 10.0, elevation, distance)
    return render_scene(placements, camera, sensor="kinect", seed=seed)


def true_pose(frame, model, x, z, yaw):
    """The model-to-camera pose of an object placed by :func:`scene`."""
    return np.linalg.inv(frame.camera) @ object_pose(model, x, z, yaw)


def unknown_box():
    box = trimesh.creation.box(extents=(0.1, 0.12, 0.1))
    return hd.Model.untextured("crate", np.asarray(box.vertices), np.asarray(box.faces), (0.6, 0.6, 0.3), label="box")


def test_every_object_on_the_table_is_found_named_posed_and_placed(library, models):
    placed = [(models["milk-carton"], -0.3, 0.1, 30.0), (models["beer-mug"], 0.05, -0.15, 200.0),
              (models["bread"], 0.3, 0.15, 70.0), (unknown_box(), -0.05, 0.25, 10.0)]  # fmt: skip
    frame = scene(placed)
    answer = library.recognize_scene(frame.depth, frame.intrinsics, frame.rgb)
    # the sliced loaf is cut at its own concave seam: its slice's face (65 cm^2, above the 40 cm^2 that rejoin) is a
    # fifth segment, lying on the bread (the segmenter's known cost, docs/chapters/scenes.md)
    assert answer.plane is not None and len(answer.detections) == 5
    truth = {}
    readings = np.isfinite(frame.depth)
    for number, name in enumerate([*OBJECTS, "crate"]):
        mask = (frame.labels == FURNITURE + number) & readings
        truth[name] = mask
    named = {}
    for detection in answer.detections:
        overlap = {name: (mask & detection.mask).sum() / (mask | detection.mask).sum() for name, mask in truth.items()}
        name = max(overlap, key=overlap.get)
        if name == "bread" and overlap[name] < 0.5:  # the slice's face: wholly on the bread, and said to be unknown
            assert (truth[name] & detection.mask).sum() > 0.95 * detection.pixels and detection.object is None
            continue
        assert overlap[name] > 0.5 if name == "bread" else overlap[name] > 0.7, overlap
        named[name] = detection
        points = hd.views.depth.back_project(frame.depth, frame.intrinsics)[detection.mask]
        assert np.allclose(detection.centroid, points.mean(axis=0))
        assert detection.pixels == detection.mask.sum()
        rows, cols = np.nonzero(detection.mask)
        assert detection.bbox == (cols.min(), rows.min(), cols.max(), rows.max())
    for name in OBJECTS:  # off the image centre, each nearest its own object, and surer of it than of the crate
        assert named[name].recognition.best.object == name, (name, named[name].recognition.matches[:2])
        assert named[name].confidence > 100 * named["crate"].confidence
    assert named["crate"].object is None and named["crate"].label is None  # no library holds it: unknown
    # named without its slice's face, the loaf is less sure (0.46; 0.9 and more whole)
    assert named["bread"].object == "bread" and named["bread"].confidence > 0.4
    for model, x, z, yaw in placed[:3]:  # each known object's pose, from the nearest library view by ICP
        pose = named[model.name].pose
        assert pose.object == model.name and pose.accepted and pose.converged
        surface = library.surfaces[model.name]
        errors = pose_errors(pose.matrix, true_pose(frame, model, x, z, yaw), surface, symmetry_turns(surface))
        # the targets are medians over the scenes experiment (ADD-S 10%, 1 cm, 5 deg); one view of one mug is 6.7 deg.
        # The carton, square but for its gable's ridge, lands a quarter turn away from a segment 98% the same as
        # its truth: ADD-S, the scenes' measure, counts it right; its rotation is right to within a quarter turn
        turn = errors["rotation"] % 90.0 if model.name == "milk-carton" else errors["rotation"]
        within = min(turn, 90.0 - turn) if model.name == "milk-carton" else turn
        # The loaf, seen without its slice's face, is posed from its nearest library views: with the HGD's vertex
        # budget they are 30 deg from those of every vertex, and ICP settles 1.1 cm and 16 deg off (ADD-S 5 mm,
        # right; 0.4 mm and 0.4 deg from every vertex's views). Over the budget's 30 scenes the median errors are
        # the same with and without it (docs/guide/speed.md).
        far, turned = (0.015, 20.0) if model.name == "bread" else (0.01, 10.0)
        assert errors["add_s_ok"] and errors["translation"] < far and within < turned, (model.name, errors)
    shape = answer.to_dict()
    assert set(shape) == {"descriptor", "objects", "plane", "repairs"} and len(shape["plane"]) == 4
    keys = {"object", "label", "confidence", "distance", "centroid", "pixels", "bbox", "notes", "pose"}
    assert keys <= set(shape["objects"][0])
    bread = next(o for o in shape["objects"] if o["object"] == "bread")["pose"]
    assert np.allclose(bread["matrix"], named["bread"].pose.matrix) and bread["accepted"] and 0 < bread["fitness"] <= 1
    crate = next(o for o in shape["objects"] if o["confidence"] == named["crate"].confidence)
    assert crate["object"] is None and crate["matches"][0]["object"] in OBJECTS  # the nearest, all the same
    # the user's threshold: 0 keeps every answer a pose explains (the default where poses are checked): not the
    # crate's, nor the loaf's slice face, whose whole loaf would sink 40% into the table to fit it
    everything = library.recognize_scene(frame.depth, frame.intrinsics, frame.rgb, threshold=0.0)
    assert sorted(d.object or "" for d in everything.detections) == ["", "", "beer-mug", "bread", "milk-carton"]
    assert [d.object for d in everything.detections] == [d.object for d in answer.detections]
    crate = max((d for d in everything.detections if d.object is None), key=lambda d: d.pixels)
    assert crate.recognition.confident and not crate.recognition.verified and not crate.pose.accepted
    slice_face = min(everything.detections, key=lambda d: d.pixels)
    assert slice_face.object is None and slice_face.pose.object == "bread" and slice_face.pose.below > 0.2
    unposed = library.recognize_scene(frame.depth, frame.intrinsics, frame.rgb, threshold=0.0, pose=False)
    assert all(d.object is not None and d.pose is None for d in unposed.detections)
    nothing = library.recognize_scene(frame.depth, frame.intrinsics, frame.rgb, threshold=1.0)
    assert all(d.object is None for d in nothing.detections)
    for bad in (-0.1, 1.5, float("nan"), "high"):
        with pytest.raises(hd.HeatdataError, match="threshold is a number in"):
            library.recognize_scene(frame.depth, frame.intrinsics, frame.rgb, threshold=bad)
    json.dumps(shape)


def test_objects_touching_are_cut_apart_and_each_named(library, models):
    frame = scene([(models["milk-carton"], -0.05, 0.0, 0.0), (models["beer-mug"], 0.07, 0.0, 90.0)])
    answer = library.recognize_scene(frame.depth, frame.intrinsics, frame.rgb)
    assert sorted(d.object for d in answer.detections) == ["beer-mug", "milk-carton"]
    for detection in answer.detections:  # each its own object's pixels, and not taken for several
        number = FURNITURE + OBJECTS.index(detection.object)
        truth = (frame.labels == number) & np.isfinite(frame.depth)
        assert (truth & detection.mask).sum() / (truth | detection.mask).sum() > 0.8
        assert not any("several objects touching" in note for note in detection.notes), detection.notes


def test_a_bare_table_an_empty_frame_and_an_isolated_object(library, models):
    bare = scene([])
    answer = library.recognize_scene(bare.depth, bare.intrinsics, bare.rgb)
    assert answer.detections == [] and answer.plane is not None and "no object on the support plane" in answer.repairs
    with pytest.raises(hd.ViewError, match="empty frame"):
        library.recognize_scene(np.zeros((480, 640)), bare.intrinsics)
    view = hd.render_view(models["bread"], 60.0, 30.0, 1.0, seed=2)
    depth = np.full((480, 640), np.nan)
    rgb = np.zeros((480, 640, 3))
    pixels = np.round(view.pixels).astype(int)
    depth[pixels[:, 1], pixels[:, 0]] = view.vertices[:, 2]
    rgb[pixels[:, 1], pixels[:, 0]] = view.colors
    answer = library.recognize_scene(depth, view.intrinsics, rgb)
    assert answer.plane is None and len(answer.detections) == 1
    assert answer.detections[0].object == library.recognize(view).best.object == "bread"


def test_a_frame_without_colour_warns_once(library, models):
    frame = scene([(models["beer-mug"], 0.0, 0.0, 0.0)])
    answer = library.recognize_scene(frame.depth, frame.intrinsics)
    assert sum("has no colour" in r for r in answer.repairs) == 1
    coloured = library.recognize_scene(frame.depth, frame.intrinsics, frame.rgb)
    assert not any("has no colour" in r for r in coloured.repairs)


def write_frame(frame, folder):
    millimetres = np.nan_to_num(np.round(frame.depth * 1000), nan=0).astype(np.uint16)
    Image.fromarray(millimetres).save(folder / "frame.png")
    Image.fromarray(np.round(frame.rgb * 255).astype(np.uint8)).save(folder / "frame.rgb.png")
    (folder / "frame.json").write_text(json.dumps(frame.intrinsics))
    return [
        str(folder / "frame.png"),
        "--intrinsics",
        str(folder / "frame.json"),
        "--rgb",
        str(folder / "frame.rgb.png"),
    ]


def test_the_command_answers_for_each_object_draws_them_and_says_when_there_is_none(library, models, tmp_path, capsys):
    from heatdata.cli import main

    # not the sliced loaf, which the segmenter cuts at its slices' faces, nor a mug's handle turned to the camera
    # (large handles are cut off too: docs/chapters/scenes.md); this test is of the command
    frame = scene([(models["milk-carton"], -0.2, 0.0, 30.0), (models["beer-mug"], 0.2, 0.1, 200.0)])
    command = ["recognize", *write_frame(frame, tmp_path), "--library", library.path]
    assert main([*command, "--overlay", str(tmp_path / "overlay.png")]) == 0
    out, err = capsys.readouterr()
    assert f"overlay written to {tmp_path / 'overlay.png'}" in err
    assert "objects on the support plane" in out and "milk-carton" in out and "beer-mug" in out
    assert "centroid x y z (m)" in out and "frame: support plane" in out
    overlay = np.asarray(Image.open(tmp_path / "overlay.png"))
    assert overlay.shape == (480, 640, 3) and not np.array_equal(overlay, np.round(frame.rgb * 255))
    assert main([*command, "--json", "--threshold", "0"]) == 0  # every answer kept: the nearest objects
    answer = json.loads(capsys.readouterr().out)
    assert {"beer-mug", "milk-carton"} <= {o["object"] for o in answer["objects"]}
    assert answer["plane"] is not None and answer["frame"].endswith("frame.png")
    assert all(0 <= o["confidence"] <= 1 for o in answer["objects"])
    assert main([*command, "--threshold", "1"]) == 0  # none kept: each unknown, its nearest object said
    out = capsys.readouterr().out
    assert "unknown" in out and "1: unknown: nearest" in out and "2: unknown: nearest" in out
    for bad in ("-0.5", "1.5", "nan", "high"):
        with pytest.raises(SystemExit) as stop:
            main([*command, "--threshold", bad])
        assert stop.value.code == 2 and "--threshold" in capsys.readouterr().err

    bare = tmp_path / "bare"
    bare.mkdir()
    assert main(["recognize", *write_frame(scene([]), bare), "--library", library.path]) == 0
    assert "no object found (no object on the support plane)" in capsys.readouterr().out


def test_the_command_refuses_what_it_cannot_draw_or_read(library, tmp_path, caplog):
    from heatdata.cli import main

    Image.fromarray(np.zeros((480, 640), np.uint16)).save(tmp_path / "empty.png")
    (tmp_path / "empty.json").write_text(json.dumps(hd.kinect_intrinsics()))
    base = ["recognize", str(tmp_path / "empty.png"), "--intrinsics", str(tmp_path / "empty.json")]
    cases = [
        ([*base, "--library", library.path], "empty frame"),
        ([*base, "--library", library.path, "--overlay", str(tmp_path / "o.jpg")], "ending in .png"),
        ([*base, "--library", library.path, "--overlay", str(tmp_path / "empty.png")], "empty.png"),
    ]
    for command, message in cases:
        caplog.clear()
        assert main(command) == 1, command
        errors = [r.getMessage() for r in caplog.records if r.levelname == "ERROR"]
        assert len(errors) == 1 and message in errors[0], errors


def test_a_mask_over_two_objects_gives_two_answers(library, models, tmp_path, capsys):
    from heatdata.cli import main

    frame = scene([(models["milk-carton"], -0.15, 0.0, 30.0), (models["beer-mug"], 0.15, 0.1, 0.0)])
    mask = np.isin(frame.labels, [FURNITURE, FURNITURE + 1])  # the user's mask of both objects, no table
    answer = library.recognize_scene(frame.depth, frame.intrinsics, frame.rgb, mask=mask)
    assert sorted(d.object for d in answer.detections) == ["beer-mug", "milk-carton"]
    assert answer.repairs[0].startswith("segmented by the mask") and answer.plane is None
    Image.fromarray((mask * 255).astype(np.uint8)).save(tmp_path / "frame.mask.png")
    command = ["recognize", *write_frame(frame, tmp_path), "--mask", str(tmp_path / "frame.mask.png")]
    assert main([*command, "--library", library.path, "--json"]) == 0
    assert len(json.loads(capsys.readouterr().out)["objects"]) == 2


def test_the_command_prints_each_pose_draws_its_outline_and_says_why_an_object_is_unknown(library, models, tmp_path,
                                                                                          capsys):  # fmt: skip
    from heatdata.cli import main

    frame = scene([(models["milk-carton"], -0.2, 0.0, 30.0), (unknown_box(), 0.2, 0.1, 0.0)])
    command = ["recognize", *write_frame(frame, tmp_path), "--library", library.path, "--threshold", "0"]
    assert main([*command, "--overlay", str(tmp_path / "posed.png")]) == 0
    out = capsys.readouterr().out
    assert "position x y z (m)" in out and "fitness" in out and "rmse (mm)" in out
    assert "pose of the milk-carton (model to camera" in out
    assert "unknown: no candidate's pose explains it (nearest" in out  # the crate, confident at threshold 0
    assert main([*command, "--no-pose", "--overlay", str(tmp_path / "plain.png")]) == 0
    out = capsys.readouterr().out
    assert "pose of the" not in out and "unknown" not in out  # without verification every answer is said
    posed, plain = (np.asarray(Image.open(tmp_path / f"{name}.png")) for name in ("posed", "plain"))
    changed = np.any(posed != plain, axis=2)  # the carton's outline (and the crate's label, now unknown)
    answer = library.recognize_scene(frame.depth, frame.intrinsics, frame.rgb, threshold=0.0)
    u0, v0, u1, v1 = next(d.bbox for d in answer.detections if d.object == "milk-carton")
    assert changed[v0 : v1 + 1, u0 : u1 + 1].sum() > 100


def test_a_library_without_surface_samples_answers_without_a_pose_and_says_how_to_rebuild(library, models, tmp_path,
                                                                                           capsys):  # fmt: skip
    from heatdata.cli import main
    from heatdata.io.tables import DESCRIPTOR_SCHEMA, read_table, write_table
    from heatdata.recognition.library import LIBRARY_KEY

    rows, run = read_table(library.path)
    older = {**run[LIBRARY_KEY], "surfaces": {}}
    write_table(rows, tmp_path / "older.parquet", DESCRIPTOR_SCHEMA, {LIBRARY_KEY: older})
    frame = scene([(models["bread"], 0.0, 0.0, 30.0)])
    assert main(["recognize", *write_frame(frame, tmp_path), "--library", str(tmp_path / "older.parquet")]) == 0
    out = capsys.readouterr().out
    assert out.count("holds no surface samples") == 1 and "rebuild it with the workflow" in out and "bread" in out
    answer = hd.load_library(tmp_path / "older.parquet").recognize(hd.render_view(models["bread"], 30.0, seed=1))
    assert answer.object == "bread" and answer.pose is None and any("surface samples" in r for r in answer.repairs)


def test_a_rejected_answer_falls_to_the_next_candidate_even_beyond_the_k_listed(library, models):
    import copy

    frame = scene([(models["bread"], 0.0, 0.0, 30.0)])
    swapped = copy.copy(library)  # the loaf's surface filed under the mug's name, the mug's under the loaf's
    swapped.surfaces = {
        **library.surfaces,
        "bread": library.surfaces["beer-mug"],
        "beer-mug": library.surfaces["bread"],
    }
    detections = swapped.recognize_scene(frame.depth, frame.intrinsics, frame.rgb, k=1, threshold=0.0).detections
    found = max(detections, key=lambda d: d.pixels)  # the loaf (its slices' faces are pieces of their own)
    assert found.recognition.best.object == "bread"  # the nearest, whose (swapped) surface cannot explain it
    assert found.object == "beer-mug" and found.pose.accepted  # the candidate whose surface is the loaf's
    assert [m.object for m in found.recognition.matches][0] == "bread" and found.recognition.answer.object == "beer-mug"


def test_two_unknown_pieces_of_one_object_are_joined_when_its_pose_explains_them_together(library, models):
    from dataclasses import replace

    from heatdata.recognition.answers import Detection
    from heatdata.segmentation.segment import Segment, Segmentation

    frame = scene([(models["milk-carton"], 0.0, 0.0, 30.0)])
    whole = hd.segment_frame(frame.depth, frame.intrinsics, frame.rgb)
    (carton,) = whole.segments
    # the carton cut in two down the middle of the image, as the segmenter cuts a drill's handle from its body
    rows, cols = np.nonzero(carton.mask)
    middle = int(np.median(cols))
    pieces = []
    for side in (
        carton.mask & (np.arange(carton.mask.shape[1]) < middle),
        carton.mask & ~(np.arange(carton.mask.shape[1]) < middle),
    ):
        keep = side[np.round(carton.view.pixels[:, 1]).astype(int), np.round(carton.view.pixels[:, 0]).astype(int)]
        view = carton.view.submesh(keep, "one side")
        r, c = np.nonzero(side)
        pieces.append(
            Segment(view, side, int(side.sum()), (c.min(), r.min(), c.max(), r.max()), view.vertices.mean(0), 0.1)
        )
    cut = Segmentation(whole.plane, pieces, coloured=True, depth=whole.depth)
    answers = library.recognize_segments(cut)
    # each half is unknown when its own pose is rejected (forced here): the two are tried together
    rejected = [
        Detection(
            replace(d.recognition, pose=replace(d.recognition.pose, accepted=False)),
            d.centroid,
            d.pixels,
            d.bbox,
            [],
            d.mask,
        )
        for d in answers.detections
    ]
    (joined,) = library._join_pieces(rejected, cut, 5, 0.0, False)
    assert joined.object == "milk-carton" and joined.pixels == carton.mask.sum()
    assert "two touching pieces joined" in joined.notes[0] and joined.bbox == carton.bbox
    apart = Segmentation(whole.plane, [pieces[0]], coloured=True, depth=whole.depth)
    assert len(library._join_pieces(rejected[:1], apart, 5, 0.0, False)) == 1  # nothing touches it: left alone


def test_a_wrong_focal_length_or_depth_unit_is_said_and_so_is_a_frame_of_unknowns(library, models):
    frame = scene([(models["beer-mug"], 0.0, 0.0, 0.0), (models["milk-carton"], 0.25, 0.1, 40.0)])
    right = library.recognize_scene(frame.depth, frame.intrinsics, frame.rgb)
    assert {d.object for d in right.detections} == {"beer-mug", "milk-carton"}
    assert not any("field of view" in r or "unknown to this library" in r for r in right.repairs)
    wide = {**frame.intrinsics, "fx": frame.intrinsics["fx"] / 3, "fy": frame.intrinsics["fy"] / 3}  # 122 deg: no note
    wrong = library.recognize_scene(frame.depth, wide, frame.rgb)
    assert all(d.object is None for d in wrong.detections) and wrong.detections
    assert any("every object of the frame is unknown to this library" in r for r in wrong.repairs)
    narrow = {**frame.intrinsics, "fx": frame.intrinsics["fx"] * 3, "fy": frame.intrinsics["fy"] * 3}
    assert any("field of view of 21 deg" in r for r in library.recognize_scene(frame.depth, narrow).repairs)
    metres_as_millimetres = library.recognize_scene(frame.depth * 1000, frame.intrinsics, frame.rgb)
    assert any("is the depth's unit right" in r for r in metres_as_millimetres.repairs)
