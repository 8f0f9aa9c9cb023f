"""JASNOM's stitch (thesis 7.4) and the ``stitch`` command, end to end: an ellipsoid cut in two, moved, and
stitched back; welded halves, known motions, bad meshes."""

import logging

import numpy as np
import pytest
import trimesh
from conftest import model_of
from meshes import MOTION, as_trimesh, moved_half, truth, unwelded
from scipy.spatial.transform import Rotation

from heatdata.errors import StitchError
from heatdata.io.models import Model, load_model, transformed
from heatdata.jasnom.boundary import boundary
from heatdata.jasnom.cuts import closed_part, split_model
from heatdata.jasnom.seam import nearest_targets, stitch, strip_faces


@pytest.mark.parametrize("amplitude", [0.0, 0.05])
def test_two_halves_moved_apart_are_aligned_and_welded_closed(ellipsoid, amplitude, tmp_path):
    from heatdata.io.models import save_model

    a, b = moved_half(ellipsoid, [0.3, 1.0, 0.2], amplitude)
    result = stitch(a, b, samples=64)
    expected = truth(*MOTION)
    assert np.degrees(Rotation.from_matrix(result.alignment.rotation @ expected[:3, :3].T).magnitude()) < 1e-6
    np.testing.assert_allclose(result.alignment.translation, expected[:3, 3], atol=1e-9)
    assert result.alignment.cost < 1e-20 and result.alignment.gap < 1e-9
    # the halves share their boundary: its vertices are welded and no strip is left, in the first half's frame
    assert result.welded == len(result.first.loop) and result.strip_faces == 0
    assert len(result.model.faces) == len(ellipsoid.faces) and len(result.model.vertices) == len(ellipsoid.vertices)
    np.testing.assert_array_equal(result.model.vertices[: len(a.vertices)], a.vertices)
    save_model(result.model, tmp_path / "whole.ply")
    for mesh in (as_trimesh(result.model), trimesh.load(tmp_path / "whole.ply")):  # as a user reads it: merged
        assert mesh.is_watertight and mesh.is_winding_consistent
        assert mesh.volume == pytest.approx(as_trimesh(ellipsoid).volume, rel=1e-6)  # PLY stores float32
    assert result.alignment.facing < -0.9
    # both halves' colours are kept
    assert (
        np.isclose(result.model.corner_colors[..., 2], 0.9).any()
        and np.isclose(result.model.corner_colors[..., 0], 0.8).any()
    )


@pytest.mark.parametrize("duplicated", ["every vertex (STL)", "the cut's vertices"])
def test_halves_with_duplicated_vertices_are_welded_and_stitched_exactly(ellipsoid, duplicated, tmp_path):
    a, b = moved_half(ellipsoid, [0.3, 1.0, 0.2])
    cut_vertices = [np.isin(np.arange(len(m.vertices)), boundary(m).loop) for m in (a, b)]
    if duplicated.startswith("every"):
        for half in (a, b):
            trimesh.Trimesh(half.vertices, half.faces, process=False).export(tmp_path / f"{half.name}.stl")
        a, b = (load_model(tmp_path / f"{half.name}.stl", center=False) for half in (a, b))
        assert len(a.vertices) == 3 * len(a.faces)
    else:  # each face keeps its own copy of the cut's vertices, a nanometre apart
        a, b = (unwelded(half, where, 1e-9) for half, where in zip((a, b), cut_vertices, strict=True))
    result = stitch(a, b, samples=64)
    expected = truth(*MOTION)
    assert np.degrees(Rotation.from_matrix(result.alignment.rotation @ expected[:3, :3].T).magnitude()) < 1e-4
    assert result.alignment.cost < 1e-12 and result.open_loops == 0
    mesh = as_trimesh(result.model)
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume == pytest.approx(as_trimesh(ellipsoid).volume, rel=1e-6)
    assert len(result.model.vertices) == len(ellipsoid.vertices)
    assert any("coincident vertices merged" in repair for repair in result.model.repairs)


def test_a_known_motion_is_used_as_given(ellipsoid, caplog):
    a, moved = moved_half(ellipsoid, [0.3, 1.0, 0.2], 0.05)
    inverse = truth(*MOTION)
    result = stitch(a, moved, motion=inverse, samples=64)
    np.testing.assert_allclose(result.alignment.rotation, inverse[:3, :3])
    np.testing.assert_allclose(result.alignment.translation, inverse[:3, 3])
    assert result.alignment.candidates == 1 and np.isnan(result.alignment.runner_up)
    mesh = as_trimesh(result.model)
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume == pytest.approx(as_trimesh(ellipsoid).volume, rel=1e-9)
    # a motion off by a tenth of the size: a gap the strip bridges, still closed
    off = inverse.copy()
    off[:3, 3] += [0.01, 0.0, 0.0]
    bridged = stitch(a, moved, motion=off, samples=64)
    assert bridged.strip_faces > 0 and bridged.welded == 0 and bridged.alignment.edge_cost > 1e-4
    assert as_trimesh(bridged.model).is_watertight and as_trimesh(bridged.model).is_winding_consistent
    # at a given motion, boundaries that do not face each other are a gap to span: a warning, not an error
    caplog.set_level(logging.WARNING, logger="heatdata.jasnom.seam")
    above = transformed(a, np.eye(3), [0.0, 0.05, 0.0])  # a copy of the half, above it: both normals point down
    assert stitch(a, above, motion=np.eye(4), samples=32).alignment.facing > 0.5
    assert "do not face each other across their boundaries at the given motion" in caplog.text
    with pytest.raises(StitchError, match="4x4 rigid transform"):
        stitch(a, moved, motion=np.diag([1.0, -1.0, 1.0, 1.0]))
    with pytest.raises(StitchError, match="4x4 rigid transform"):
        stitch(a, moved, motion=np.eye(3))


def test_the_strip_uses_every_boundary_edge_once_against_its_face(ellipsoid):
    a, b = split_model(ellipsoid, [1.0, 0.2, 0.0])
    b1, b2 = boundary(a), boundary(transformed(b, np.eye(3), [0.01, 0.0, 0.0]))  # a gap to bridge
    targets = nearest_targets(b1, b2)
    faces = strip_faces(b1, b2, targets, offset=len(a.vertices))
    assert len(faces) == len(b1.loop) + len(b2.loop)
    halves = {tuple(e) for f in faces for e in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))}
    for loop, offset in ((b1.loop, 0), (b2.loop, len(a.vertices))):
        for u, v in zip(loop, np.roll(loop, -1), strict=True):
            assert (v + offset, u + offset) in halves  # the reverse of the mesh's own boundary half-edge
    # targets that step back are held, so the strip still walks each loop once
    noisy = targets.copy()
    noisy[::7] = (noisy[::7] + 2) % len(b1.loop)
    assert len(strip_faces(b1, b2, noisy, offset=len(a.vertices))) == len(b1.loop) + len(b2.loop)


def test_bad_meshes_are_clear_errors(ellipsoid, caplog):
    with pytest.raises(StitchError, match="closed"):
        boundary(ellipsoid)
    a, b = split_model(ellipsoid, [0.0, 1.0, 0.0])
    triangle = Model.untextured("triangle", np.eye(3), [[0, 1, 2]], (0.0, 0.0, 0.0))
    assert len(boundary(triangle).loop) == 3
    with pytest.raises(StitchError, match="a boundary of 3 vertices cannot fix a motion"):
        stitch(a, triangle)
    fin = Model(
        name="fin",
        vertices=np.vstack([a.vertices, [[0.0, 0.5, 0.0]]]),
        faces=np.vstack([a.faces, [[a.faces[0, 0], a.faces[0, 1], len(a.vertices)]]]),
        corner_colors=np.concatenate([a.corner_colors, a.corner_colors[:1]]),
        corner_uv=np.concatenate([a.corner_uv, a.corner_uv[:1]]),
        face_texture=np.concatenate([a.face_texture, a.face_texture[:1]]),
    )
    with pytest.raises(StitchError, match="more than two faces"):
        boundary(fin)
    with pytest.raises(StitchError, match="the same mesh"):
        stitch(a, a)
    caplog.set_level(logging.WARNING, logger="heatdata.jasnom.seam")
    mirrored = transformed(a, np.diag([1.0, -1.0, 1.0]), [0.0, 0.0, 0.0])  # the lower half, wound inwards
    mesh = as_trimesh(stitch(a, mirrored, samples=32).model)  # found by the mirrored candidates, then reversed
    assert "wound the other way round the object" in caplog.text and mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume == pytest.approx(as_trimesh(ellipsoid).volume, rel=0.05)  # the mirror of a's triangulation
    stitch(a, transformed(b, np.eye(3) * 0.5, [0.0, 0.0, 0.0]), samples=32)  # a boundary half as long
    assert "lengths differ by a factor 2.00" in caplog.text
    for name in ("alpha", "beta", "gamma", "along"):
        with pytest.raises(StitchError, match=f"{name} must be a finite"):
            stitch(a, b, **{name: np.nan})
    with pytest.raises(StitchError, match="alpha must be a finite positive"):
        stitch(a, b, alpha=0.0)
    with pytest.raises(StitchError, match="one side"):
        split_model(ellipsoid, [0.0, 1.0, 0.0], offset=1.0)


def stitch_command(first: Model, second: Model, folder, *options: str) -> int:
    """``heatdata stitch a.ply b.ply -o ab.ply`` on the two models, saved in ``folder``: its exit status."""
    from heatdata.cli import main
    from heatdata.io.models import save_model

    save_model(first, folder / "a.ply")
    save_model(second, folder / "b.ply")
    return main(["stitch", str(folder / "a.ply"), str(folder / "b.ply"), "-o", str(folder / "ab.ply"), *options])


def test_the_command_writes_a_closed_coloured_mesh_in_the_first_frame(ellipsoid, tmp_path, capsys, caplog):
    import json

    from heatdata.cli import main

    a, b = moved_half(ellipsoid, [0.3, 1.0, 0.2], 0.05)
    a = transformed(a, np.eye(3), [1.0, 2.0, 3.0])  # far from the origin: the output must stay there
    b = transformed(b, np.eye(3), [0.0, 0.0, 0.0])
    assert stitch_command(a, b, tmp_path, "--samples", "32", "--json") == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["faces"] == len(ellipsoid.faces) and printed["mean_gap_of_size"] < 1e-6
    assert printed["cost"] < 1e-12 and printed["runner_up"] > 1e-4 and not printed["ambiguous"]
    assert {"edge_cost", "crossing_cost", "crease_cost", "rotation", "translation"} <= printed.keys()
    mesh = trimesh.load(tmp_path / "ab.ply")
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.visual.vertex_colors[:, 2].max() > 200
    np.testing.assert_allclose(mesh.bounds.mean(axis=0), ellipsoid.center + [1.0, 2.0, 3.0], atol=1e-6)
    (tmp_path / "table").mkdir()
    assert stitch_command(a, b, tmp_path / "table", "--samples", "32") == 0  # without --json: a short table
    table = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in table] == ["model", "motion", "cost", "seam", "verdict", "time"]
    assert table[1].startswith("motion   turn ") and table[1].endswith(" m") and table[4] == "verdict  clear"
    assert main(["stitch", str(tmp_path / "a.ply"), str(tmp_path / "b.ply"), "-o", str(tmp_path / "x.txt")]) == 1
    before = (tmp_path / "a.ply").read_bytes()
    assert main(["stitch", str(tmp_path / "a.ply"), str(tmp_path / "b.ply"), "-o", str(tmp_path / "a.ply")]) == 1
    assert "is also an input of this command" in caplog.text and (tmp_path / "a.ply").read_bytes() == before
    # registered scans: the known motion is used as given
    inverse = truth(*MOTION)
    inverse[:3, 3] += [1.0, 2.0, 3.0]
    np.savetxt(tmp_path / "motion.txt", inverse)
    assert stitch_command(a, b, tmp_path, "--motion", str(tmp_path / "motion.txt"), "--json") == 0
    np.testing.assert_allclose(json.loads(capsys.readouterr().out)["translation"], inverse[:3, 3], atol=1e-6)
    assert trimesh.load(tmp_path / "ab.ply").is_watertight
    for bad, text in (("letters.txt", "1 2\n3 x\n"), ("small.txt", "1 0 0\n0 1 0\n0 0 1\n")):
        (tmp_path / bad).write_text(text)
        assert stitch_command(a, b, tmp_path, "--motion", str(tmp_path / bad)) == 1
        assert f"{bad}: not a 4x4 matrix" in caplog.text


def test_the_command_warns_when_the_answer_is_ambiguous(tmp_path, capsys, caplog):
    cylinder = closed_part(model_of(trimesh.creation.cylinder(radius=0.05, height=0.12, sections=48), "cylinder"))
    a, b = moved_half(cylinder, [0.0, 0.0, 1.0], offset=0.05)
    caplog.set_level(logging.WARNING)
    assert stitch_command(a, b, tmp_path, "--samples", "48") == 0
    assert "verdict  ambiguous (see the warnings above)" in capsys.readouterr().out
    assert "ambiguous: another pose" in caplog.text
    assert trimesh.load(tmp_path / "ab.ply").is_watertight  # a turned cylinder is still the cylinder


def test_a_cut_leaving_two_loops_is_aligned_by_the_longest_and_closed_at_both():
    torus = model_of(
        trimesh.creation.torus(major_radius=0.1, minor_radius=0.03, major_sections=48, minor_sections=16), "torus"
    )
    a, b = split_model(torus, [1.0, 0.0, 0.0], offset=0.05)  # through both sides of the tube: two loops
    assert boundary(a).loops == 2
    rotation, translation = MOTION
    result = stitch(a, transformed(b, rotation.as_matrix(), translation), samples=64)
    assert result.loop_pairs == 2 and result.open_loops == 0
    mesh = as_trimesh(result.model)
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume == pytest.approx(as_trimesh(torus).volume, rel=1e-3)
