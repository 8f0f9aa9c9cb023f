"""Untrusted input, round 2 (issue 31): one section per class of what went wrong.

Resources are bounded, face indices are checked before native code, no command writes over its inputs or leaves
a half file, nothing wrong is returned silently, and every failure is one line with exit 1 or 2.
"""

import json
import os
import subprocess
import sys
import tracemalloc
import zipfile
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import trimesh
from conftest import ROOT, grid_mesh, make_sh3f, write_textured_quad
from PIL import Image

import heatdata as hd
from heatdata.cli import main
from heatdata.frames.clouds import read_organized_cloud
from heatdata.io import files
from heatdata.io.sh3f import MAX_MEMBER_BYTES, sh3f_catalog, sh3f_entries
from heatdata.io.tables import DESCRIPTOR_SCHEMA, write_table
from heatdata.views.depth import read_depth, read_intrinsics, write_depth

KINECT = {"fx": 580.0, "fy": 580.0, "cx": 319.5, "cy": 239.5, "width": 640, "height": 480}
RANGE_MAP = Path(__import__("pymeshlab").__file__).parent / "tests/sample_meshes/rangemaps/face000.ply"


def written_bytes(folder: Path) -> int:
    return sum(p.stat().st_size for p in folder.rglob("*") if p.is_file())


def add_member(sh3f: Path, name: str, megabytes: int, byte: bytes = b"\0") -> None:
    """Append a member of ``megabytes`` MB of one byte, written in chunks (a zip bomb costs the test little)."""
    with zipfile.ZipFile(sh3f, "a", zipfile.ZIP_DEFLATED) as archive, archive.open(name, "w", force_zip64=True) as out:
        for _ in range(megabytes):
            out.write(byte * 2**20)


def one_line_error(caplog, *needles: str) -> None:
    errors = [r for r in caplog.records if r.levelname == "ERROR"]
    assert len(errors) == 1 and "\n" not in errors[0].getMessage(), [r.getMessage() for r in errors]
    for needle in needles:
        assert needle in errors[0].getMessage()


@pytest.fixture
def box(tmp_path) -> Path:
    path = tmp_path / "box.ply"
    trimesh.creation.box(extents=(0.2, 0.1, 0.15)).export(path)
    return path


# -- 1. resources -------------------------------------------------------------------------------------------


def test_an_sh3f_model_folder_with_a_bomb_extracts_only_what_the_model_needs(tmp_path):
    """A 200 MB member of zeros next to the model used to be written out whole (201 MB, exit 0)."""
    sh3f = make_sh3f(tmp_path)
    add_member(sh3f, "mini/mug/padding.bin", 200)
    assert sh3f.stat().st_size < 1_000_000
    out = tmp_path / "models"
    tracemalloc.start()
    hd.import_sh3f(sh3f, out, name_pattern="mug")
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert written_bytes(out) < 100_000 and peak < 20 * 2**20
    assert sorted(p.name for p in (out / "mini/mug").iterdir()) == ["quad.mtl", "quad.obj", "tex.png"]


@pytest.mark.parametrize(
    "member, megabytes, message",
    [
        ("mini/mug/quad.obj", 2, "compressed"),  # the ratio cap: 2 MB of zeros
        ("mini/mug/tex.png", MAX_MEMBER_BYTES // 2**20 + 1, "above the cap"),  # the size cap
    ],
)
def test_a_bomb_the_model_needs_is_refused_in_one_line(tmp_path, caplog, member, megabytes, message):
    sh3f = tmp_path / "Bomb.sh3f"
    with zipfile.ZipFile(make_sh3f(tmp_path)) as source, zipfile.ZipFile(sh3f, "w", zipfile.ZIP_DEFLATED) as out:
        for item in source.infolist():
            if item.filename != member:
                out.writestr(item, source.read(item))
    add_member(sh3f, member, megabytes)
    out = tmp_path / "models"
    assert main(["import-sh3f", str(sh3f), str(out), "--names", "mug"]) == 1
    one_line_error(caplog, member, message)
    assert written_bytes(out) < 100_000


def test_an_oversized_properties_file_is_refused_before_it_is_read(tmp_path):
    """A 200 MB PluginFurnitureCatalog.properties used to be read whole (870 MB peak)."""
    sh3f = tmp_path / "Huge.sh3f"
    with zipfile.ZipFile(sh3f, "w", zipfile.ZIP_DEFLATED) as archive:
        with archive.open("PluginFurnitureCatalog.properties", "w", force_zip64=True) as out:
            for k in range(40):  # 40 MB of comments: above the cap of 16 MB, under the ratio cap's reach
                out.write(b"".join(b"# %07d %s\n" % (j, os.urandom(20).hex().encode()) for j in range(16_000)))
    tracemalloc.start()
    with pytest.raises(hd.ModelError, match="above the cap"):
        sh3f_entries(sh3f)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 10 * 2**20


def write_texture_model(folder: Path, image: Image.Image | bytes, name: str = "tex.png") -> Path:
    obj = write_textured_quad(folder)
    if isinstance(image, bytes):
        (folder / name).write_bytes(image)
    else:
        image.save(folder / name)
    (folder / "quad.mtl").write_text(f"newmtl skin\nKd 0.2 0.4 0.6\nmap_Kd {name}\n")
    return obj


def peak_rss_of(code: str) -> int:
    """Peak resident memory (bytes) of a fresh Python running ``code`` after importing heatdata."""
    script = f"import resource, heatdata as hd\n{code}\nprint(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)"
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True)
    return int(result.stdout.split()[-1]) * 1024


@pytest.mark.parametrize("container", ["obj", "glb"])
def test_a_texture_bomb_is_refused_before_it_is_decoded(tmp_path, container):
    """An 8000 x 8000 PNG of ~200 kB cost 2.1 GB in load_model, with no note (a GLB's embedded one too)."""
    if container == "obj":
        model_path = write_texture_model(tmp_path, Image.new("RGB", (8000, 8000)))
        assert (tmp_path / "tex.png").stat().st_size < 300_000
    else:
        box = trimesh.creation.box()
        material = trimesh.visual.material.PBRMaterial(baseColorTexture=Image.new("RGB", (8000, 8000)))
        box.visual = trimesh.visual.TextureVisuals(uv=np.zeros((len(box.vertices), 2)), material=material)
        model_path = tmp_path / "bomb.glb"
        box.export(model_path)
    (tmp_path / "small").mkdir()
    baseline = peak_rss_of(f"hd.load_model({str(write_textured_quad(tmp_path / 'small'))!r})")
    peak = peak_rss_of(f"m = hd.load_model({str(model_path)!r}); assert not m.textures, m.repairs")
    assert peak - baseline < 50 * 2**20
    model = hd.load_model(model_path)
    assert not model.textures and any("8000x8000" in r and "refused" in r for r in model.repairs)
    if container == "obj":
        assert np.allclose(model.corner_colors[0, 0], [0.2, 0.4, 0.6])  # the material's colour stands in


def test_a_large_texture_is_downscaled_with_a_note(tmp_path):
    obj = write_texture_model(tmp_path, Image.new("RGB", (3000, 2000), (255, 0, 0)))
    model = hd.load_model(obj)
    (texture,) = model.textures
    assert texture.shape == (1000, 1500, 3) and np.allclose(texture[0, 0], [1, 0, 0])
    assert any("3000x2000" in r and "downscaled 2x" in r for r in model.repairs)


def test_many_materials_on_large_textures_stop_at_a_total_cap(tmp_path):
    """Each material decodes its own copy: 200 materials on one 4096 x 2048 texture would hold 6.7 GB."""
    obj = write_texture_model(tmp_path, Image.new("RGB", (4096, 2048)))
    materials = "".join(f"newmtl m{k}\nKd 0.2 0.4 0.6\nmap_Kd tex.png\n" for k in range(200))
    (tmp_path / "quad.mtl").write_text(materials)
    faces = "".join(f"usemtl m{k}\nf 1/1 2/2 3/3\n" for k in range(200))
    obj.write_text(obj.read_text().split("usemtl")[0] + faces)
    baseline = peak_rss_of("pass")
    peak = peak_rss_of(f"m = hd.load_model({str(obj)!r})")
    assert peak - baseline < 600 * 2**20  # 417 MB measured: 8 textures decoded, downscaled to 2048 x 1024
    model = hd.load_model(obj)
    assert any("together" in r for r in model.repairs) and len(model.textures) <= 8


@pytest.mark.parametrize("kind", ["garbage", "truncated", "nul in the name"])
def test_a_texture_that_cannot_be_read_leaves_a_repairs_note(tmp_path, kind):
    if kind == "nul in the name":
        obj = write_textured_quad(tmp_path)
        (tmp_path / "quad.mtl").write_text("newmtl skin\nKd 0.2 0.4 0.6\nmap_Kd te\0x.png\n")
    else:
        Image.fromarray(np.random.default_rng(0).integers(0, 255, (64, 64, 3), dtype=np.uint8)).save(tmp_path / "t.png")
        good = (tmp_path / "t.png").read_bytes()
        data = b"\x89PNG\r\n\x1a\n" + os.urandom(200) if kind == "garbage" else good[: len(good) // 2]
        obj = write_texture_model(tmp_path, data)
    model = hd.load_model(obj)
    assert not model.textures and len(model.repairs) == 1 and "colour is used instead" in model.repairs[0]


# -- 2. indices reach native code unchecked -----------------------------------------------------------------

TRIANGLE_OFF = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 {index}\n"
TRIANGLE_PLY = (
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 {index}\n"
)


@pytest.mark.parametrize("template, suffix", [(TRIANGLE_OFF, ".off"), (TRIANGLE_PLY, ".ply")])
@pytest.mark.parametrize("index", [7, 3, -1, 2**31 - 1])
def test_faces_past_the_vertex_list_are_refused_on_load(tmp_path, template, suffix, index):
    path = tmp_path / f"t{suffix}"
    path.write_text(template.format(index=index))
    with pytest.raises(hd.ModelError, match=f"outside 0..2 \\(e.g. {index}\\)"):
        hd.load_model(path)


def test_a_model_built_in_code_is_checked_before_the_ray_caster(monkeypatch):
    with pytest.raises(hd.ModelError, match="outside 0..2"):
        hd.Model.untextured("t", np.eye(3), [[0, 1, 3]])
    model = hd.Model.untextured("t", np.eye(3), [[0, 1, 2]])
    with pytest.raises(hd.ModelError, match="outside 0..2"):
        model.faces = np.array([[0, 1, -5]])
        model.__post_init__()  # replace() and every constructor pass here


# -- 3. data loss -------------------------------------------------------------------------------------------


def test_no_command_writes_over_one_of_its_inputs(tmp_path, caplog, box, depth_frame):
    table = tmp_path / "d.parquet"
    vertices, faces = grid_mesh(12, 12)
    write_table(pd.DataFrame(columns=DESCRIPTOR_SCHEMA.names), table, DESCRIPTOR_SCHEMA)
    png, intrinsics = depth_frame
    link = tmp_path / "link.parquet"
    link.symlink_to(table)
    cases = [
        ["classify", str(table), "--out", str(table)],
        ["classify", str(table), "--out", str(link)],
        ["stitch", str(box), str(box), "-o", str(box)],
        ["view-from-depth", str(RANGE_MAP), "-o", str(tmp_path / ".." / tmp_path.name / "x.ply"), "-o", str(RANGE_MAP)],
        [
            "view-from-depth",
            str(png),
            "--intrinsics",
            str(intrinsics),
            "-o",
            str(png.with_suffix(".npz")),
            "--rgb",
            str(png.with_suffix(".npz")),
        ],
        ["render", str(box), "--out", str(tmp_path / "v.npz"), "--size", "1", "1", "1"],
    ]
    (tmp_path / "v.npz").symlink_to(box)  # render --out a link to its own model
    before = {p: p.read_bytes() for p in (table, box, RANGE_MAP)}
    for argv in cases:
        caplog.clear()
        assert main(argv) == 1, argv
        one_line_error(caplog, "is also an input")
    assert {p: p.read_bytes() for p in before} == before


def test_an_interrupted_write_leaves_no_half_file(tmp_path, monkeypatch, disc):
    table = tmp_path / "d.parquet"
    frame = pd.DataFrame(columns=DESCRIPTOR_SCHEMA.names)
    write_table(frame, table, DESCRIPTOR_SCHEMA)
    before = table.read_bytes()

    def interrupted(table_, where, **kwargs):
        Path(where).write_bytes(b"PAR1 half")
        raise KeyboardInterrupt

    monkeypatch.setattr("pyarrow.parquet.write_table", interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_table(frame, table, DESCRIPTOR_SCHEMA)
    assert table.read_bytes() == before and sorted(tmp_path.iterdir()) == [table]
    monkeypatch.setattr(np, "savez_compressed", lambda where, **arrays: (Path(where).write_bytes(b"PK"), 1 / 0))
    with pytest.raises(ZeroDivisionError):
        disc.save(tmp_path / "v.npz")
    assert sorted(tmp_path.iterdir()) == [table]


def test_ctrl_c_in_a_command_leaves_no_file_and_one_line(tmp_path, caplog, monkeypatch, box):
    def interrupted(view, path):
        Path(path).write_bytes(b"PK half")
        raise KeyboardInterrupt

    monkeypatch.setattr("heatdata.views.view.View._write_npz", interrupted)
    assert main(["render", str(box), "--out", str(tmp_path / "out" / "v.npz")]) == 130
    one_line_error(caplog, "interrupted")
    assert list((tmp_path / "out").iterdir()) == []


# -- 4. silent wrong or truncated results -------------------------------------------------------------------


def test_a_truncated_off_or_ascii_ply_is_refused(tmp_path):
    sphere = trimesh.creation.icosphere(3)
    for suffix in (".off", ".ply"):
        path = tmp_path / f"s{suffix}"
        sphere.export(path, encoding="ascii") if suffix == ".ply" else sphere.export(path)
        text = path.read_text()
        path.write_text(text[: int(len(text) * 0.8)])
        with pytest.raises(hd.ModelError, match="truncated: its header declares 642 vertices and 1,280 faces"):
            hd.load_model(path)


@pytest.mark.parametrize("width", ["NaN", "0", "-12", "Infinity"])
def test_sh3f_sizes_that_are_not_positive_lengths_are_refused(tmp_path, width):
    with pytest.raises(hd.ModelError, match=f"width#1={width}"):
        sh3f_entries(make_sh3f(tmp_path, extra=(f"width#1={width}",)))


@pytest.mark.parametrize("rotation", [np.full((3, 3), np.nan), np.zeros((3, 3)), np.diag([1, 1, -1]), np.eye(2)])
def test_rotations_that_are_not_rotations_are_refused(box, rotation):
    with pytest.raises(hd.ModelError, match="rotation must be a 3x3 rotation matrix"):
        hd.load_model(box, rotation=rotation)


def test_a_zero_size_that_would_flatten_the_model_is_refused(box):
    with pytest.raises(hd.ModelError, match="size 0 along y would flatten"):
        hd.load_model(box, size=(0.2, 0.0, 0.1))


@pytest.mark.parametrize(
    "change, message",
    [
        ({"fx": -580.0}, "fx=-580"),
        ({"fx": float("inf")}, "fx=inf"),
        ({"fx": True}, "fx=True"),
        ({"width": 640.5}, "width=640.5"),
        ({"cy": float("nan")}, "cy=nan"),
        ({"fy": "580"}, "fy='580'"),
    ],
)
def test_intrinsics_that_are_not_a_camera_are_refused(tmp_path, box, change, message):
    with pytest.raises(hd.ViewError, match=message.replace("(", r"\(")):
        hd.render_view(hd.load_model(box), intrinsics=KINECT | change)
    path = tmp_path / "k.json"
    path.write_text(json.dumps(KINECT | change).replace("inf", "Infinity"))
    with pytest.raises(hd.ViewError):
        read_intrinsics(path)


def test_a_saved_view_with_a_mirroring_camera_or_a_nan_pose_is_refused(tmp_path, disc):
    disc.save(tmp_path / "v.npz")
    with np.load(tmp_path / "v.npz") as data:
        arrays = dict(data)
    for key, value in [
        ("intrinsics", np.array(json.dumps(KINECT | {"fx": -580.0}))),
        ("pose", np.full((4, 4), np.nan)),
    ]:
        np.savez(tmp_path / "bad.npz", **(arrays | {key: value}))
        with pytest.raises(hd.ViewError, match="fx=-580" if key == "intrinsics" else "pose must be a finite 4x4"):
            hd.View.load(tmp_path / "bad.npz")


def test_a_catalogue_row_with_part_of_a_size_or_bad_cells_is_refused(tmp_path):
    from heatdata.io.catalog import load_catalog_model

    write_textured_quad(tmp_path)
    row = {"object": "q", "label": "quad", "path": str(tmp_path / "quad.obj")}
    for cells, message in [
        ({"width": "0.1", "height": "", "depth": "0.1"}, "together"),
        ({"width": "NaN", "height": "0.2", "depth": "0.1"}, "together"),
        ({"width": "wide", "height": "0.2", "depth": "0.1"}, "must be numbers"),
        ({"scale": "big"}, "scale and hue must be numbers"),
        ({"rotation": "1 0 0"}, "not 9 numbers"),
    ]:
        with pytest.raises(hd.ModelError, match=message):
            load_catalog_model(row | cells)
    assert load_catalog_model(row | {"width": "", "height": "", "depth": ""}).extents[0] == pytest.approx(1.0)
    (tmp_path / "catalog.csv").write_bytes(b'object,label,file\n"q,quad\n\0\xff')
    with pytest.raises(hd.ModelError, match="catalog.csv"):
        hd.read_catalog(tmp_path / "catalog.csv")


@pytest.mark.parametrize("colors, message", [(255.0, "divide by 255"), (-0.5, "-0.5..-0.5")])
def test_view_colours_outside_zero_one_are_refused(colors, message):
    vertices, faces = grid_mesh(8, 8)
    with pytest.raises(hd.ViewError, match=message):
        hd.View.from_arrays(vertices, faces, np.full(vertices.shape, colors))


def test_descriptors_of_different_samples_or_sampling_have_no_distance(disc):
    spec = hd.DescriptorSpec("pvhk", 16)
    a, b = hd.describe(disc, [spec, hd.DescriptorSpec("pvhk", 64)])
    with pytest.raises(hd.HeatdataError, match="of 16 and 64 samples"):
        hd.distance(a, b)
    (polar,) = hd.describe(disc, [hd.DescriptorSpec("pvhk", 16, sampling="polar")])
    with pytest.raises(hd.HeatdataError, match="sampling 'arclength' and 'polar'"):
        hd.distance(a, polar)
    per_vertex = hd.describe(disc, [hd.DescriptorSpec("pvhk", None), hd.DescriptorSpec("pvhk", None, "center")])
    assert hd.distance(*per_vertex) >= 0  # once per boundary vertex: lengths may differ by design
    assert hd.distance(a, a) == 0


@pytest.mark.parametrize("size", [0, -2, 1.5, True])
def test_a_library_of_no_view_is_refused(size):
    from heatdata.recognition.evaluate import library_subset

    rows = pd.DataFrame({"object": ["a", "a"], "split": ["train", "train"], "azimuth": [0.0, 180.0]})
    with pytest.raises(hd.HeatdataError, match="library size must be a whole number"):
        library_subset(rows, size)
    assert len(library_subset(rows, 1)) == 1


# -- 5. tracebacks: one line, exit 1 or 2 -------------------------------------------------------------------


def test_every_writing_command_refuses_an_unwritable_output_before_the_work(tmp_path, caplog, box, monkeypatch):
    """Under /proc, under a regular file, or a folder where a file should go (a file where a folder should)."""
    table = tmp_path / "d.parquet"
    write_table(pd.DataFrame(columns=DESCRIPTOR_SCHEMA.names), table, DESCRIPTOR_SCHEMA)
    sh3f = make_sh3f(tmp_path)
    (tmp_path / "afile").write_text("")
    for suffix in (".npz", ".ply", ".parquet"):
        (tmp_path / f"folder{suffix}").mkdir()
    for name in (  # the commands import these when they run
        "experiments.demo.describe_and_classify",
        "views.render.render_view",
        "frames.clouds.read_organized_cloud",
        "jasnom.seam.stitch",
    ):
        monkeypatch.setattr(f"heatdata.{name}", lambda *a, **k: pytest.fail("the work started"))
    monkeypatch.setattr("heatdata.io.sh3f.extract_sh3f_model", lambda *a, **k: pytest.fail("the work started"))
    for file, folder in [
        ("/proc/heatdata/x", "/proc/heatdata/x"),
        (tmp_path / "afile" / "x", tmp_path / "afile" / "x"),
        (tmp_path / "folder", tmp_path / "afile"),
    ]:
        commands = [
            ["render", str(box), "--out", f"{file}.npz"],
            ["view-from-depth", str(RANGE_MAP), "-o", f"{file}.ply"],
            ["stitch", str(box), str(box), "-o", f"{file}.ply"],
            ["classify", str(table), "--out", f"{file}.parquet"],
            ["demo", "--out", str(folder)],
            ["import-sh3f", str(sh3f), str(folder)],
        ]
        for argv in commands:
            caplog.clear()
            assert main(argv) == 1, argv
            one_line_error(caplog, str(file if argv[0] not in ("demo", "import-sh3f") else folder))


def test_write_depth_creates_its_folder_and_refuses_a_lossy_format(tmp_path, depth_frame):
    view = read_depth(*depth_frame)
    write_depth(view, tmp_path / "new" / "deep" / "d.png")
    assert read_depth(tmp_path / "new/deep/d.png", tmp_path / "new/deep/d.json").n_vertices == view.n_vertices
    with pytest.raises(hd.OutputError, match="16-bit .png"):
        write_depth(view, tmp_path / "d.jpg")
    with pytest.raises(hd.OutputError, match="written as .json"):
        write_depth(view, tmp_path / "e.png", tmp_path / "e.png")
    with pytest.raises(hd.OutputError):
        write_depth(view, "/proc/heatdata/d.png")


def bad_depth_files(folder: Path, png: Path) -> dict[str, Path]:
    good = png.read_bytes()
    files_ = {
        "truncated.png": good[: len(good) // 3],
        "garbage.png": b"\x89PNG\r\n\x1a\n" + bytes(range(256)) * 4,
        "truncated.npy": b"\x93NUMPY\x01\x00v\x00{'descr': '<f8', 'fortran_order': False, 'shape': (480, 640), }"
        + b" " * 50
        + b"\n"
        + b"\0" * 1000,
    }
    for name, data in files_.items():
        (folder / name).write_bytes(data)
    Image.new("I;16", (5000, 4000)).save(folder / "oversized.png")  # 20 Mpixel of ~60 kB
    np.save(folder / "object.npy", np.array([{"a": 1}], dtype=object), allow_pickle=True)
    return {name: folder / name for name in [*files_, "oversized.png", "object.npy"]}


def test_bad_depth_images_rgb_and_masks_are_one_line(tmp_path, caplog, depth_frame):
    png, intrinsics = depth_frame
    for name, path in bad_depth_files(tmp_path, png).items():
        for role in ("depth", "--rgb", "--mask"):
            if role != "depth" and name.endswith(".npy"):
                continue
            argv = ["view-from-depth", str(png if role != "depth" else path), "--intrinsics", str(intrinsics)]
            argv += [role, str(path)] if role != "depth" else []
            caplog.clear()
            assert main([*argv, "-o", str(tmp_path / "v.npz")]) == 1, (name, role)
            one_line_error(caplog, name)
            with pytest.raises(hd.ViewError, match=name):
                read_depth(
                    png if role != "depth" else path,
                    intrinsics,
                    **({role[2:] + "_path": path} if role != "depth" else {}),
                )


PCD_HEADER = (
    "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 4\nHEIGHT 4\nVIEWPOINT 0 0 0 1 0 0 0\n"
)


@pytest.mark.parametrize(
    "text, message",
    [
        (PCD_HEADER + "POINTS 16\nDATA binary\n" + "\0" * 40, "truncated: 40 bytes"),
        (PCD_HEADER + "DATA binary\n" + "\0" * 192, "no POINTS line"),
        (PCD_HEADER + "POINTS 16\nDATA ascii\n" + "0 0\n" * 16, "rows have 2 numbers"),
        (PCD_HEADER.replace("SIZE 4 4 4", "SIZE 4 4") + "POINTS 16\nDATA ascii\n" + "0 0 1\n" * 16, "2 SIZE"),
        (PCD_HEADER + "POINTS 16\nDATA ascii\n" + "a b c\n" * 16, "not rows of numbers"),
        (PCD_HEADER.replace("WIDTH 4", "WIDTH 999999999") + "POINTS 16\nDATA binary\n", "is not read"),
    ],
)
def test_bad_pcd_files_are_one_line(tmp_path, caplog, text, message):
    path = tmp_path / "c.pcd"
    path.write_bytes(text.encode("latin-1"))
    with pytest.raises(hd.ViewError, match=message):
        read_organized_cloud(path)
    assert main(["view-from-depth", str(path), "-o", str(tmp_path / "v.npz")]) == 1
    one_line_error(caplog, message)


def test_an_ascii_range_map_ply_reads_as_its_binary_twin(tmp_path):
    """Every ASCII range-map PLY failed with KeyError: 0 (trimesh reads an ASCII element as columns)."""
    binary = trimesh.load(RANGE_MAP, process=False)
    camera = binary.metadata["_ply_raw"]["camera"]["data"]
    names = camera.dtype.names
    lines = ["ply", "format ascii 1.0", "element camera 1"]
    lines += [f"property {'int' if camera.dtype[n].kind == 'i' else 'float'} {n}" for n in names]
    lines += [f"element vertex {len(binary.vertices)}", *(f"property float {a}" for a in "xyz")]
    lines += [f"element face {len(binary.faces)}", "property list uchar int vertex_indices", "end_header"]
    lines.append(
        " ".join(repr(float(camera[0][n])) if camera.dtype[n].kind == "f" else str(camera[0][n]) for n in names)
    )
    lines += [" ".join(map(repr, v)) for v in np.asarray(binary.vertices, np.float32).tolist()]
    lines += ["3 " + " ".join(map(str, f)) for f in binary.faces.tolist()]
    (tmp_path / "a.ply").write_text("\n".join(lines) + "\n")
    ascii_view, binary_view = (read_organized_cloud(p, scale=0.001) for p in (tmp_path / "a.ply", RANGE_MAP))
    assert ascii_view.n_vertices == binary_view.n_vertices
    assert np.allclose(ascii_view.vertices, binary_view.vertices, atol=1e-6)


def test_classify_on_a_table_that_is_not_of_descriptors_is_one_line(tmp_path, caplog):
    pd.DataFrame({"a": [1, 2]}).to_parquet(tmp_path / "other.parquet")
    assert main(["classify", str(tmp_path / "other.parquet")]) == 1
    one_line_error(caplog, "lacks column(s) object")


def test_import_sh3f_leaves_out_odd_keys_and_refuses_a_bad_leftover_catalogue(tmp_path, caplog):
    sh3f = make_sh3f(tmp_path, extra=("name#abc=", "name#=Nothing"))
    table = hd.import_sh3f(sh3f, tmp_path / "models")
    assert len(table) == 2 and "name#abc" in caplog.text
    for leftover in ("\0\0\0garbage", "a,b\n1,2\n", '"unclosed\n'):
        (tmp_path / "models" / "catalog.csv").write_text(leftover)
        caplog.clear()
        assert main(["import-sh3f", str(sh3f), str(tmp_path / "models")]) == 1
        one_line_error(caplog, "catalog.csv")


def test_repeated_faces_are_dropped_as_a_repair():
    vertices, faces = grid_mesh(8, 8)
    view = hd.View.from_arrays(vertices, np.vstack([faces, faces[:3], faces[:1, ::-1]]))
    assert len(view.faces) == len(faces) and "dropped 4 repeated faces" in view.repairs


def test_non_finite_config_numbers_and_too_few_views_are_refused_before_any_job():
    from heatdata.experiments.config import check_numbers, check_stages

    with pytest.raises(hd.ConfigError, match=r"views.distance: nan is not a finite number"):
        check_numbers({"views": {"distance": float("nan"), "train": 40}})
    with pytest.raises(hd.ConfigError, match=r"descriptors\[1\].options.seed: inf"):
        check_numbers({"descriptors": [{}, {"options": {"seed": float("inf")}}]})
    import yaml

    config = yaml.safe_load((ROOT / "config/config.yaml").read_text())
    config["views"]["train"] = 2
    with pytest.raises(hd.ConfigError, match="Isomap.*1 object"):
        check_stages(config, ["mug"], [])


# -- 6. messages that point the right way -------------------------------------------------------------------


def test_messages_say_what_is_wrong(tmp_path, caplog, capsys, box):
    assert main(["render", str(tmp_path), "--out", str(tmp_path / "v.npz")]) == 1
    one_line_error(caplog, "is a folder, not a model file")
    caplog.clear()
    assert main(["stitch", str(box), str(box), "-o", str(tmp_path / "s.ply"), "--motion", "/dev/zero"]) == 1
    one_line_error(caplog, "/dev/zero: is not a regular file")
    caplog.clear()
    with pytest.raises(hd.ViewError, match="fx=0"):
        hd.render_view(hd.load_model(box), intrinsics=KINECT | {"fx": 0})
    with pytest.raises(hd.RenderError, match="tau"):
        hd.render_view(hd.load_model(box), tau=float("nan"))
    assert main(["describe", str(tmp_path / "missing.npz")]) == 1
    one_line_error(caplog, "no such view file")
    with pytest.raises(SystemExit):
        main(["render", str(box), "--out", "v.npz", "--seed", "-3"])
    err = capsys.readouterr().err
    assert "'-3': need a number >= 0" in err and ": number" not in err
    empty = tmp_path / "Empty.sh3f"
    with zipfile.ZipFile(empty, "w") as archive:
        archive.writestr("PluginFurnitureCatalog.properties", "# nothing\n")
    with pytest.raises(hd.ModelError, match="no furniture in the library$"):
        sh3f_catalog(empty)
    with pytest.raises(hd.ModelError, match="no furniture matches 'piano'$"):
        sh3f_catalog(make_sh3f(tmp_path), name_pattern="piano")


def test_a_model_in_millimetres_gets_a_hint(tmp_path, caplog):
    path = tmp_path / "mm.ply"
    trimesh.creation.box(extents=(200.0, 100.0, 150.0)).export(path)
    model = hd.load_model(path)
    assert "--scale" in caplog.text and "millimetres" in caplog.text
    with pytest.raises(hd.RenderError, match="give --scale 0.001"):
        hd.render_view(model)


def test_check_output_and_atomic(tmp_path):
    with pytest.raises(hd.OutputError, match="ending in .npz"):
        files.check_output(tmp_path / "a.txt", suffixes=(".npz",))
    assert not files.check_output(tmp_path / "new" / "a.npz").parent.exists()  # the writer creates it
    with pytest.raises(hd.OutputError, match="cannot be written"):
        files.check_output("/proc/heatdata/a.txt")
    with pytest.raises(hd.OutputError, match="cannot be written"):
        with files.atomic("/proc/heatdata/a.txt") as temporary:
            temporary.write_text("x")
    with files.atomic(tmp_path / "b.txt") as temporary:
        assert temporary.parent == tmp_path and temporary.suffix == ".txt" and temporary.name.startswith(".b.")
        temporary.write_text("done")
    assert (tmp_path / "b.txt").read_text() == "done"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.txt"]
