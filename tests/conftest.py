"""Shared fixtures: small meshes with known answers, written without the renderer."""

import zipfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import settings
from scipy.spatial import Delaunay

import heatdata as hd

# a property's example may wait for a core on a busy machine (CI beside other jobs): no deadline
settings.register_profile("suite", deadline=None)
settings.load_profile("suite")

ROOT = Path(__file__).resolve().parents[1]

#: the test files that take a minute or more, longest first: the suite starts them first (pytest-xdist hands out
#: files in collection order, ``--no-loadscope-reorder`` in pyproject.toml), so that no long file is left to end the
#: run alone on one worker while the other waits; the Slurm test mostly waits for Slurm's status checks, and runs
#: beside the workflow's own runs
LONG_FIRST = (
    "experiments/test_workflow.py",
    "experiments/test_slurm.py",
    "descriptors/test_invariance.py",
    "experiments/test_docs_targets.py",
    "test_docs.py",
    "test_readme.py",
)
if missing := [name for name in LONG_FIRST if not (ROOT / "tests" / name).is_file()]:
    raise pytest.UsageError(f"tests/conftest.py LONG_FIRST names test files that do not exist: {missing}")


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """The files of :data:`LONG_FIRST` first, in its order; every other test keeps its place."""
    rank = {(ROOT / "tests" / name).resolve(): k for k, name in enumerate(LONG_FIRST)}
    items.sort(key=lambda item: rank.get(Path(item.path).resolve(), len(rank)))


def grid_mesh(nx: int, ny: int, spacing: float = 0.002, depth: float = 1.0):
    """A flat rectangular grid of triangles facing the camera at ``depth`` metres.

    Returns (vertices (nx*ny, 3), faces (2(nx-1)(ny-1), 3)); faces are oriented like the
    renderer's (counter-clockwise in image coordinates with v down).
    """
    xs = (np.arange(nx) - (nx - 1) / 2) * spacing
    ys = (np.arange(ny) - (ny - 1) / 2) * spacing
    x, y = np.meshgrid(xs, ys)
    vertices = np.column_stack([x.ravel(), y.ravel(), np.full(x.size, depth)])
    index = np.arange(nx * ny).reshape(ny, nx)
    a, b, c, d = index[:-1, :-1].ravel(), index[:-1, 1:].ravel(), index[1:, :-1].ravel(), index[1:, 1:].ravel()
    faces = np.concatenate([np.column_stack([a, b, c]), np.column_stack([b, d, c])])
    return vertices, faces


def disc_view(rings: int = 20, spacing: float = 0.002) -> hd.View:
    """A flat disc of concentric rings (6k vertices on ring k), Delaunay-triangulated.

    Nearly isotropic, unlike a square grid, so a central source gives an almost
    constant boundary temperature.
    """
    points = [np.zeros((1, 2))]
    for k in range(1, rings + 1):
        angle = 2 * np.pi * (np.arange(6 * k) + 0.5 * (k % 2)) / (6 * k)
        points.append(k * spacing * np.column_stack([np.cos(angle), np.sin(angle)]))
    xy = np.vstack(points)
    faces = Delaunay(xy).simplices
    vertices = np.column_stack([xy, np.ones(len(xy))])
    return hd.View.from_arrays(vertices, faces, view_id="disc")


def square_view(n: int = 21, spacing: float = 0.002) -> hd.View:
    vertices, faces = grid_mesh(n, n, spacing)
    return hd.View.from_arrays(vertices, faces, view_id="square")


@pytest.fixture
def disc() -> hd.View:
    return disc_view()


@pytest.fixture
def square() -> hd.View:
    return square_view()


def model_of(mesh, name: str = "ellipsoid") -> hd.Model:
    """A trimesh mesh as a model, red below y = 0.03 and blue above (a colour a stitch must carry across its seam)."""
    colors = np.zeros((len(mesh.faces), 3, 3), np.float32)
    colors[..., 0] = 0.8
    colors[mesh.triangles_center[:, 1] > 0.03] = [0.1, 0.3, 0.9]
    return hd.Model.untextured(name, mesh.vertices, mesh.faces, colors)


@pytest.fixture(scope="module")
def ellipsoid() -> hd.Model:
    """A two-tone ellipsoid of semi-axes 10, 6 and 8 cm (642 vertices): JASNOM's tests cut, move and stitch it."""
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.1)
    return model_of(trimesh.Trimesh(sphere.vertices * [1.0, 0.6, 0.8], sphere.faces))


@pytest.fixture(scope="session")
def catalog():
    return hd.read_catalog(ROOT / "data" / "models" / "catalog.csv")


@pytest.fixture(scope="session")
def mug(catalog) -> hd.Model:
    return hd.load_catalog_model(catalog[catalog["object"] == "beer-mug"].iloc[0])


def write_textured_quad(folder):
    """A 1 x 1 quad whose texture is red on the left half and blue on the right."""
    from PIL import Image

    texture = np.zeros((4, 4, 3), np.uint8)
    texture[:, :2] = [255, 0, 0]
    texture[:, 2:] = [0, 0, 255]
    Image.fromarray(texture).save(folder / "tex.png")
    (folder / "quad.mtl").write_text("newmtl skin\nKd 1 1 1\nmap_Kd tex.png\n")
    (folder / "quad.obj").write_text(
        "mtllib quad.mtl\n"
        "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "usemtl skin\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n"
    )
    return folder / "quad.obj"


def colored_box(extents=(0.2, 0.2, 0.2)):
    """A box with every face one red."""
    import trimesh

    box = trimesh.creation.box(extents=extents)
    box.visual.face_colors = np.tile([200, 50, 50, 255], (len(box.faces), 1))
    return box


def make_sh3f(tmp_path, extra: tuple[str, ...] = ()) -> Path:
    """A two-model Sweet Home 3D library in the real layout; ``extra``: more lines of its properties."""
    src = tmp_path / "src"
    src.mkdir(exist_ok=True)
    write_textured_quad(src)
    path = tmp_path / "Mini.sh3f"
    props = "\n".join(
        [
            "# a comment",
            "name#1=Coffee mug",
            "category#1=Kitchen",
            "model#1=/mini/mug/quad.obj",
            "width#1=12",
            "depth#1=8",
            "height#1=10",
            "creator#1=Someone",
            "name#2=Caf\\u00e9 chair",
            "category#2=Living room",
            "model#2=/mini/chair/quad.obj",
            "width#2=40",
            "depth#2=40",
            "height#2=80",
            "modelRotation#2=1 0 0 0 0 1 0 -1 0",
            "creator#2=Other",
        ]
    )
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("PluginFurnitureCatalog.properties", props + "".join(f"\n{line}" for line in extra))
        for folder in ("mini/mug", "mini/chair"):
            for f in ("quad.obj", "quad.mtl", "tex.png"):
                archive.write(src / f, f"{folder}/{f}")
    return path


@pytest.fixture(scope="module")
def depth_frame(tmp_path_factory) -> tuple[Path, Path]:
    """A depth PNG and its intrinsics, written from a rendered view of an embedded model."""
    folder = tmp_path_factory.mktemp("frame")
    view = hd.render_view(hd.load_model(ROOT / "data/models/beer-mug/beerGlass.obj", size=(0.08, 0.15, 0.08)))
    from heatdata.views.depth import write_depth

    write_depth(view, folder / "d.png")
    return folder / "d.png", folder / "d.json"


def range_grid_ply(path, rows=20, cols=30, holes=(), cells=None):
    """A tilted plane scanned on a rows x cols grid (0.5 mm steps, y up, the scanner looking along -z), as the
    Stanford repository writes it: ASCII, obj_info num_cols/num_rows, a vertex list and a range_grid."""
    vertices, grid = [], []
    for r in range(rows):
        for c in range(cols):
            if (r, c) in holes:
                grid.append("0")
                continue
            x, y = 0.0005 * c, 0.0005 * r
            grid.append(f"1 {len(vertices)}")
            vertices.append(f"{x} {y} {0.2 * x}")
    header = [
        "ply",
        "format ascii 1.0",
        f"obj_info num_cols {cols}",
        f"obj_info num_rows {rows}",
        f"element vertex {len(vertices)}",
        "property float x",
        "property float y",
        "property float z",
        f"element range_grid {cells or rows * cols}",
        "property list uchar int vertex_indices",
        "end_header",
    ]
    path.write_text("\n".join(header + vertices + grid[: cells or rows * cols]) + "\n")
    return path
