"""JASNOM's search (thesis eq. 7.5-7.6): the truth is the cheapest pose visited, symmetric boundaries are
ambiguous, opposite scans are turned right."""

import numpy as np
import pytest
import trimesh
from conftest import model_of
from meshes import MOTION, moved_half, truth
from scipy.spatial.transform import Rotation

from heatdata.io.models import Model
from heatdata.jasnom.align import align, alignment_at
from heatdata.jasnom.boundary import boundaries
from heatdata.jasnom.cost import ScanSurface
from heatdata.jasnom.cuts import closed_part
from heatdata.jasnom.seam import stitch


@pytest.mark.parametrize("amplitude, offset", [(0.0, 0.0), (0.05, 0.1), (0.0, -0.15)])
def test_the_cost_at_the_truth_is_at_or_below_every_pose_the_search_visits(ellipsoid, amplitude, offset):
    a, b = moved_half(ellipsoid, [0.3, 1.0, 0.2], amplitude, offset)
    loops1, loops2 = boundaries(a), boundaries(b)
    visited: list = []
    found = align(loops1, loops2, samples=64, trace=visited)
    expected = truth(*MOTION)
    at_truth = alignment_at(loops1, loops2, expected[:3, :3], expected[:3, 3], samples=64)
    assert len(visited) == found.candidates > 2 * 64
    assert at_truth.cost <= min(cost for _, _, cost in visited)
    assert at_truth.edge_cost < 1e-20 and at_truth.crossing_cost < 1e-20


def test_a_symmetric_boundary_is_reported_ambiguous_and_an_asymmetric_one_is_not():
    cylinder = model_of(trimesh.creation.cylinder(radius=0.05, height=0.12, sections=48), "cylinder")
    a, b = moved_half(closed_part(cylinder), [0.0, 0.0, 1.0], offset=0.05)
    assert align(boundaries(a), boundaries(b), samples=48).ambiguous  # a circle fits at every turn
    egg = trimesh.creation.icosphere(subdivisions=3)
    egg = model_of(trimesh.Trimesh(egg.vertices * [0.12, 0.09, 0.07] * (1 + 0.1 * egg.vertices[:, [0]]), egg.faces))
    a, b = moved_half(egg, [0.3, 1.0, 0.2])
    found = align(boundaries(a), boundaries(b), samples=48)
    assert not found.ambiguous and found.runner_up > 100 * found.cost


def test_two_rendered_scans_from_opposite_sides_are_turned_right():
    from heatdata.io.catalog import embedded_catalog, load_catalog_model, read_catalog
    from heatdata.views.render import render_view

    catalog = read_catalog(embedded_catalog()).set_index("object", drop=False)
    bottle = load_catalog_model(catalog.loc["yogurt-bottle"])
    size = float(np.linalg.norm(bottle.extents))
    views = [
        render_view(bottle, azimuth, elevation, 3 * size, seed=seed)
        for azimuth, elevation, seed in ((0.0, 45.0, 1), (180.0, -45.0, 2))
    ]  # standing, then flipped (7.5)
    first, second = (
        Model.untextured(name, v.vertices, v.faces, v.colors[v.faces])
        for name, v in zip(("standing", "flipped"), views, strict=True)
    )
    truth = np.linalg.inv(views[0].pose) @ views[1].pose
    found = stitch(first, second, scans=True, samples=64).alignment
    assert np.degrees(Rotation.from_matrix(found.rotation @ truth[:3, :3].T).magnitude()) < 5
    # each scan lies on the far side from the other's camera there
    assert ScanSurface.of(second).faces_camera(found.rotation, found.translation, np.zeros(3)) < 0.5
