"""Views from depth images and organized clouds (heatdata.views.depth): round trips through files, a real range scan,
and every kind of bad input."""

import json
import re
from pathlib import Path

import numpy as np
import open3d as o3d
import pymeshlab
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

import heatdata as hd
from heatdata.experiments.captures import find_captures
from heatdata.experiments.views import capture_view_table
from heatdata.frames.clouds import fit_intrinsics
from heatdata.views.depth import back_project, grid_faces, nearest_readings, pixels_of

FACE = Path(pymeshlab.__file__).parent / "tests/sample_meshes/rangemaps/face000.ply"  # a real range scan


@pytest.fixture(scope="module")
def rendered():
    catalog = hd.read_catalog(hd.embedded_catalog())
    model = hd.load_catalog_model(catalog[catalog["object"] == "beer-mug"].iloc[0])
    return hd.render_view(model, azimuth=30.0, elevation=30.0, distance=1.0, seed=4)


def test_a_grid_of_four_pixels_gives_two_triangles_facing_away_from_the_camera():
    index = np.array([[0, 1], [2, 3]])
    faces = grid_faces(index, np.ones(4), 0.02)
    assert len(faces) == 2
    points = back_project(np.ones((2, 2)), {"fx": 1.0, "fy": 1.0, "cx": 0.0, "cy": 0.0}).reshape(-1, 3)
    normals = np.cross(points[faces[:, 1]] - points[faces[:, 0]], points[faces[:, 2]] - points[faces[:, 0]])
    assert (normals[:, 2] > 0).all()  # away from the camera at the origin
    assert len(grid_faces(index, np.array([1.0, 1.0, 1.0, 1.1]), 0.02)) == 1  # a 10% step cuts one triangle off
    assert len(grid_faces(np.array([[0, 1], [2, -1]]), np.ones(3), 0.02)) == 1


def test_a_rendered_view_written_as_a_depth_png_reads_back_as_the_same_view(rendered, tmp_path):
    hd.write_depth(rendered, tmp_path / "mug.png")
    k = json.loads((tmp_path / "mug.json").read_text())
    assert k == {key: rendered.intrinsics[key] for key in ("fx", "fy", "cx", "cy", "width", "height")}
    back = hd.read_depth(tmp_path / "mug.png", tmp_path / "mug.json")
    assert abs(back.n_vertices - rendered.n_vertices) <= 0.02 * rendered.n_vertices
    assert back.view_id == "mug" and "not segmented" in back.repairs[0]
    # millimetre steps move vertices by at most half a millimetre along their rays
    spec = hd.DescriptorSpec("pvhk", 64, "center", "polar")
    a, b = hd.describe(rendered, [spec])[0].values, hd.describe(back, [spec])[0].values
    assert np.abs(a - b).max() < 0.02 * np.abs(a).max()


def test_colour_and_a_mask_come_from_their_images(rendered, tmp_path):
    hd.write_depth(rendered, tmp_path / "mug.png")
    pixels = np.round(rendered.pixels).astype(int)
    h, w = rendered.intrinsics["height"], rendered.intrinsics["width"]
    rgb = np.zeros((h, w, 3), np.uint8)
    rgb[pixels[:, 1], pixels[:, 0]] = np.round(rendered.colors * 255).astype(np.uint8)
    Image.fromarray(rgb).save(tmp_path / "rgb.png")
    mask = np.zeros((h, w), np.uint8)
    left = pixels[:, 0] < np.median(pixels[:, 0])
    mask[pixels[left, 1], pixels[left, 0]] = 255
    Image.fromarray(mask).save(tmp_path / "mask.png")
    coloured = hd.read_depth(tmp_path / "mug.png", tmp_path / "mug.json", tmp_path / "rgb.png")
    nearest = np.argmin(np.linalg.norm(coloured.vertices[:50, None] - rendered.vertices[None], axis=2), axis=1)
    np.testing.assert_allclose(coloured.colors[:50], rendered.colors[nearest], atol=1 / 255)
    half = hd.read_depth(tmp_path / "mug.png", tmp_path / "mug.json", mask_path=tmp_path / "mask.png")
    assert half.n_vertices < 0.6 * rendered.n_vertices and "segmented by the mask" in half.repairs[0]
    assert (np.round(half.pixels[:, 0]) < np.median(pixels[:, 0])).all()


def test_a_depth_range_cuts_off_what_lies_behind(rendered):
    depth = np.full((rendered.intrinsics["height"], rendered.intrinsics["width"]), np.nan)
    pixels = np.round(rendered.pixels).astype(int)
    depth[pixels[:, 1], pixels[:, 0]] = rendered.vertices[:, 2]
    wall = np.isnan(depth)
    depth[wall] = 2.0  # a wall 2 m away, around the mug
    everything = hd.view_from_depth(depth, rendered.intrinsics)
    assert everything.n_vertices > 10 * rendered.n_vertices  # the wall, joined to nothing, is the largest piece
    near = hd.view_from_depth(depth, rendered.intrinsics, depth_range=(0.5, 1.5), view_id="near")
    assert abs(near.n_vertices - rendered.n_vertices) <= 0.02 * rendered.n_vertices
    assert near.repairs[0].startswith("segmented by depth 0.5-1.5 m")


def test_an_organized_pcd_gives_the_grid_back_with_its_intrinsics(rendered, tmp_path):
    k = rendered.intrinsics
    depth = np.full((k["height"], k["width"]), np.nan)
    pixels = np.round(rendered.pixels).astype(int)
    depth[pixels[:, 1], pixels[:, 0]] = rendered.vertices[:, 2]
    rows = np.flatnonzero(np.isfinite(depth).any(axis=1))
    cols = np.flatnonzero(np.isfinite(depth).any(axis=0))
    window = back_project(depth, k)[rows[0] : rows[-1] + 1, cols[0] : cols[-1] + 1]
    packed = np.full(window.shape[:2], (200 << 16) | (100 << 8) | 50, np.uint32)
    h, w = window.shape[:2]
    header = (
        "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\n"
        f"WIDTH {w}\nHEIGHT {h}\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {w * h}\n"
    )
    table = np.zeros(w * h, [("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("rgb", "<u4")])
    for axis, name in enumerate("xyz"):
        table[name] = window[..., axis].ravel()
    table["rgb"] = packed.ravel()
    (tmp_path / "binary.pcd").write_bytes((header + "DATA binary\n").encode() + table.tobytes())
    lines = [f"{p['x']} {p['y']} {p['z']} {p['rgb']}" for p in table]
    (tmp_path / "ascii.pcd").write_text(header + "DATA ascii\n" + "\n".join(lines) + "\n")
    for name in ("binary.pcd", "ascii.pcd"):
        view = hd.read_organized_cloud(tmp_path / name)
        assert abs(view.n_vertices - rendered.n_vertices) <= 0.02 * rendered.n_vertices
        assert view.intrinsics["fx"] == pytest.approx(k["fx"], rel=1e-4)
        assert view.intrinsics["cx"] == pytest.approx(k["cx"] - cols[0], abs=0.05)  # the window's own origin
        np.testing.assert_allclose(view.colors[0], [200 / 255, 100 / 255, 50 / 255])
    flat = header.replace(f"WIDTH {w}\nHEIGHT {h}", f"WIDTH {w * h}\nHEIGHT 1")
    (tmp_path / "flat.pcd").write_bytes((flat + "DATA binary\n").encode() + table.tobytes())
    with pytest.raises(hd.ViewError, match=r"unorganized cloud \(HEIGHT 1\) has no pixel grid"):
        hd.read_organized_cloud(tmp_path / "flat.pcd")


@pytest.mark.slow
def test_a_real_range_scan_loads_on_its_grid_and_is_described():
    view = hd.read_organized_cloud(FACE, scale=0.001)  # MeshLab's range map of a face, millimetres
    assert view.n_vertices > 80_000 and view.n_components == 1
    assert 0.7 < np.median(view.vertices[:, 2]) < 1.0  # the face is about 0.8 m from the scanner
    assert view.intrinsics["fx"] == pytest.approx(1977.4, rel=1e-3)  # MeshLab's header says 1943: see _read_range_ply
    d = hd.pvhk(view, samples=64)
    assert d.values.shape == (64,) and np.isfinite(d.values).all()


def test_a_view_is_written_as_a_coloured_ply_others_can_open(rendered, tmp_path):
    rendered.to_ply(tmp_path / "view.ply")
    mesh = o3d.io.read_triangle_mesh(str(tmp_path / "view.ply"))
    assert len(mesh.vertices) == rendered.n_vertices and len(mesh.triangles) == len(rendered.faces)
    np.testing.assert_allclose(np.asarray(mesh.vertex_colors), rendered.colors, atol=1 / 255)


def test_bad_depth_input_is_a_clear_error(rendered, tmp_path):
    k = rendered.intrinsics
    depth = np.ones((k["height"], k["width"]))
    with pytest.raises(hd.ViewError, match="no valid pixel"):
        hd.view_from_depth(np.zeros_like(depth), k)
    with pytest.raises(hd.ViewError, match="are for 640x480 but the depth image is 320x240"):
        hd.view_from_depth(np.ones((240, 320)), k)
    with pytest.raises(hd.ViewError, match="the RGB image is"):
        hd.view_from_depth(depth, k, rgb=np.zeros((10, 10, 3), np.uint8))
    with pytest.raises(hd.ViewError, match="the mask is"):
        hd.view_from_depth(depth, k, mask=np.ones((10, 10), bool))
    with pytest.raises(hd.ViewError, match="no valid pixel is left after segmentation"):
        hd.view_from_depth(depth, k, mask=np.zeros_like(depth, bool))
    with pytest.raises(hd.ViewError, match="missing cy"):
        hd.view_from_depth(depth, {key: k[key] for key in ("fx", "fy", "cx", "width", "height")})
    with pytest.raises(hd.ViewError, match="depth_range"):
        hd.view_from_depth(depth, k, depth_range=(2.0, 1.0))
    Image.fromarray(np.ones((k["height"], k["width"]), np.uint8)).save(tmp_path / "eight.png")
    (tmp_path / "k.json").write_text(json.dumps(k))
    with pytest.raises(hd.ViewError, match="must be 16-bit"):
        hd.read_depth(tmp_path / "eight.png", tmp_path / "k.json")
    with pytest.raises(hd.ViewError, match="convert EXR"):
        (tmp_path / "d.exr").write_bytes(b"x")
        hd.read_depth(tmp_path / "d.exr", tmp_path / "k.json")
    (tmp_path / "list.yaml").write_text("- 1\n- 2\n")
    np.save(tmp_path / "d.npy", depth.astype(np.float32))
    with pytest.raises(hd.ViewError, match="must be a mapping"):
        hd.read_depth(tmp_path / "d.npy", tmp_path / "list.yaml")
    np.save(tmp_path / "int.npy", depth.astype(np.int32))
    with pytest.raises(hd.ViewError, match="float metres"):
        hd.read_depth(tmp_path / "int.npy", tmp_path / "k.json")
    rendered.to_ply(tmp_path / "plain.ply")
    with pytest.raises(hd.ViewError, match="no camera element"):
        hd.read_organized_cloud(tmp_path / "plain.ply")
    with pytest.raises(hd.ViewError, match="at least 3 valid points"):
        fit_intrinsics(np.full((2, 2, 3), np.nan))


def test_the_command_writes_a_view_and_a_ply(rendered, tmp_path, capsys, caplog):
    from heatdata.cli import main

    hd.write_depth(rendered, tmp_path / "mug.png")
    assert (
        main(
            [
                "view-from-depth",
                str(tmp_path / "mug.png"),
                "--intrinsics",
                str(tmp_path / "mug.json"),
                "--depth-range",
                "0.5",
                "1.5",
                "-o",
                str(tmp_path / "v.npz"),
                "-o",
                str(tmp_path / "v.ply"),
                "--json",
            ]
        )
        == 0
    )
    printed = json.loads(capsys.readouterr().out)
    assert printed["vertices"] == hd.View.load(tmp_path / "v.npz").n_vertices
    argv = ["view-from-depth", str(tmp_path / "mug.png"), "--intrinsics", str(tmp_path / "mug.json"), "-o"]
    assert main([*argv, str(tmp_path / "w.npz")]) == 0  # without --json: a line a person reads
    assert re.match(rf"\S+w\.npz: {printed['vertices']:,} vertices, [\d,]+ faces, [\d,]+ on the outer boundary",
                    capsys.readouterr().out)  # fmt: skip
    assert (tmp_path / "v.ply").stat().st_size > 10_000
    assert main(["view-from-depth", str(tmp_path / "mug.png"), "-o", str(tmp_path / "v.npz")]) == 1
    assert "needs --intrinsics" in caplog.text
    assert (
        main(["view-from-depth", str(FACE), "--intrinsics", str(tmp_path / "mug.json"), "-o", str(tmp_path / "f.npz")])
        == 1
    )
    assert "carries its own grid" in caplog.text


def test_a_folder_of_captures_is_found_with_its_colour_masks_and_cameras(rendered, tmp_path):
    (tmp_path / "beer-mug").mkdir()
    (tmp_path / "cup").mkdir()
    hd.write_depth(rendered, tmp_path / "beer-mug" / "a.png")  # its own a.json
    hd.write_depth(rendered, tmp_path / "cup" / "b.png", tmp_path / "camera.json")  # the folder's shared camera
    np.save(tmp_path / "cup" / "c.npy", np.full((480, 640), 0.9, np.float32))
    Image.fromarray(np.zeros((480, 640, 3), np.uint8)).save(tmp_path / "cup" / "b.rgb.png")
    Image.fromarray(np.full((480, 640), 255, np.uint8)).save(tmp_path / "cup" / "b.mask.png")
    found = find_captures(tmp_path)
    assert [(c["object"], c["name"]) for c in found] == [("beer-mug", "a"), ("cup", "b"), ("cup", "c")]
    assert found[0]["intrinsics"].endswith("beer-mug/a.json") and found[1]["intrinsics"].endswith("/camera.json")
    assert found[1]["rgb"].endswith("b.rgb.png") and found[1]["mask"].endswith("b.mask.png")
    assert found[0]["rgb"] == found[2]["mask"] == ""
    frame = capture_view_table([c for c in found if c["object"] == "cup"], "mug", depth_range=[0.5, 1.5])
    assert list(frame["view_id"]) == ["cup/capture/b", "cup/capture/c"] and set(frame["split"]) == {"test"}
    assert set(frame["label"]) == {"mug"} and frame["n_vertices"].iloc[1] == 640 * 480  # a flat wall at 0.9 m
    (tmp_path / "camera.json").unlink()
    with pytest.raises(hd.ViewError, match="b.png: no intrinsics"):
        find_captures(tmp_path)
    with pytest.raises(hd.ViewError, match="no capture"):
        find_captures(tmp_path / "beer-mug")
    with pytest.raises(hd.ViewError, match="no such folder"):
        find_captures(tmp_path / "none")


def test_pixels_of_rounds_the_projection_and_says_which_land_inside():
    k = {"fx": 100.0, "fy": 100.0, "cx": 2.0, "cy": 1.0, "width": 5, "height": 3}
    points = np.array([[0.0, 0.0, 1.0], [0.024, 0.006, 2.0], [1.0, 0.0, 1.0], [0.0, 0.0, -1.0]])
    pixel, inside = pixels_of(points, k)
    assert inside.tolist() == [True, True, False, False]
    assert pixel.tolist() == [[2, 1], [3, 1], [0, 0], [0, 0]]


def test_nearest_readings_take_the_smallest_depth_in_the_window_and_nan_where_there_is_none():
    depth = np.full((5, 7), np.nan)
    depth[2, 1], depth[2, 2] = 2.0, 1.5
    nearest = nearest_readings(depth, 3)
    assert nearest[2, 0] == 2.0 and nearest[1, 1] == 1.5 and nearest[3, 3] == 1.5
    assert np.isnan(nearest[2, 4]) and np.isnan(nearest[0, 6])
    assert np.array_equal(nearest_readings(np.full((4, 4), 0.7), 5), np.full((4, 4), 0.7))


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("meta.yml", "INTRINSICS: [600.0, 0.0, 320.5, 0.0, 601.0, 240.5,\n  0.0, 0.0, 1.0]\n"),  # YCB-Video's meta
        ("scene_camera.json", '{"cam_K": [600.0, 0, 320.5, 0, 601.0, 240.5, 0, 0, 1], "depth_scale": 1.0}'),  # BOP
        ("k.yaml", "K: [[600.0, 0, 320.5], [0, 601.0, 240.5], [0, 0, 1]]\nwidth: 64\nheight: 48\n"),
    ],
)
def test_intrinsics_are_read_from_a_camera_matrix_the_image_giving_the_size(tmp_path, name, text):
    from heatdata.views.depth import read_intrinsics

    (tmp_path / name).write_text(text)
    k = read_intrinsics(tmp_path / name, (48, 64))
    assert k == {"fx": 600.0, "fy": 601.0, "cx": 320.5, "cy": 240.5, "width": 64, "height": 48}
    if name != "k.yaml":
        with pytest.raises(hd.ViewError, match=f"{name}: a camera matrix carries no image size"):
            read_intrinsics(tmp_path / name)


@pytest.mark.parametrize(
    ("matrix", "message"),
    [
        ("[600, 0, 320, 0, 600, 240, 0, 0]", "nine numbers, row-major; got 8"),
        ("[600, 2, 320, 0, 600, 240, 0, 0, 1]", r"\[\[fx 0 cx\] \[0 fy cy\] \[0 0 1\]\]"),
        ("[600, 0, 320, 0, 600, 240, 0, 0, 2]", r"\[\[fx 0 cx\]"),
        ("[a, 0, 320, 0, 600, 240, 0, 0, 1]", "nine numbers"),
        ("[.nan, 0, 320, 0, 600, 240, 0, 0, 1]", "not finite"),
        ("[-600, 0, 320, 0, 600, 240, 0, 0, 1]", "a focal length in pixels is > 0"),
    ],
)
def test_a_bad_camera_matrix_is_refused_in_one_line(tmp_path, matrix, message):
    from heatdata.views.depth import read_intrinsics

    (tmp_path / "meta.yml").write_text(f"INTRINSICS: {matrix}\n")
    with pytest.raises(hd.ViewError, match=message):
        read_intrinsics(tmp_path / "meta.yml", (480, 640))


def test_a_depth_png_reads_with_a_camera_matrix_beside_it(rendered, tmp_path):
    k = rendered.intrinsics
    depth = np.zeros((k["height"], k["width"]), np.uint16)
    pixels = np.round(rendered.pixels).astype(int)
    depth[pixels[:, 1], pixels[:, 0]] = np.round(rendered.vertices[:, 2] * 1000).astype(np.uint16)
    Image.fromarray(depth).save(tmp_path / "d.png")
    matrix = [k["fx"], 0, k["cx"], 0, k["fy"], k["cy"], 0, 0, 1]
    (tmp_path / "meta.yml").write_text(f"INTRINSICS: {matrix}\n")
    view = hd.read_depth(tmp_path / "d.png", tmp_path / "meta.yml")
    assert view.intrinsics == k and len(view.vertices) > 100


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 24), st.integers(1, 24), st.sampled_from([1, 3, 5]), st.floats(0.0, 1.0), st.integers(0, 2**31))
def test_nearest_readings_over_the_readings_box_equal_the_filter_over_the_whole_image(h, w, size, share, seed):
    from scipy.ndimage import minimum_filter

    rng = np.random.default_rng(seed)
    depth = np.where(rng.random((h, w)) < share, rng.uniform(0.3, 3.0, (h, w)), np.nan)
    whole = minimum_filter(np.where(np.isfinite(depth), depth, np.inf), size=size, mode="constant", cval=np.inf)
    assert np.array_equal(nearest_readings(depth, size), np.where(np.isfinite(whole), whole, np.nan), equal_nan=True)
