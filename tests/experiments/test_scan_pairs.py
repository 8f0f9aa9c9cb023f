"""Scan pairs scored against a scanner's poses (heatdata.experiments.scan_pairs): the .conf convention, the true
motion between two scans' camera frames, the random starts and the errors, on analytic cases."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import heatdata as hd
from heatdata.errors import HeatdataError
from heatdata.experiments.scan_pairs import FLIP, camera_offset, errors, random_motion, read_conf, true_motion


def test_a_conf_line_is_a_turn_transposed_then_a_shift(tmp_path):
    conf = tmp_path / "bun.conf"
    quarter = Rotation.from_rotvec([0, np.pi / 2, 0])
    conf.write_text("camera 0 0 0 0 0 0 1\nbmesh a.ply 1 2 3 " + " ".join(map(str, quarter.as_quat())) + "\n")
    (pose,) = read_conf(conf).values()
    assert np.allclose(pose[:3, :3], quarter.as_matrix().T) and np.allclose(pose[:3, 3], [1, 2, 3])
    conf.write_text("bmesh a.ply 1 2 3 0 0 0\n")
    with pytest.raises(HeatdataError, match="bun.conf:1: a bmesh line"):
        read_conf(conf)


def test_the_true_motion_maps_one_scan_s_camera_points_onto_the_other_s():
    rng = np.random.default_rng(1)
    world = rng.normal(size=(50, 3))
    poses, offsets, cameras = {}, [], []
    for name, offset in (("a", 0.3), ("b", 0.5)):
        pose = np.eye(4)  # object frame <- file frame
        pose[:3, :3], pose[:3, 3] = Rotation.random(random_state=rng).as_matrix(), rng.normal(size=3)
        poses[name] = pose
        file_points = (world - pose[:3, 3]) @ pose[:3, :3]  # the scan's own points
        offsets.append(np.array([0.0, 0.0, offset]))
        cameras.append(file_points @ FLIP + offsets[-1])
    truth = true_motion(poses, ("a", "b"), tuple(offsets))
    assert np.allclose(cameras[1] @ truth[:3, :3].T + truth[:3, 3], cameras[0])
    model = hd.Model.untextured("b", cameras[1], np.array([[0, 1, 2]]), np.ones((1, 3, 3)))
    assert np.allclose(camera_offset(model, (world - poses["b"][:3, 3]) @ poses["b"][:3, :3]), offsets[1])


def test_random_starts_roll_the_scan_about_its_camera_axis_and_errors_measure_them():
    rng = np.random.default_rng(0)
    points = np.column_stack([rng.uniform(-0.1, 0.1, (100, 2)), rng.uniform(0.9, 1.1, 100)])
    for _ in range(20):
        start = random_motion(rng, 0.2)
        assert np.allclose(start[:3, :3] @ [0, 0, 1], [0, 0, 1]) and np.all(np.abs(start[:2, 3]) <= 0.02)
        assert np.all((points @ start[:3, :3].T + start[:3, 3])[:, 2] > 0)  # still in front of its camera
    turn = np.eye(4)
    turn[:3, :3] = Rotation.from_rotvec([0, 0, np.radians(10)]).as_matrix()
    angle, shift = errors(turn, np.eye(4), points, 0.2)
    centre = points.mean(axis=0)
    assert angle == pytest.approx(10.0)
    assert shift == pytest.approx(np.linalg.norm(turn[:3, :3] @ centre - centre) / 0.2)
