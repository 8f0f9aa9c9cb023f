"""Loading models in every supported format, and every kind of bad file."""

import numpy as np
import pytest
from conftest import colored_box, write_textured_quad

import heatdata as hd
from heatdata.errors import ModelError
from heatdata.io.models import Model, load_model


def test_obj_with_mtl_and_texture(tmp_path):
    model = hd.load_model(write_textured_quad(tmp_path))
    assert len(model.textures) == 1 and model.textures[0].shape == (4, 4, 3)
    assert np.all(model.face_texture == 0)
    assert model.corner_uv.shape == (2, 3, 2)


@pytest.mark.parametrize("suffix", ["ply", "stl", "off", "glb"])
def test_other_formats(tmp_path, suffix):
    path = tmp_path / f"box.{suffix}"
    colored_box().export(path)
    model = hd.load_model(path, name="box", label="cube")
    assert len(model.faces) == 12
    assert np.allclose(model.extents, 0.2, atol=1e-6)
    assert model.name == "box" and model.label == "cube"
    if suffix in ("ply", "glb"):
        assert np.allclose(model.corner_colors[0, 0], np.array([200, 50, 50]) / 255, atol=0.02)


def test_size_and_scale(tmp_path):
    path = tmp_path / "box.ply"
    colored_box((20.0, 10.0, 5.0)).export(path)  # centimetres
    assert np.allclose(hd.load_model(path, scale=0.01).extents, [0.2, 0.1, 0.05])
    assert np.allclose(hd.load_model(path, size=(0.3, 0.3, 0.3)).extents, 0.3)
    assert np.allclose(hd.load_model(path).center, 0.0)
    moved = colored_box((20.0, 10.0, 5.0))
    moved.apply_translation([100.0, 0.0, -50.0])
    moved.export(path)
    assert np.allclose(hd.load_model(path, scale=0.01).center, 0.0)
    assert np.allclose(hd.load_model(path, scale=0.01, center=False).center, [1.0, 0.0, -0.5])  # the file's frame


def test_missing_file(tmp_path):
    with pytest.raises(hd.ModelError, match="no such model file"):
        hd.load_model(tmp_path / "nothing.obj")


@pytest.mark.parametrize(
    "name, content, message",
    [
        ("model.fbx", b"x", "unsupported"),
        ("empty.ply", b"", "empty"),
        ("points.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no triangle faces"),
        ("nan.obj", b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "NaN"),
    ],
)
def test_bad_files(tmp_path, name, content, message):
    path = tmp_path / name
    path.write_bytes(content)
    with pytest.raises(hd.ModelError, match=message):
        hd.load_model(path)


@pytest.mark.parametrize("suffix", ["ply", "glb", "stl"])
def test_corrupt_file(tmp_path, suffix):
    path = tmp_path / f"corrupt.{suffix}"
    path.write_bytes(bytes(np.random.default_rng(0).integers(0, 256, 500, dtype=np.uint8)))
    with pytest.raises(hd.ModelError, match=str(path.name)):
        hd.load_model(path)


@pytest.mark.parametrize(
    "texture, note",
    [
        ("../secret.png", "refused '../secret.png'"),
        ("/etc/passwd", "refused '/etc/passwd'"),
        ("../../../../etc/passwd", "refused '../../../../etc/passwd'"),
        ("nothere.png", "missing 'nothere.png'"),
    ],
)
def test_textures_outside_the_model_folder_are_refused_and_recorded(tmp_path, caplog, texture, note):
    """A model's MTL is untrusted: nothing outside the model's folder is read, and the view says what it lacks."""
    folder = tmp_path / "model"
    folder.mkdir()
    obj = write_textured_quad(folder)
    (tmp_path / "secret.png").write_bytes((folder / "tex.png").read_bytes())  # readable if the path escaped
    (folder / "quad.mtl").write_text(f"newmtl skin\nKd 1 0 0\nmap_Kd {texture}\n")
    model = hd.load_model(obj)
    assert model.textures == [] and np.allclose(model.corner_colors, [1, 0, 0])  # the Kd colour
    assert len(model.repairs) == 1 and note in model.repairs[0] and note in caplog.text
    view = hd.render_view(hd.load_model(obj, size=(0.2, 0.2, 0.0)), 0.0, 0.0, 1.0, noise=False)
    assert any(note in r for r in view.repairs)


def test_a_hue_rotated_twin_turns_colours_and_textures_and_keeps_greys_and_the_mesh():
    from heatdata.io.models import hue_rotated

    red = np.array([0.8, 0.1, 0.1], np.float32)
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    model = hd.Model(
        name="tile",
        vertices=np.eye(4, 3),
        faces=faces,
        corner_colors=np.stack([np.tile(red, (3, 1)), np.full((3, 3), 0.5, np.float32)]),
        corner_uv=np.zeros((2, 3, 2), np.float32),
        face_texture=np.array([-1, 0], np.int32),
        textures=[np.tile(red, (2, 2, 1))],
    )
    twin = hue_rotated(model, 120.0)
    np.testing.assert_allclose(twin.corner_colors[0, 0], [0.1, 0.8, 0.1], atol=1e-6)  # red -> green
    np.testing.assert_allclose(twin.corner_colors[1], 0.5)  # grey stays grey
    np.testing.assert_allclose(twin.textures[0][0, 0], [0.1, 0.8, 0.1], atol=1e-6)
    assert twin.vertices is model.vertices and twin.name == "tile-hue120"
    np.testing.assert_allclose(hue_rotated(model, 360.0).corner_colors, model.corner_colors, atol=1e-6)
    np.testing.assert_allclose(model.corner_colors[0, 0], red)  # the original is left alone
    with pytest.raises(hd.ModelError, match="finite"):
        hue_rotated(model, float("nan"))


def test_an_untextured_model_has_one_colour_or_its_corners_and_no_texture():
    grey = hd.Model.untextured("tri", np.eye(3), [[0, 1, 2]])
    np.testing.assert_allclose(grey.corner_colors, 0.7)
    assert grey.face_texture.tolist() == [-1] and grey.corner_uv.shape == (1, 3, 2) and grey.textures == []
    corners = np.random.default_rng(0).random((1, 3, 3))
    coloured = hd.Model.untextured("tri", np.eye(3), [[0, 1, 2]], corners, label="tile")
    np.testing.assert_allclose(coloured.corner_colors, corners.astype(np.float32))
    assert coloured.label == "tile" and coloured.faces.dtype == np.int64


def test_an_stl_box_is_welded_to_its_eight_corners_with_its_colours_kept(tmp_path, caplog):
    from heatdata.io.models import welded

    path = tmp_path / "box.stl"
    colored_box().export(path)
    model = hd.load_model(path)
    assert len(model.vertices) == 36  # STL: three vertices of its own per triangle
    model = hd.Model.untextured(model.name, model.vertices, model.faces, np.random.default_rng(0).random((12, 3, 3)))
    with caplog.at_level("INFO"):
        merged = welded(model)
    assert len(merged.vertices) == 8 and len(merged.faces) == 12
    np.testing.assert_allclose(merged.vertices[merged.faces], model.vertices[model.faces])
    np.testing.assert_array_equal(merged.corner_colors, model.corner_colors)
    assert merged.repairs == [merged.repairs[0]] and "28 coincident vertices merged" in merged.repairs[0]
    assert "28 coincident vertices merged" in caplog.text
    assert welded(merged) is merged  # nothing left to merge: the model itself


def test_welding_drops_the_faces_it_collapses_and_second_copies():
    from heatdata.io.models import welded

    # a square of two triangles, a sliver whose two corners are one point, and the first triangle again
    vertices = [[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [1, 0, 1e-6], [0, 0, 1e-7]]
    faces = [[0, 1, 2], [0, 2, 3], [0, 1, 4], [5, 1, 2]]
    merged = welded(hd.Model.untextured("square", vertices, faces))
    np.testing.assert_array_equal(merged.faces, [[0, 1, 2], [0, 2, 3]])
    assert len(merged.vertices) == 4 and merged.corner_colors.shape == (2, 3, 3)
    assert "2 face(s) this collapsed or repeated dropped" in merged.repairs[-1]


def test_colour_is_known_from_a_texture_or_a_colour_other_than_the_untextured_grey():
    from heatdata.io.models import DEFAULT_GREY

    vertices, faces = np.eye(3), np.array([[0, 1, 2]])
    assert not Model.untextured("scan", vertices, faces).coloured
    assert not Model.untextured("scan", vertices, faces, DEFAULT_GREY).coloured
    assert Model.untextured("red", vertices, faces, (0.9, 0.1, 0.1)).coloured
    assert Model.untextured("grey", vertices, faces, (0.5, 0.5, 0.5)).coloured


def test_a_z_up_file_is_turned_to_stand_on_y_without_a_mirror(tmp_path):
    import trimesh

    mesh = trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [0, 2, 0], [0, 0, 3]], [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    mesh.export(tmp_path / "t.ply")
    y_up = load_model(tmp_path / "t.ply", center=False)
    z_up = load_model(tmp_path / "t.ply", up_axis="z", center=False)
    assert np.allclose(z_up.vertices[:, 0], y_up.vertices[:, 0])
    assert np.allclose(z_up.vertices[:, 1], y_up.vertices[:, 2])  # up is the file's z
    assert np.allclose(z_up.vertices[:, 2], -y_up.vertices[:, 1])
    volume = trimesh.Trimesh(z_up.vertices, z_up.faces).volume
    assert volume == pytest.approx(trimesh.Trimesh(y_up.vertices, y_up.faces).volume)  # not mirrored
    with pytest.raises(ModelError, match="up_axis must be one of y, z, got 'x'"):
        load_model(tmp_path / "t.ply", up_axis="x")
