"""Scene segmentation: the support plane by RANSAC, the objects on it by DBSCAN, one view each, and what a user
is told about frames that are not a table with objects on it."""

import subprocess
import sys

import numpy as np
import pytest
import trimesh

import heatdata as hd
from heatdata.experiments.scenes import TABLE_HEIGHT, box_model, object_pose, room
from heatdata.segmentation.segment import SegmentSettings, segment_frame
from heatdata.views.render import Placement, camera_pose, render_scene
from heatdata.views.view import KINECT_INTRINSICS


def solid(name, mesh, color):
    return hd.Model.untextured(name, np.asarray(mesh.vertices), np.asarray(mesh.faces), color, label=name)


BOX = solid("box", trimesh.creation.box(extents=(0.12, 0.18, 0.08)), (0.8, 0.3, 0.2))
CAN = solid("can", trimesh.creation.cylinder(radius=0.04, height=0.15, sections=48), (0.2, 0.5, 0.8))
BALL = solid("ball", trimesh.creation.icosphere(subdivisions=3, radius=0.06), (0.3, 0.7, 0.3))


def table_scene(
    objects, *, elevation=30.0, distance=1.0, target=(0.0, 0.0), sensor="kinect", wall=True, wall_gap=0.1, seed=0
):
    """Objects ``[(model, x, z, yaw)]`` on a 1.2 x 0.8 m table in a room (the wall optional, ``wall_gap`` behind
    it); the camera looks at ``target``. Placement ``i`` of the objects is label ``FURNITURE + i``."""
    placements = room(1.2, 0.8, wall_gap)
    if not wall:
        placements[1] = Placement(placements[1].model, _at(0.0, -5.0, 0.0))  # under the floor
    placements += [Placement(m, object_pose(m, x, z, yaw)) for m, x, z, yaw in objects]
    camera = camera_pose(np.array([target[0], TABLE_HEIGHT, target[1]]), 0.0, elevation, distance)
    return render_scene(placements, camera, sensor=sensor, seed=seed)


FURNITURE = 3


def _at(x, y, z):
    pose = np.eye(4)
    pose[:3, 3] = [x, y, z]
    return pose


def iou(a, b):
    return (a & b).sum() / (a | b).sum()


def test_objects_on_a_table_are_found_one_segment_each_wherever_they_stand():
    frame = table_scene([(BOX, -0.25, 0.05, 20.0), (CAN, 0.0, -0.1, 0.0), (BALL, 0.3, 0.12, 0.0)])
    found = segment_frame(frame.depth, frame.intrinsics, frame.rgb)
    assert len(found.segments) == 3
    readings = np.isfinite(frame.depth)
    for segment in found.segments:
        labels, counts = np.unique(frame.labels[segment.mask], return_counts=True)
        truth = (frame.labels == labels[np.argmax(counts)]) & readings
        assert iou(segment.mask, truth) > 0.9
        assert segment.view.n_components >= 1 and segment.pixels == segment.mask.sum()
        assert np.allclose(
            segment.centroid, np.nanmean(np.where(segment.mask[..., None], _points(frame), np.nan), axis=(0, 1))
        )
    # the plane: the table top, its normal towards the camera, 1 m from a camera 30 deg above it
    normal = found.plane[:3]
    assert normal @ [0.0, -np.cos(np.radians(30)), -np.sin(np.radians(30))] > 0.999
    assert found.plane[3] == pytest.approx(np.sin(np.radians(30)), abs=0.01)
    assert any(note.startswith("support plane") for note in found.notes)


def _points(frame):
    from heatdata.views.depth import back_project

    return back_project(frame.depth, frame.intrinsics)


def test_a_frame_of_one_isolated_object_has_no_plane_and_one_segment(mug):
    view = hd.render_view(mug, 100.0, 30.0, 1.0, seed=1)
    depth = np.full((480, 640), np.nan)
    pixels = np.round(view.pixels).astype(int)
    depth[pixels[:, 1], pixels[:, 0]] = view.vertices[:, 2]
    found = segment_frame(depth, KINECT_INTRINSICS)
    assert found.plane is None and len(found.segments) == 1
    assert found.segments[0].view.n_vertices == pytest.approx(view.n_vertices, rel=0.02)
    assert any("no support plane" in note for note in found.notes)


def test_an_isolated_cup_seen_into_is_one_segment_not_a_crash(catalog):
    # its inside, seen over the rim, is parted from its outside by a depth step; with no support plane no neighbour
    # can meet it, so the pieces within the cluster distance are one object (this view crashed the plane's search)
    cup = hd.load_catalog_model(catalog[catalog["object"] == "plastic-cup"].iloc[0])
    view = hd.render_view(cup, azimuth=159.0, seed=902)
    depth = np.full((480, 640), np.nan)
    pixels = np.round(view.pixels).astype(int)
    depth[pixels[:, 1], pixels[:, 0]] = view.vertices[:, 2]
    found = segment_frame(depth, KINECT_INTRINSICS)
    assert found.plane is None and len(found.segments) == 1
    assert found.segments[0].pixels >= 0.98 * np.isfinite(depth).sum()


def test_a_box_alone_is_not_its_own_support_plane():
    big = solid("crate", trimesh.creation.box(extents=(0.45, 0.3, 0.45)), (0.6, 0.6, 0.3))
    frame = table_scene([(big, 0.0, 0.0, 30.0)], wall=False, distance=1.2)
    frame.depth[frame.labels != FURNITURE] = np.nan  # the crate alone, no table
    found = segment_frame(frame.depth, frame.intrinsics, frame.rgb)
    assert found.plane is None and len(found.segments) == 1
    assert found.segments[0].pixels >= 0.995 * np.isfinite(frame.depth).sum()


def test_a_frame_of_only_a_table_or_only_a_wall_holds_no_object():
    table = table_scene([], wall=False)
    found = segment_frame(table.depth, table.intrinsics)
    assert found.plane is not None and found.segments == []
    assert "no object on the support plane" in found.notes
    wall = render_scene([Placement(box_model("wall", (3.0, 3.0, 0.02), (0.8, 0.8, 0.8)), _at(0, 0, 1.5))], np.eye(4))
    found = segment_frame(wall.depth, wall.intrinsics)
    assert found.segments == []


def test_an_empty_frame_is_a_clear_error():
    with pytest.raises(hd.ViewError, match="empty frame"):
        segment_frame(np.zeros((480, 640)), KINECT_INTRINSICS)
    with pytest.raises(hd.ViewError, match="intrinsics are for"):
        segment_frame(np.ones((240, 320)), KINECT_INTRINSICS)


@pytest.mark.parametrize("sensor", ["ideal", "kinect"])
def test_objects_touching_each_other_are_cut_apart_at_their_concave_seam(sensor):
    frame = table_scene([(BOX, -0.03, 0.0, 0.0), (CAN, 0.07, 0.0, 0.0)], sensor=sensor)
    found = segment_frame(frame.depth, frame.intrinsics, frame.rgb)
    assert len(found.segments) == 2
    for label, segment in zip((FURNITURE, FURNITURE + 1), sorted(found.segments, key=lambda s: s.centroid[0])):
        assert iou(segment.mask, (frame.labels == label) & np.isfinite(frame.depth)) > 0.8


def test_an_object_by_the_wall_keeps_to_itself():
    # the table against the wall: the wall's base is in the band of an object's foot, all along the table's back edge
    frame = table_scene([(CAN, -0.2, -0.35, 0.0)], wall_gap=0.0, distance=1.2, target=(0.0, -0.1))
    (segment,) = segment_frame(frame.depth, frame.intrinsics, frame.rgb).segments
    truth = (frame.labels == FURNITURE) & np.isfinite(frame.depth)
    assert iou(segment.mask, truth) > 0.9
    assert segment.extent < np.hypot(0.08, 0.15)  # the can (lying along z), not a line along the wall


@pytest.mark.parametrize("yaw", [0.0, 30.0, 45.0])
def test_a_segment_measures_its_footprint_however_it_is_turned(yaw):
    frame = table_scene([(BOX, 0.0, 0.0, yaw)], sensor="ideal")  # its top, seen from above, is its footprint
    (segment,) = segment_frame(frame.depth, frame.intrinsics, frame.rgb).segments
    assert segment.extent == pytest.approx(np.hypot(0.12, 0.08), rel=0.05)


def test_an_object_cut_by_the_image_border_says_so():
    frame = table_scene([(BOX, -0.5, 0.0, 0.0), (CAN, 0.0, 0.0, 0.0)], sensor="ideal")
    found = segment_frame(frame.depth, frame.intrinsics, frame.rgb)
    cut = [s for s in found.segments if any("image border" in n for n in s.notes)]
    whole = [s for s in found.segments if not any("image border" in n for n in s.notes)]
    assert len(cut) == 1 and cut[0].bbox[0] == 0
    assert len(whole) == 1


def test_a_table_seen_edge_on_says_so():
    frame = table_scene([(CAN, 0.0, 0.0, 0.0)], elevation=4.0, distance=0.9, sensor="ideal")
    found = segment_frame(frame.depth, frame.intrinsics, frame.rgb)
    assert any("edge-on" in note for note in found.notes)


def test_bad_settings_are_refused():
    for fields in ({"plane_distance": 0.0}, {"plane_share": 1.5}, {"min_height": 2.0}, {"min_pixels": 2.5}):
        with pytest.raises(hd.ViewError, match="bad segmentation settings"):
            SegmentSettings(**fields)


def test_a_table_seen_from_straight_above_is_still_the_support():
    frame = table_scene([(BOX, -0.2, 0.0, 0.0), (CAN, 0.15, 0.1, 0.0)], elevation=89.0, distance=1.0, sensor="ideal")
    found = segment_frame(frame.depth, frame.intrinsics, frame.rgb)
    assert found.plane is not None and np.abs(found.plane[:3] @ [0.0, 0.0, -1.0]) > 0.99
    assert len(found.segments) == 2


def test_a_frame_is_segmented_the_same_every_time_even_on_a_busy_machine(catalog):
    # open3d's RANSAC runs in threads and returns a plane a little apart each time (the refit plane is the same), and
    # its early stop depended on their timing: with both cores busy, the flipped beer mug's table (a frame of the
    # JASNOM experiment) came out another way in 3 of 6 runs
    from heatdata.experiments.scenes import render_flipped_pair

    mug = hd.load_catalog_model(catalog[catalog["object"] == "beer-mug"].iloc[0])
    frames = [
        table_scene([(BOX, -0.2, 0.05, 20.0), (CAN, 0.15, -0.1, 0.0)], distance=1.3),
        render_flipped_pair(mug, elevation=38.2, yaw=262.6, flip_axis=0.87, seed=1)[1],
    ]
    first = [segment_frame(f.depth, f.intrinsics, f.rgb) for f in frames]
    busy = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(2)]
    try:
        for _ in range(4):
            for frame, before in zip(frames, first):
                again = segment_frame(frame.depth, frame.intrinsics, frame.rgb)
                assert np.array_equal(again.plane, before.plane)
                assert [s.pixels for s in again.segments] == [s.pixels for s in before.segments]
    finally:
        for process in busy:
            process.kill()
            process.wait()
