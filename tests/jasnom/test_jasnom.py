"""JASNOM (thesis ch. 7) on meshes with known answers: an ellipsoid cut in two, moved, and stitched back."""

import logging

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from heatdata.errors import StitchError
from heatdata.io.models import Model, load_model, transformed
from heatdata.jasnom.align import align, alignment_at
from heatdata.jasnom.boundary import boundaries, boundary, resample_loop
from heatdata.jasnom.cost import ScanSurface
from heatdata.jasnom.cuts import closed_part, split_model
from heatdata.jasnom.seam import nearest_targets, stitch, strip_faces

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


def truth(rotation: Rotation, translation: np.ndarray) -> np.ndarray:
    """The 4x4 inverse of the motion that moved the second half: what JASNOM must find."""
    inverse = np.eye(4)
    inverse[:3, :3] = rotation.inv().as_matrix()
    inverse[:3, 3] = -rotation.inv().apply(translation)
    return inverse


def moved_half(model: Model, normal, amplitude: float = 0.0, offset: float = 0.0) -> tuple[Model, Model]:
    a, b = split_model(model, normal, amplitude=amplitude, offset=offset)
    return a, transformed(b, MOTION[0].as_matrix(), MOTION[1])


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


def unwelded(model: Model, where: np.ndarray, noise: float = 0.0) -> Model:
    """``model`` with each face given its own copy of the vertices in ``where`` (a mask), moved by up to
    ``noise``: the duplicated vertices an STL file or a cutting tool leaves."""
    faces = model.faces.copy()
    vertices = [model.vertices]
    count = len(model.vertices)
    rng = np.random.default_rng(1)
    for f, c in zip(*np.nonzero(where[model.faces]), strict=True):
        vertices.append(model.vertices[faces[f, c]][None] + rng.uniform(-noise, noise, (1, 3)))
        faces[f, c] = count
        count += 1
    return Model.untextured(model.name, np.vstack(vertices), faces, model.corner_colors)


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


def test_a_symmetric_boundary_is_reported_ambiguous_and_an_asymmetric_one_is_not():
    cylinder = model_of(trimesh.creation.cylinder(radius=0.05, height=0.12, sections=48), "cylinder")
    a, b = moved_half(closed_part(cylinder), [0.0, 0.0, 1.0], offset=0.05)
    assert align(boundaries(a), boundaries(b), samples=48).ambiguous  # a circle fits at every turn
    egg = trimesh.creation.icosphere(subdivisions=3)
    egg = model_of(trimesh.Trimesh(egg.vertices * [0.12, 0.09, 0.07] * (1 + 0.1 * egg.vertices[:, [0]]), egg.faces))
    a, b = moved_half(egg, [0.3, 1.0, 0.2])
    found = align(boundaries(a), boundaries(b), samples=48)
    assert not found.ambiguous and found.runner_up > 100 * found.cost


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


def test_resampling_is_uniform_by_arc_length_and_interpolates_normals():
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    normals = np.array([[0, -1, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0]], dtype=float)
    points, between = resample_loop(square, 8, normals)
    np.testing.assert_allclose(np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1), 0.5)
    np.testing.assert_allclose(between[1], [np.sqrt(0.5), -np.sqrt(0.5), 0.0])  # half-way from the first to the next
    assert resample_loop(square, 4)[1] is None
    with pytest.raises(StitchError, match="at least 3 samples"):
        resample_loop(square, 2)


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


def test_a_boundary_that_pinches_is_split_into_loops_that_visit_each_vertex_once():
    bowtie = Model.untextured(
        "bowtie", [[0, 0, 0], [1, 0, 0], [1, 1, 0], [-1, 0, 0], [-1, -1, 0]], [[0, 1, 2], [0, 3, 4]], (0.5, 0.5, 0.5)
    )  # two triangles that share a corner
    loops = boundaries(bowtie)
    assert sorted(sorted(b.loop.tolist()) for b in loops) == [[0, 1, 2], [0, 3, 4]]
    assert all(b.loops == 2 for b in loops)


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


def test_the_command_writes_a_closed_coloured_mesh_in_the_first_frame(ellipsoid, tmp_path, capsys, caplog):
    import json

    from heatdata.cli import main
    from heatdata.io.models import save_model

    a, b = moved_half(ellipsoid, [0.3, 1.0, 0.2], 0.05)
    a = transformed(a, np.eye(3), [1.0, 2.0, 3.0])  # far from the origin: the output must stay there
    b = transformed(b, np.eye(3), [0.0, 0.0, 0.0])
    save_model(a, tmp_path / "a.ply")
    save_model(b, tmp_path / "b.ply")
    assert (
        main(
            [
                "stitch",
                str(tmp_path / "a.ply"),
                str(tmp_path / "b.ply"),
                "-o",
                str(tmp_path / "ab.ply"),
                "--samples",
                "32",
            ]
        )
        == 0
    )
    printed = json.loads(capsys.readouterr().out)
    assert printed["faces"] == len(ellipsoid.faces) and printed["mean_gap_of_size"] < 1e-6
    assert printed["cost"] < 1e-12 and printed["runner_up"] > 1e-4 and not printed["ambiguous"]
    assert {"edge_cost", "crossing_cost", "crease_cost", "rotation", "translation"} <= printed.keys()
    mesh = trimesh.load(tmp_path / "ab.ply")
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.visual.vertex_colors[:, 2].max() > 200
    np.testing.assert_allclose(mesh.bounds.mean(axis=0), ellipsoid.center + [1.0, 2.0, 3.0], atol=1e-6)
    assert main(["stitch", str(tmp_path / "a.ply"), str(tmp_path / "b.ply"), "-o", str(tmp_path / "x.txt")]) == 1
    before = (tmp_path / "a.ply").read_bytes()
    assert main(["stitch", str(tmp_path / "a.ply"), str(tmp_path / "b.ply"), "-o", str(tmp_path / "a.ply")]) == 1
    assert "is also an input of this command" in caplog.text and (tmp_path / "a.ply").read_bytes() == before
    # registered scans: the known motion is used as given
    inverse = truth(*MOTION)
    inverse[:3, 3] += [1.0, 2.0, 3.0]
    np.savetxt(tmp_path / "motion.txt", inverse)
    assert (
        main(
            [
                "stitch",
                str(tmp_path / "a.ply"),
                str(tmp_path / "b.ply"),
                "-o",
                str(tmp_path / "ab.ply"),
                "--motion",
                str(tmp_path / "motion.txt"),
            ]
        )
        == 0
    )
    np.testing.assert_allclose(json.loads(capsys.readouterr().out)["translation"], inverse[:3, 3], atol=1e-6)
    assert trimesh.load(tmp_path / "ab.ply").is_watertight
    for bad, text in (("letters.txt", "1 2\n3 x\n"), ("small.txt", "1 0 0\n0 1 0\n0 0 1\n")):
        (tmp_path / bad).write_text(text)
        assert (
            main(
                [
                    "stitch",
                    str(tmp_path / "a.ply"),
                    str(tmp_path / "b.ply"),
                    "-o",
                    str(tmp_path / "ab.ply"),
                    "--motion",
                    str(tmp_path / bad),
                ]
            )
            == 1
        )
        assert f"{bad}: not a 4x4 matrix" in caplog.text


def test_the_command_warns_when_the_answer_is_ambiguous(tmp_path, capsys, caplog):
    import json

    from heatdata.cli import main
    from heatdata.io.models import save_model

    cylinder = closed_part(model_of(trimesh.creation.cylinder(radius=0.05, height=0.12, sections=48), "cylinder"))
    a, b = moved_half(cylinder, [0.0, 0.0, 1.0], offset=0.05)
    save_model(a, tmp_path / "a.ply")
    save_model(b, tmp_path / "b.ply")
    caplog.set_level(logging.WARNING)
    assert (
        main(
            [
                "stitch",
                str(tmp_path / "a.ply"),
                str(tmp_path / "b.ply"),
                "-o",
                str(tmp_path / "ab.ply"),
                "--samples",
                "48",
            ]
        )
        == 0
    )
    assert json.loads(capsys.readouterr().out)["ambiguous"] and "ambiguous: another pose" in caplog.text
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


def test_a_scan_faces_its_own_camera_and_not_the_opposite_one():
    cap = trimesh.creation.icosphere(subdivisions=3, radius=0.1)
    keep = cap.triangles_center[:, 2] < 0  # the half a camera at the origin sees of a ball 1 m ahead
    scan = Model.untextured("scan", cap.vertices + [0.0, 0.0, 1.0], cap.faces[keep][:, ::-1], (0.5, 0.5, 0.5))
    surface = ScanSurface.of(scan)
    assert surface.toward_camera == -1.0  # wound away from its camera, as heatdata's views are
    assert surface.faces_camera(np.eye(3), np.zeros(3), np.zeros(3)) > 0.85  # all but the faces near the limb
    turned = Rotation.from_rotvec([0.0, np.pi, 0.0]).as_matrix()  # the back of the ball, seen from the same camera
    assert surface.faces_camera(turned, [0.0, 0.0, 2.0] - turned @ [0.0, 0.0, 1.0], np.zeros(3)) < 0.15


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


def test_the_workflow_schema_defaults_are_the_library_defaults():
    import inspect
    from pathlib import Path

    import yaml

    schema = yaml.safe_load((Path(__file__).parents[2] / "workflow/schemas/config.schema.yaml").read_text())
    keys = schema["properties"]["stitch"]["properties"]
    signature = inspect.signature(stitch).parameters
    for name in ("alpha", "beta", "gamma", "samples"):
        assert keys[name]["default"] == signature[name].default, name
    for name in ("along", "robust"):  # unset: the library chooses by the kind of input (cuts or scans)
        assert "default" not in keys[name] and signature[name].default is None
    assert keys["pairs"]["items"]["properties"]["scans"]["default"] is signature["scans"].default
