"""JASNOM (thesis ch. 7) on meshes with known answers: an ellipsoid cut in two, moved, and stitched back."""

import logging

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from heatdata.models import Model
from heatdata.stitch import (StitchError, boundary, closed_part, order_preserving_assignment, resample_loop,
                             split_model, stitch, strip_faces, transformed)

MOTION = Rotation.from_rotvec([0.5, -1.0, 0.3]), np.array([0.3, 0.1, -0.2])


def model_of(mesh: trimesh.Trimesh, name: str = "ellipsoid") -> Model:
    colors = np.zeros((len(mesh.faces), 3, 3), np.float32)
    colors[..., 0] = 0.8
    colors[mesh.triangles_center[:, 1] > 0.03] = [0.1, 0.3, 0.9]
    return Model.untextured(name, mesh.vertices, mesh.faces, colors)


@pytest.fixture(scope="module")
def ellipsoid() -> Model:
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.1)
    return model_of(trimesh.Trimesh(sphere.vertices * [1.0, 0.6, 0.8], sphere.faces))


def as_trimesh(model: Model) -> trimesh.Trimesh:
    return trimesh.Trimesh(model.vertices, model.faces, process=False)


@pytest.mark.parametrize("amplitude", [0.0, 0.05])
def test_two_halves_moved_apart_are_aligned_and_stitched_closed(ellipsoid, amplitude):
    a, b = split_model(ellipsoid, [0.3, 1.0, 0.2], amplitude=amplitude)
    rotation, translation = MOTION
    result = stitch(a, transformed(b, rotation.as_matrix(), translation), workers=1, samples=64)
    # ground truth: the inverse motion
    error = Rotation.from_matrix(result.alignment.rotation) * rotation
    assert np.degrees(error.magnitude()) < 0.1
    expected_t = -(rotation.inv().apply(translation))
    assert np.linalg.norm(result.alignment.translation - expected_t) < 1e-3 * np.linalg.norm(ellipsoid.extents)
    mesh = as_trimesh(result.model)
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
    assert mesh.volume == pytest.approx(as_trimesh(ellipsoid).volume, rel=1e-3)
    assert len(result.model.faces) == len(ellipsoid.faces) + len(result.first.loop) + len(result.second.loop)
    assert result.alignment.facing < -0.5 and len(result.alignment.costs) == 64
    # both halves' colours are kept, the strip's come from its corners
    assert result.model.corner_colors.shape == (len(result.model.faces), 3, 3)
    assert np.isclose(result.model.corner_colors[..., 2], 0.9).any() and np.isclose(
        result.model.corner_colors[..., 0], 0.8).any()


def test_the_shift_search_in_processes_gives_the_same_answer(ellipsoid):
    a, b = split_model(ellipsoid, [0.0, 1.0, 0.0])
    b = transformed(b, *(m.as_matrix() if i == 0 else m for i, m in enumerate(MOTION)))
    one = stitch(a, b, workers=1, samples=32).alignment
    two = stitch(a, b, workers=2, samples=32).alignment
    np.testing.assert_allclose(one.costs, two.costs)
    np.testing.assert_allclose(one.rotation, two.rotation)


def test_a_known_motion_is_used_as_given_and_only_the_shift_is_searched(ellipsoid, caplog):
    a, b = split_model(ellipsoid, [0.3, 1.0, 0.2], amplitude=0.05)
    rotation, translation = MOTION
    moved = transformed(b, rotation.as_matrix(), translation)
    inverse = np.eye(4)
    inverse[:3, :3] = rotation.inv().as_matrix()
    inverse[:3, 3] = -rotation.inv().apply(translation)
    result = stitch(a, moved, motion=inverse, samples=64)
    np.testing.assert_allclose(result.alignment.rotation, inverse[:3, :3])
    np.testing.assert_allclose(result.alignment.translation, inverse[:3, 3])
    assert result.alignment.edge_cost < 0.02 and result.alignment.facing < -0.5  # half a sample apart at most
    mesh = as_trimesh(result.model)
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume == pytest.approx(as_trimesh(ellipsoid).volume, rel=1e-3)
    # a motion a tenth of the size off costs more, even at its own best shift
    off = inverse.copy()
    off[:3, 3] += [0.02, 0.0, 0.0]
    assert stitch(a, moved, motion=off, samples=64).alignment.edge_cost > 3 * result.alignment.edge_cost
    # at a given motion, boundaries that do not face each other are a gap to span: a warning, not an error
    caplog.set_level(logging.WARNING, logger="heatdata.stitch")
    lifted = np.eye(4)
    lifted[1, 3] = 0.05  # the same half again, above itself: both boundaries' normals point down
    assert stitch(a, a, motion=lifted, samples=32).alignment.facing > 0.5
    assert "do not face each other across their boundaries at the given motion" in caplog.text
    with pytest.raises(StitchError, match="4x4 rigid transform"):
        stitch(a, moved, motion=np.diag([1.0, -1.0, 1.0, 1.0]))
    with pytest.raises(StitchError, match="4x4 rigid transform"):
        stitch(a, moved, motion=np.eye(3))


def test_the_assignment_preserves_order_and_reverses_direction():
    first = np.arange(8) / 8
    np.testing.assert_array_equal(order_preserving_assignment(first, first, 0.0), [0, 7, 6, 5, 4, 3, 2, 1])
    np.testing.assert_array_equal(order_preserving_assignment(first, first, 0.25), [2, 1, 0, 7, 6, 5, 4, 3])
    coarse = np.arange(4) / 4  # fewer vertices on the second boundary: every one still finds its nearest
    np.testing.assert_array_equal(order_preserving_assignment(first, coarse, 0.0), [0, 6, 4, 2])


def test_resampling_is_uniform_by_arc_length():
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    points, nearest = resample_loop(square, 8)
    np.testing.assert_allclose(np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1), 0.5)
    assert nearest.tolist() == [0, 1, 1, 2, 2, 3, 3, 0]
    with pytest.raises(StitchError, match="at least 3 samples"):
        resample_loop(square, 2)


def test_the_strip_uses_every_boundary_edge_once_against_its_face(ellipsoid):
    a, b = split_model(ellipsoid, [1.0, 0.2, 0.0])
    b1, b2 = boundary(a), boundary(b)
    faces = strip_faces(b1, b2, 0.0, offset=len(a.vertices))
    assert len(faces) == len(b1.loop) + len(b2.loop)
    halves = {tuple(e) for f in faces for e in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))}
    for loop, offset in ((b1.loop, 0), (b2.loop, len(a.vertices))):
        for u, v in zip(loop, np.roll(loop, -1), strict=True):
            assert (v + offset, u + offset) in halves  # the reverse of the mesh's own boundary half-edge


def test_boundary_normals_point_out_of_the_mesh(ellipsoid):
    a, _ = split_model(ellipsoid, [0.0, 1.0, 0.0])  # the upper half: its boundary runs round the equator
    b = boundary(a)
    assert b.loops == 1 and np.allclose(np.linalg.norm(b.normals, axis=1), 1.0)
    assert np.mean(b.normals[:, 1]) < -0.5  # out of the upper half is downwards
    assert b.arclength[0] == 0.0 and np.all(np.diff(b.arclength) > 0) and b.arclength[-1] < 1.0


def test_bad_meshes_are_clear_errors(ellipsoid, caplog):
    with pytest.raises(StitchError, match="closed"):
        boundary(ellipsoid)
    a, b = split_model(ellipsoid, [0.0, 1.0, 0.0])
    triangle = Model.untextured("triangle", np.eye(3), [[0, 1, 2]], (0.0, 0.0, 0.0))
    assert len(boundary(triangle).loop) == 3
    fin = Model(name="fin", vertices=np.vstack([a.vertices, [[0.0, 0.5, 0.0]]]),
                faces=np.vstack([a.faces, [[a.faces[0, 0], a.faces[0, 1], len(a.vertices)]]]),
                corner_colors=np.concatenate([a.corner_colors, a.corner_colors[:1]]),
                corner_uv=np.concatenate([a.corner_uv, a.corner_uv[:1]]),
                face_texture=np.concatenate([a.face_texture, a.face_texture[:1]]))
    with pytest.raises(StitchError, match="more than two faces"):
        boundary(fin)
    mirrored = transformed(a, np.diag([1.0, -1.0, 1.0]), [0.0, 0.0, 0.0])  # the lower half, wound inwards
    with pytest.raises(StitchError, match="do not face each other"):
        stitch(a, mirrored, workers=1, samples=32)
    caplog.set_level(logging.WARNING, logger="heatdata.stitch")
    stitch(a, transformed(b, np.eye(3) * 0.5, [0.0, 0.0, 0.0]), workers=1, samples=32)  # a boundary half as long
    assert "lengths differ by a factor 2.00" in caplog.text
    with pytest.raises(StitchError, match="alpha must be positive"):
        stitch(a, b, alpha=0.0, workers=1)
    with pytest.raises(StitchError, match="one side"):
        split_model(ellipsoid, [0.0, 1.0, 0.0], offset=1.0)


def test_the_command_writes_a_closed_coloured_mesh(ellipsoid, tmp_path, capsys, caplog):
    import json

    from heatdata.cli import main
    from heatdata.models import save_model

    a, b = split_model(ellipsoid, [0.3, 1.0, 0.2], amplitude=0.05)
    save_model(a, tmp_path / "a.ply")
    save_model(transformed(b, MOTION[0].as_matrix(), MOTION[1]), tmp_path / "b.ply")
    assert main(["stitch", str(tmp_path / "a.ply"), str(tmp_path / "b.ply"), "-o", str(tmp_path / "ab.ply"),
                        "--samples", "32", "--jobs", "1"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["faces"] == len(ellipsoid.faces) + sum(printed["boundaries"])
    mesh = trimesh.load(tmp_path / "ab.ply", process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.visual.vertex_colors[:, 2].max() > 200
    assert main(["stitch", str(tmp_path / "a.ply"), str(tmp_path / "b.ply"), "-o", str(tmp_path / "x.txt")]) == 1
    # registered scans: the known motion is used as given
    inverse = np.eye(4)
    inverse[:3, :3] = MOTION[0].inv().as_matrix()
    inverse[:3, 3] = -MOTION[0].inv().apply(MOTION[1])
    np.savetxt(tmp_path / "motion.txt", inverse)
    assert main(["stitch", str(tmp_path / "a.ply"), str(tmp_path / "b.ply"), "-o", str(tmp_path / "ab.ply"),
                 "--samples", "32", "--motion", str(tmp_path / "motion.txt")]) == 0
    np.testing.assert_allclose(json.loads(capsys.readouterr().out)["rotation"], inverse[:3, :3], atol=1e-6)
    mesh = trimesh.load(tmp_path / "ab.ply", process=False)  # the files' own frames, not recentred ones
    assert mesh.is_watertight and mesh.volume == pytest.approx(as_trimesh(ellipsoid).volume, rel=1e-3)
    for bad, text in (("letters.txt", "1 2\n3 x\n"), ("small.txt", "1 0 0\n0 1 0\n0 0 1\n")):
        (tmp_path / bad).write_text(text)
        assert main(["stitch", str(tmp_path / "a.ply"), str(tmp_path / "b.ply"), "-o", str(tmp_path / "ab.ply"),
                     "--motion", str(tmp_path / bad)]) == 1
        assert f"{bad}: not a 4x4 matrix" in caplog.text


def test_a_cut_leaving_two_loops_is_aligned_by_the_longest_and_closed_at_both():
    torus = model_of(trimesh.creation.torus(major_radius=0.1, minor_radius=0.03, major_sections=48,
                                            minor_sections=16), "torus")
    a, b = split_model(torus, [1.0, 0.0, 0.0], offset=0.05)  # through both sides of the tube: two loops
    assert boundary(a).loops == 2
    rotation, translation = MOTION
    result = stitch(a, transformed(b, rotation.as_matrix(), translation), workers=1, samples=64)
    assert result.loop_pairs == 2 and result.open_loops == 0
    mesh = as_trimesh(result.model)
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume == pytest.approx(as_trimesh(torus).volume, rel=1e-3)


def test_the_closed_part_merges_seams_keeps_the_largest_piece_and_faces_outwards(ellipsoid):
    seamed = ellipsoid.faces.copy()
    copies = len(ellipsoid.vertices) + np.arange(3)  # the first face's corners duplicated, as at a texture seam
    seamed[0] = copies
    vertices = np.vstack([ellipsoid.vertices, ellipsoid.vertices[ellipsoid.faces[0]]])
    speck = trimesh.creation.icosphere(subdivisions=0, radius=0.01)  # a small separate piece
    faces = np.vstack([seamed, speck.faces + len(vertices)])[:, ::-1]  # and everything wound inwards
    vertices = np.vstack([vertices, speck.vertices + 1.0])
    messy = Model.untextured("messy", vertices, faces, (0.0, 0.0, 0.0))
    part = closed_part(messy)
    mesh = as_trimesh(part)
    assert len(part.faces) == len(ellipsoid.faces) and mesh.is_watertight and mesh.volume > 0
    with pytest.raises(StitchError, match="not closed"):
        closed_part(split_model(ellipsoid, [0.0, 1.0, 0.0])[0])
