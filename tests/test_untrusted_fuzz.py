"""Every reader, fed random truncations and byte flips of a valid file, returns a valid object or raises a
HeatdataError, never anything else (issue 31).

The examples are derandomized, so CI runs the same ones each time, within its budget of 60 s for the whole
module; ``HEATDATA_FUZZ_EXAMPLES=2000 HEATDATA_FUZZ_RANDOM=1 pytest tests/test_untrusted_fuzz.py`` fuzzes longer,
with new examples.
"""

import io
import json
import os
import tempfile
import zipfile
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import trimesh
from conftest import make_sh3f, write_textured_quad
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from PIL import Image

import heatdata as hd
from heatdata.frames.clouds import read_organized_cloud
from heatdata.io.sh3f import sh3f_entries
from heatdata.views.depth import read_depth, read_intrinsics

EXAMPLES = int(os.environ.get("HEATDATA_FUZZ_EXAMPLES", "100"))
FUZZ = settings(
    max_examples=EXAMPLES,
    deadline=None,
    database=None,
    derandomize=os.environ.get("HEATDATA_FUZZ_RANDOM") is None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
K = {"fx": 30.0, "fy": 30.0, "cx": 15.5, "cy": 11.5, "width": 32, "height": 24}


@st.composite
def damaged(draw, data: bytes) -> bytes:
    """``data`` cut short, or with up to eight bytes overwritten."""
    if draw(st.booleans()):
        return data[: draw(st.integers(0, len(data) - 1))]
    damaged_data = bytearray(data)
    for where, value in draw(
        st.lists(st.tuples(st.integers(0, len(data) - 1), st.integers(0, 255)), min_size=1, max_size=8)
    ):
        damaged_data[where] = value
    return bytes(damaged_data)


def check_model(model: hd.Model) -> None:
    assert np.isfinite(model.vertices).all() and len(model.faces)
    assert model.faces.min() >= 0 and model.faces.max() < len(model.vertices)
    assert all(t.ndim == 3 and t.shape[2] == 3 for t in model.textures)


def check_view(view: hd.View) -> None:
    assert np.isfinite(view.vertices).all() and view.faces.max() < view.n_vertices
    assert (view.colors >= 0).all() and (view.colors <= 1).all()


def mesh_bytes(suffix: str, **export) -> bytes:
    mesh = trimesh.creation.icosphere(1)
    mesh.visual.vertex_colors = np.tile([200, 40, 40, 255], (len(mesh.vertices), 1))
    data = mesh.export(file_type=suffix[1:], **export)
    return data.encode() if isinstance(data, str) else data


def grid_points() -> np.ndarray:
    """(24, 32, 3) points of a bumpy surface seen by the camera ``K``."""
    rows, cols = np.indices((K["height"], K["width"]))
    z = 1.0 + 0.05 * np.sin(cols / 5.0) * np.cos(rows / 4.0)
    return np.stack([(cols - K["cx"]) / K["fx"] * z, (rows - K["cy"]) / K["fy"] * z, z], axis=-1)


def pcd_bytes(binary: bool) -> bytes:
    points = grid_points().reshape(-1, 3).astype(np.float32)
    header = (
        "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
        f"WIDTH {K['width']}\nHEIGHT {K['height']}\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {len(points)}\n"
    )
    if binary:
        return (header + "DATA binary\n").encode() + points.tobytes()
    return (header + "DATA ascii\n" + "".join(f"{x:.5f} {y:.5f} {z:.5f}\n" for x, y, z in points)).encode()


def range_ply_bytes() -> bytes:
    """A small range map in MeshLab's layout: a VCG camera element, then the grid's vertices and faces."""
    points = grid_points()
    index = np.arange(points.shape[0] * points.shape[1]).reshape(points.shape[:2])
    a, b, c, d = index[:-1, :-1].ravel(), index[:-1, 1:].ravel(), index[1:, :-1].ravel(), index[1:, 1:].ravel()
    faces = np.concatenate([np.column_stack([a, b, c]), np.column_stack([b, d, c])])
    vertices = points.reshape(-1, 3) * [1.0, -1.0, 1.0]  # VCG's camera y is up
    camera = {"view_px": 0, "view_py": 0, "view_pz": 0, "x_axisx": 1, "x_axisy": 0, "x_axisz": 0}
    camera |= {"y_axisx": 0, "y_axisy": 1, "y_axisz": 0, "z_axisx": 0, "z_axisy": 0, "z_axisz": 1}
    lines = ["ply", "format ascii 1.0", "element camera 1", *(f"property float {n}" for n in camera)]
    lines += [f"element vertex {len(vertices)}", "property float x", "property float y", "property float z"]
    lines += [f"element face {len(faces)}", "property list uchar int vertex_indices", "end_header"]
    lines += [" ".join(str(v) for v in camera.values())]
    lines += [f"{x:.5f} {y:.5f} {z:.5f}" for x, y, z in vertices] + [f"3 {p} {q} {r}" for p, q, r in faces]
    return ("\n".join(lines) + "\n").encode()


def depth_png_bytes() -> bytes:
    buffer = io.BytesIO()
    Image.fromarray((grid_points()[..., 2] * 1000).astype(np.uint16)).save(buffer, format="PNG")
    return buffer.getvalue()


def npy_bytes() -> bytes:
    buffer = io.BytesIO()
    np.save(buffer, grid_points()[..., 2])
    return buffer.getvalue()


def obj_bytes() -> tuple[bytes, dict[str, bytes]]:
    with tempfile.TemporaryDirectory() as folder:
        obj = write_textured_quad(Path(folder))
        return obj.read_bytes(), {p.name: p.read_bytes() for p in Path(folder).iterdir() if p != obj}


def sh3f_bytes() -> bytes:
    with tempfile.TemporaryDirectory() as folder:
        return make_sh3f(Path(folder)).read_bytes()


def view_bytes() -> bytes:
    with tempfile.TemporaryDirectory() as folder:
        vertices = grid_points().reshape(-1, 3)[: 12 * 32]
        rows, cols = np.indices((11, 31))
        a = (rows * 32 + cols).ravel()
        faces = np.concatenate([np.column_stack([a, a + 1, a + 32]), np.column_stack([a + 1, a + 33, a + 32])])
        hd.View.from_arrays(vertices, faces, view_id="grid").save(Path(folder) / "v.npz")
        return (Path(folder) / "v.npz").read_bytes()


def table_bytes() -> bytes:
    import pandas as pd

    from heatdata.io.tables import PREDICTION_SCHEMA, write_table

    row = {"descriptor": "pvhk", "object": "a", "label": "cup", "view_id": "a/test/000", "azimuth": 1.5}
    row |= {"predicted_object": "a", "predicted_label": "cup", "predicted_view_id": "a/train/000"}
    row |= {"predicted_azimuth": 0.0, "distance": 0.25, "correct": True, "library_size": 40}
    with tempfile.TemporaryDirectory() as folder:
        write_table(pd.DataFrame([row, row]), Path(folder) / "p.parquet", PREDICTION_SCHEMA, {"seed": 3})
        return (Path(folder) / "p.parquet").read_bytes()


def read_prediction_table(path: Path) -> None:
    from heatdata.io.tables import PREDICTION_SCHEMA, read_table

    read_table(path, schema=PREDICTION_SCHEMA)


def load_catalogue(path: Path) -> None:
    from heatdata.io.catalog import load_catalog_model

    for _, row in hd.read_catalog(path).iterrows():
        check_model(load_catalog_model(row))


def import_sh3f_and_load(path: Path) -> None:
    table = hd.import_sh3f(path, path.parent / "models")
    for file in table["file"]:
        check_model(hd.load_model(path.parent / "models" / file))


def write_frame_files(folder: Path) -> Path:
    (folder / "k.json").write_text(json.dumps(K))
    return folder / "k.json"


OBJ, OBJ_COMPANIONS = obj_bytes()
BESIDE = OBJ_COMPANIONS | {"quad.obj": OBJ}  # written beside every damaged file (the catalogue names quad.obj)
READERS: dict[str, tuple[str, bytes, Callable[[Path], object]]] = {
    "obj": (".obj", OBJ, lambda p: check_model(hd.load_model(p))),
    "off": (".off", mesh_bytes(".off"), lambda p: check_model(hd.load_model(p))),
    "ply ascii": (".ply", mesh_bytes(".ply", encoding="ascii"), lambda p: check_model(hd.load_model(p))),
    "ply binary": (".ply", mesh_bytes(".ply"), lambda p: check_model(hd.load_model(p))),
    "stl": (".stl", mesh_bytes(".stl"), lambda p: check_model(hd.load_model(p))),
    "glb": (".glb", mesh_bytes(".glb"), lambda p: check_model(hd.load_model(p))),
    "sh3f": (".sh3f", sh3f_bytes(), lambda p: (sh3f_entries(p), import_sh3f_and_load(p))),
    "depth png": (".png", depth_png_bytes(), lambda p: check_view(read_depth(p, write_frame_files(p.parent)))),
    "depth npy": (".npy", npy_bytes(), lambda p: check_view(read_depth(p, write_frame_files(p.parent)))),
    "pcd ascii": (".pcd", pcd_bytes(False), lambda p: check_view(read_organized_cloud(p))),
    "pcd binary": (".pcd", pcd_bytes(True), lambda p: check_view(read_organized_cloud(p))),
    "range-map ply": (".ply", range_ply_bytes(), lambda p: check_view(read_organized_cloud(p))),
    "intrinsics": (".json", json.dumps(K).encode(), read_intrinsics),
    "view npz": (".npz", view_bytes(), lambda p: check_view(hd.View.load(p))),
    "parquet table": (".parquet", table_bytes(), read_prediction_table),
    "catalogue csv": (
        ".csv",
        b"object,label,file,width,height,depth,rotation,scale\nq,quad,quad.obj,0.1,0.2,0.05,1 0 0 0 1 0 0 0 1,\n",
        load_catalogue,
    ),
}


def test_every_valid_seed_reads():
    with tempfile.TemporaryDirectory() as folder:
        for name, (suffix, data, reader) in READERS.items():
            path = Path(folder) / name.replace(" ", "_") / f"input{suffix}"
            path.parent.mkdir()
            path.write_bytes(data)
            for companion, content in BESIDE.items():
                (path.parent / companion).write_bytes(content)
            reader(path)


@pytest.mark.parametrize("name", READERS)
def test_a_damaged_file_reads_or_is_a_heatdata_error(name):
    suffix, data, reader = READERS[name]

    @FUZZ
    @given(damaged(data))
    def check(damaged_data: bytes) -> None:
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / f"input{suffix}"
            path.write_bytes(damaged_data)
            for companion, content in BESIDE.items():
                (Path(folder) / companion).write_bytes(content)
            try:
                reader(path)
            except hd.HeatdataError:
                pass

    check()


@pytest.mark.parametrize("companion", sorted(OBJ_COMPANIONS))
def test_an_obj_with_a_damaged_mtl_or_texture_loads_with_a_note_or_is_a_heatdata_error(companion):
    @FUZZ
    @given(damaged(OBJ_COMPANIONS[companion]))
    def check(damaged_data: bytes) -> None:
        with tempfile.TemporaryDirectory() as folder:
            (Path(folder) / "input.obj").write_bytes(OBJ)
            for name, content in OBJ_COMPANIONS.items():
                (Path(folder) / name).write_bytes(damaged_data if name == companion else content)
            try:
                check_model(hd.load_model(Path(folder) / "input.obj"))
            except hd.HeatdataError:
                pass

    check()


def test_a_damaged_sh3f_member_is_a_heatdata_error_or_imports(tmp_path):
    """The archive is valid; the model inside it is damaged (a truncated OBJ in a well-formed zip)."""
    source = make_sh3f(tmp_path)

    @FUZZ
    @given(damaged(OBJ))
    def check(damaged_obj: bytes) -> None:
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / "Mini.sh3f"
            with zipfile.ZipFile(source) as archive, zipfile.ZipFile(path, "w") as out:
                for item in archive.infolist():
                    out.writestr(item, damaged_obj if item.filename.endswith(".obj") else archive.read(item))
            try:
                import_sh3f_and_load(path)
            except hd.HeatdataError:
                pass

    check()
