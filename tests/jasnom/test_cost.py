"""JASNOM's cost (thesis eq. 7.2-7.4, made continuous): continuous, zero at the seam, size-free; a scan faces its
camera."""

import numpy as np
import pytest
import trimesh
from meshes import MOTION, moved_half, truth
from scipy.spatial.transform import Rotation

from heatdata.io.models import Model, transformed
from heatdata.jasnom.align import alignment_at
from heatdata.jasnom.boundary import boundaries, boundary
from heatdata.jasnom.cost import ScanSurface
from heatdata.jasnom.cuts import split_model


def test_the_cost_is_continuous_and_grows_with_misalignment(ellipsoid):
    a, b = split_model(ellipsoid, [0.0, 1.0, 0.0])
    b1, b2 = boundary(a), boundary(b)
    steps = np.linspace(0.0, 0.01, 21)  # up to a tenth of the ellipsoid's radius, in steps far below the sampling
    costs = np.array([alignment_at(b1, b2, np.eye(3), [d, 0.0, 0.0], samples=32).cost for d in steps])
    assert costs[0] == pytest.approx(0.0, abs=1e-20) and np.all(np.diff(costs) > 0)
    assert np.max(np.abs(np.diff(costs, 2))) < 0.2 * costs[-1] / len(steps)  # smooth: no jumps between samples
    turns = [
        alignment_at(b1, b2, Rotation.from_rotvec([0.0, angle, 0.0]).as_matrix(), np.zeros(3), samples=32).cost
        for angle in np.radians([0.0, 0.5, 1.0, 2.0])
    ]
    assert turns[0] < turns[1] < turns[2] < turns[3]


def test_interpenetration_costs_nothing_at_the_seam_and_grows_with_depth(ellipsoid):
    a, b = split_model(ellipsoid, [0.0, 1.0, 0.0])  # a: the upper half, its boundary normals point down
    b1, b2 = boundary(a), boundary(b)
    crossing = [
        alignment_at(b1, b2, np.eye(3), [0.0, d, 0.0], samples=32).crossing_cost
        for d in (-0.01, 0.0, 0.002, 0.005, 0.01)
    ]
    # lowering the lower half opens a gap (nothing crosses); raising it pushes it into the upper one
    assert crossing[0] < 0.2 * crossing[-1] and crossing[1] < 1e-20
    assert crossing[1] < crossing[2] < crossing[3] < crossing[4]


def test_the_cost_does_not_depend_on_the_object_size(ellipsoid):
    a, b = moved_half(ellipsoid, [0.3, 1.0, 0.2], 0.05)
    offset = truth(*MOTION)
    offset[:3, 3] += [0.004, 0.0, 0.002]  # a few percent of the size off
    small = alignment_at(boundaries(a), boundaries(b), offset[:3, :3], offset[:3, 3])
    big = alignment_at(
        boundaries(transformed(a, 10 * np.eye(3), np.zeros(3))),
        boundaries(transformed(b, 10 * np.eye(3), np.zeros(3))),
        offset[:3, :3],
        10 * offset[:3, 3],
    )
    assert big.cost == pytest.approx(small.cost, rel=1e-9) and small.cost > 0


def test_a_scan_faces_its_own_camera_and_not_the_opposite_one():
    cap = trimesh.creation.icosphere(subdivisions=3, radius=0.1)
    keep = cap.triangles_center[:, 2] < 0  # the half a camera at the origin sees of a ball 1 m ahead
    scan = Model.untextured("scan", cap.vertices + [0.0, 0.0, 1.0], cap.faces[keep][:, ::-1], (0.5, 0.5, 0.5))
    surface = ScanSurface.of(scan)
    assert surface.toward_camera == -1.0  # wound away from its camera, as heatdata's views are
    assert surface.faces_camera(np.eye(3), np.zeros(3), np.zeros(3)) > 0.85  # all but the faces near the limb
    turned = Rotation.from_rotvec([0.0, np.pi, 0.0]).as_matrix()  # the back of the ball, seen from the same camera
    assert surface.faces_camera(turned, [0.0, 0.0, 2.0] - turned @ [0.0, 0.0, 1.0], np.zeros(3)) < 0.15
