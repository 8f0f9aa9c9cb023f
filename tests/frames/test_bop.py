"""BOP's formats (heatdata.frames.bop): a scene folder read as BOP writes it, heatdata's poses put in the model
file's own frame (checked against the file's points), and the results CSV as bop_toolkit reads it."""

import json

import numpy as np
import pytest
import trimesh
from PIL import Image

from heatdata.errors import ViewError
from heatdata.frames.bop import bop_object_id, file_frame_pose, read_bop_scene, write_bop_results
from heatdata.io.models import UP_AXES, load_model


def bop_scene(root, depth_scale=0.1):
    scene = root / "000048"
    (scene / "depth").mkdir(parents=True)
    (scene / "rgb").mkdir()
    depth = np.full((48, 64), 7000, np.uint16)  # 700 mm at a depth_scale of 0.1
    depth[0, 0] = 0
    for im_id in (1, 3):
        Image.fromarray(depth).save(scene / "depth" / f"{im_id:06d}.png")
        Image.fromarray(np.zeros((48, 64, 3), np.uint8)).save(scene / "rgb" / f"{im_id:06d}.png")
    camera = {"cam_K": [600.0, 0.0, 32.0, 0.0, 601.0, 24.0, 0.0, 0.0, 1.0], "depth_scale": depth_scale}
    (scene / "scene_camera.json").write_text(json.dumps({"3": camera, "1": camera}))
    return scene


def test_a_bop_scene_reads_its_cameras_and_depth_in_metres(tmp_path):
    images = read_bop_scene(bop_scene(tmp_path))
    assert [(i.scene_id, i.im_id) for i in images] == [(48, 1), (48, 3)]
    assert images[0].intrinsics == {"fx": 600.0, "fy": 601.0, "cx": 32.0, "cy": 24.0, "width": 64, "height": 48}
    depth, rgb = images[0].read()
    assert np.nanmax(depth) == pytest.approx(0.7) and np.isnan(depth[0, 0]) and rgb.shape == (48, 64, 3)


def test_a_bad_bop_scene_is_refused_in_one_line(tmp_path):
    scene = bop_scene(tmp_path)
    (scene / "rgb" / "000003.png").unlink()
    with pytest.raises(ViewError, match="image 3 lacks its depth/000003.png or rgb/000003.png"):
        read_bop_scene(scene)
    (scene / "scene_camera.json").write_text('{"1": {"depth_scale": 1.0}}')
    with pytest.raises(ViewError, match="image 1: no cam_K"):
        read_bop_scene(scene)
    (scene / "scene_camera.json").write_text("[1, 2]")
    with pytest.raises(ViewError, match="not BOP's scene_camera.json"):
        read_bop_scene(scene)
    with pytest.raises(ViewError, match="named by its scene id"):
        read_bop_scene(tmp_path)


def test_a_pose_in_the_model_files_frame_maps_its_millimetres_where_heatdata_put_them(tmp_path):
    # a z-up model in millimetres, off its origin, as BOP ships one
    mesh = trimesh.creation.box(extents=(60.0, 40.0, 200.0))
    mesh.apply_translation([15.0, -7.0, 100.0])
    mesh.export(tmp_path / "obj_000005.ply")
    model = load_model(tmp_path / "obj_000005.ply", scale=0.001, up_axis="z")
    turned = load_model(tmp_path / "obj_000005.ply", up_axis="z", center=False)  # the file turned, its units
    centre = 0.5 * (turned.vertices.min(axis=0) + turned.vertices.max(axis=0))
    angle = np.radians(35.0)
    pose = np.eye(4)
    pose[:3, :3] = [[np.cos(angle), 0, np.sin(angle)], [0, 1, 0], [-np.sin(angle), 0, np.cos(angle)]]
    pose[:3, 3] = [0.1, -0.05, 0.8]
    seen = model.vertices @ pose[:3, :3].T + pose[:3, 3]  # where heatdata puts the model, metres
    bop = file_frame_pose(pose, UP_AXES["z"], centre, 0.001)
    file_points = np.asarray(trimesh.load(tmp_path / "obj_000005.ply").vertices)
    assert np.allclose(file_points @ bop[:3, :3].T + bop[:3, 3], 1000.0 * seen, atol=1e-6)
    assert np.allclose(bop[:3, :3] @ bop[:3, :3].T, np.eye(3)) and np.linalg.det(bop[:3, :3]) == pytest.approx(1.0)
    assert bop_object_id("obj_000005") == 5 and bop_object_id("ycbv-obj_000021") == 21
    with pytest.raises(ViewError, match="not a BOP model's name"):
        bop_object_id("mug")


def test_the_results_csv_has_bop_toolkits_seven_columns(tmp_path):
    pose = np.eye(4)
    pose[:3, 3] = [10.5, -20.25, 700.0]
    path = write_bop_results(
        [{"scene_id": 48, "im_id": 1, "obj_id": 5, "score": 0.9, "time": 1.25, "pose": pose}], tmp_path / "r.csv"
    )
    header, row = path.read_text().splitlines()
    assert header == "scene_id,im_id,obj_id,score,R,t,time"
    fields = row.split(",")  # as bop_toolkit_lib.inout.load_bop_results splits it
    assert len(fields) == 7 and [int(x) for x in fields[:3]] == [48, 1, 5] and float(fields[3]) == 0.9
    assert np.allclose(np.array(fields[4].split(), float).reshape(3, 3), np.eye(3))
    assert np.allclose(np.array(fields[5].split(), float), [10.5, -20.25, 700.0]) and float(fields[6]) == 1.25
