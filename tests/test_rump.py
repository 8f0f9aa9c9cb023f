"""HBRD (thesis ch. 8, Algorithm 8.1) on surfaces with known answers: a flat rump, round rumps, moved rumps."""

import numpy as np
import pytest
import scipy.sparse.linalg as sla
from scipy.spatial import Delaunay
from scipy.spatial.transform import Rotation

import heatdata as hd
from heatdata.core.spectrum import laplacian
from heatdata.errors import RumpError
from heatdata.rump import _heat, apply_homography, hbrd_times, homography, landmark_frame, landmark_trapezoid, rump_heat

# hip left, hip right, pin left, pin right as a camera sees them (image y down: the hips above the pins)
LANDMARKS_2D = np.array([[-0.05, -0.07], [0.05, -0.07], [-0.07, 0.07], [0.07, 0.07]])


def rump(height: float, *, step: float = 0.006, seed: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A 24 x 24 cm grid seen by a camera 1 m above (z towards it is -z_camera): a bump of ``height`` metres
    between the landmarks (a Gaussian of 5 cm), and the landmarks on it."""
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.arange(-0.12, 0.12 + 1e-9, step), np.arange(-0.12, 0.12 + 1e-9, step))
    xy = np.column_stack([x.ravel(), y.ravel()]) + rng.uniform(-0.1, 0.1, (x.size, 2)) * step
    bump = height * np.exp(-np.sum(xy**2, axis=1) / (2 * 0.05**2))
    vertices = np.column_stack([xy, 1.0 - bump])  # the camera at the origin looks along +z
    faces = Delaunay(xy).simplices
    nearest = [int(np.argmin(np.linalg.norm(xy - p, axis=1))) for p in LANDMARKS_2D]
    return vertices, faces, vertices[nearest]


def test_a_flat_rump_is_its_own_planar_twin():
    vertices, faces, landmarks = rump(0.0)
    z = hd.hbrd(vertices, faces, landmarks)
    assert z.shape == (32,) and np.abs(z).max() < 1e-9


@pytest.mark.slow
def test_rounder_rumps_keep_heat_at_their_centre_longer():
    descriptors = [hd.hbrd(*rump(h)) for h in (0.005, 0.01, 0.02, 0.04)]
    peaks = [d.max() for d in descriptors]
    assert peaks[0] > 0 and np.all(np.diff(peaks) > 0)
    heat = rump_heat(*rump(0.02))
    assert heat.difference.shape == (32, len(heat.vertices)) and heat.path[0] == heat.center
    assert np.linalg.norm(heat.vertices[heat.path[-1], :2] - heat.landmarks[0]) < 0.01  # ends at the left hip
    np.testing.assert_allclose(heat.times, hbrd_times())
    assert heat.times[0] == pytest.approx(1 / 700) and heat.times[-1] == pytest.approx(0.1)


def test_a_hollow_rump_keeps_the_surface_between_its_bones():
    vertices, faces, landmarks = rump(-0.02)  # hollow between the bones: below their plane
    heat = rump_heat(vertices, faces, landmarks)
    centre = heat.vertices[heat.center]
    assert centre[2] < -0.005 and np.linalg.norm(centre[:2] - heat.landmarks.mean(axis=0)) < 0.01
    assert np.isfinite(heat.descriptor).all() and heat.descriptor.max() > 0


@pytest.mark.slow
def test_the_descriptor_does_not_depend_on_where_the_rump_is_or_how_it_is_turned():
    vertices, faces, landmarks = rump(0.02)
    turn, shift = Rotation.from_rotvec([0.4, -0.3, 1.1]), np.array([0.2, -0.5, 0.3])
    moved = hd.hbrd(
        turn.apply(vertices) + shift, faces, turn.apply(landmarks) + shift, toward=turn.apply(-landmarks.mean(axis=0))
    )
    np.testing.assert_allclose(moved, hd.hbrd(vertices, faces, landmarks), rtol=1e-6, atol=1e-9)


def test_the_normalization_sends_the_landmarks_to_the_canonical_trapezoid():
    vertices, faces, landmarks = rump(0.02)
    skewed = landmarks.copy()
    skewed[1, 0] += 0.01  # a hip bone annotated 1 cm off
    canonical = landmark_trapezoid(landmarks)
    heat = rump_heat(vertices, faces, skewed, canonical=canonical)
    np.testing.assert_allclose(heat.landmarks, canonical)
    np.testing.assert_allclose(canonical[:, 0], [-0.05, 0.05, -0.07, 0.07], atol=0.006)  # symmetric, as given
    h = homography(LANDMARKS_2D, canonical)
    np.testing.assert_allclose(apply_homography(h, LANDMARKS_2D), canonical, atol=1e-12)


def test_the_heat_is_exact_against_expm_multiply():
    vertices, faces, _ = rump(0.03, step=0.012)
    edges = np.unique(np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1), axis=0)
    times = hbrd_times(5)
    ours = _heat(vertices, edges, 100, times)
    L = laplacian(vertices, edges)
    pulse = np.zeros(len(vertices))
    pulse[100] = 1.0
    reference = np.array([sla.expm_multiply(-t * L, pulse) * len(vertices) for t in times])
    np.testing.assert_allclose(ours, reference, atol=1e-6 * reference.max())


@pytest.mark.slow
def test_an_extent_keeps_only_the_surface_around_the_bones():
    vertices, faces, landmarks = rump(0.02)
    whole, near = rump_heat(vertices, faces, landmarks), rump_heat(vertices, faces, landmarks, extent=1.2)
    assert len(near.vertices) < 0.6 * len(whole.vertices)
    assert np.abs(near.vertices[:, 0]).max() <= 1.2 * np.abs(near.landmarks[:, 0]).max() + 1e-9


def test_bad_landmarks_are_clear_errors():
    vertices, faces, landmarks = rump(0.02)
    with pytest.raises(RumpError, match="four finite 3D points"):
        hd.hbrd(vertices, faces, landmarks[:3])
    with pytest.raises(RumpError, match="with NaN"):
        hd.hbrd(vertices, faces, np.where(np.eye(4, 3, dtype=bool), np.nan, landmarks))
    lifted = landmarks.copy()
    lifted[0, 2] -= 0.2  # a hip bone 20 cm out of the others' plane
    with pytest.raises(RumpError, match="far from coplanar"):
        hd.hbrd(vertices, faces, lifted)
    off = landmarks.copy()
    off[:, 0] += 0.2  # the right landmarks beyond the surface
    with pytest.raises(RumpError, match="off the mesh"):
        hd.hbrd(vertices, faces, off)
    with pytest.raises(RumpError, match="out of order"):
        hd.hbrd(vertices, faces, landmarks[[2, 3, 0, 1]])
    with pytest.raises(RumpError, match="one line"):
        landmark_frame(np.column_stack([np.linspace(0, 1, 4), np.zeros(4), np.ones(4)]))
    with pytest.raises(RumpError, match="extent must be positive"):
        hd.hbrd(vertices, faces, landmarks, extent=0.0)
