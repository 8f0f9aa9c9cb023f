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


def ball_halves():
    """The two halves of a ball 1 m ahead, each as its camera saw it: the front from the origin, the back from 2 m
    behind the ball looking back (in its own frame); and the true motion of the back's frame into the front's."""
    cap = trimesh.creation.icosphere(subdivisions=4, radius=0.1)
    centre = np.array([0.0, 0.0, 1.0])
    front = cap.triangles_center[:, 2] < 0
    turn = Rotation.from_rotvec([0.0, np.pi, 0.0]).as_matrix()  # camera 2's frame from camera 1's: x2 = turn x1 + t
    t = np.array([0.0, 0.0, 2.0])
    first = Model.untextured("front", cap.vertices + centre, cap.faces[front][:, ::-1], (0.5, 0.5, 0.5))
    second = Model.untextured("back", (cap.vertices + centre) @ turn.T + t, cap.faces[~front][:, ::-1], (0.5,) * 3)
    return first, second, turn.T, -turn.T @ t


def ball_scans():
    first, second, rotation, translation = ball_halves()
    return ScanSurface.of(first), ScanSurface.of(second), rotation, translation


def test_free_space_is_nil_at_the_truth_and_grows_as_one_scan_enters_the_other_s_seen_space():
    front, back, rotation, translation = ball_scans()
    np.testing.assert_allclose(front.free_space(back, rotation, translation), 0.0, atol=1e-12)
    toward = [front.free_space(back, rotation, translation - [0.0, 0.0, shift])[0] for shift in (0.02, 0.04, 0.08)]
    assert 0 < toward[0] < toward[1] < toward[2]  # the back half moved towards camera 1, through the front half
    # moved away, each lies behind the other's surface: a thicker object, which only the boundary terms rule out
    np.testing.assert_array_equal(front.free_space(back, rotation, translation + [0.0, 0.0, 0.04]), 0.0)


def test_two_opposite_scans_of_a_ball_are_stitched_where_neither_enters_the_other_s_seen_space():
    from heatdata.jasnom.seam import stitch

    first, second, rotation, translation = ball_halves()
    found = stitch(first, second, scans=True, samples=64).alignment
    assert found.free_space_cost < 1e-6  # nothing at the answer
    through = np.eye(4)
    through[:3, :3], through[:3, 3] = rotation, translation - [0.0, 0.0, 0.04]  # the back half through the front
    assert stitch(first, second, scans=True, samples=64, motion=through).alignment.free_space_cost > 1e-3
    # a ball's halves may turn about its axis; the back's centre, (0, 0, 1) in its frame too, lands on the front's
    np.testing.assert_allclose(found.rotation @ [0.0, 0.0, 1.0] + found.translation, [0.0, 0.0, 1.0], atol=0.002)
    assert stitch(first, second, samples=64).alignment.free_space_cost == 0.0  # meshes: no cameras, no term
