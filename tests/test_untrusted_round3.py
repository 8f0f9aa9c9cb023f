"""Untrusted input, round 3: outputs never touch inputs, interrupted and concurrent writes leave nothing wrong, every
size is bounded, and what the terminal and a program read can be trusted. (Library files: recognition/
test_library_check.py; the config's results folder and counts: experiments/test_config.py.)
"""

import io
import json
import os
import signal
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import trimesh
from PIL import Image

import heatdata as hd
from heatdata.cli import main
from heatdata.experiments.captures import find_frames
from heatdata.io.catalog import catalog_from_folder
from heatdata.io.files import atomic_group, is_partial
from heatdata.log import printable
from heatdata.views.depth import read_intrinsics
from heatdata.views.view import MAX_IMAGE_PIXELS, MAX_VIEW_VERTICES

HEATDATA = [sys.executable, "-m", "heatdata.cli"]


@pytest.fixture
def sigterm():
    """The test process's SIGTERM handler, restored after a test that runs a command (which installs its own)."""
    before = signal.getsignal(signal.SIGTERM)
    yield
    signal.signal(signal.SIGTERM, before)


def error_lines(caplog) -> list[str]:
    return [r.getMessage() for r in caplog.records if r.levelname == "ERROR"]


# -- interrupted and concurrent writes ----------------------------------------------------------------------------


def test_sigterm_while_writing_leaves_no_temporary_file(tmp_path, depth_frame):
    """SIGTERM used to end the process at once and leave ``.v.<hash>.part.npz`` (7 MB) in 3 of 7 runs."""
    script = (
        "import os, signal, sys, time\n"
        "from heatdata.views.view import View\n"
        "write = View._write_ply\n"
        "def killed(self, path):\n"
        "    write(self, path)\n"
        "    os.kill(os.getpid(), signal.SIGTERM)\n"
        "    time.sleep(30)\n"
        "View._write_ply = killed\n"
        "from heatdata.cli import main\n"
        "sys.exit(main(sys.argv[1:]))\n"
    )
    depth, intrinsics = depth_frame
    out = tmp_path / "out"
    args = ["view-from-depth", str(depth), "--intrinsics", str(intrinsics), "-o", str(out / "v.npz")]
    done = subprocess.run(
        [sys.executable, "-c", script, *args, "-o", str(out / "v.ply")], capture_output=True, timeout=120
    )
    assert done.returncode == 143, done.stderr.decode()
    assert "terminated; no output was left half written" in done.stderr.decode()
    assert list(out.iterdir()) == []


def _handler_after_setup() -> bool:
    from heatdata.log import setup_logging

    setup_logging()
    return signal.getsignal(signal.SIGTERM) is signal.SIG_DFL


def test_a_pool_worker_keeps_the_default_sigterm(sigterm):
    """A pool ends its workers with SIGTERM: a worker that raised on it instead (the demo's, which sets up logging)
    hung the pool's exit."""
    from multiprocessing import get_context

    with get_context("spawn").Pool(1) as pool:
        assert pool.apply(_handler_after_setup)


def test_folder_readers_skip_hidden_and_partial_files(tmp_path, depth_frame):
    """``recognize FOLDER --moves`` used to read an interrupted write's ``.v.<hash>.part.npz`` as a frame."""
    depth, intrinsics = depth_frame
    for name in ("a.png", ".v.0a1b2c3d.part.npz", ".hidden.png", "b.1234abcd.part.png"):
        (tmp_path / name).write_bytes(depth.read_bytes())
    (tmp_path / "camera.json").write_text(intrinsics.read_text())
    assert [f["name"] for f in find_frames(tmp_path)] == ["a"]
    assert is_partial(".x.part") and is_partial("x.part.obj") and not is_partial("partial.obj")
    models = tmp_path / "models"
    (models / "mugs").mkdir(parents=True)
    trimesh.creation.box().export(models / "mugs" / "box.ply")
    trimesh.creation.box().export(models / "mugs" / ".box.0a1b2c3d.part.ply")
    (models / ".git").mkdir()
    trimesh.creation.box().export(models / ".git" / "old.ply")
    assert catalog_from_folder(models)["file"].tolist() == ["mugs/box.ply"]


def test_two_writers_of_the_same_outputs_leave_one_of_their_sets(tmp_path, depth_frame):
    """Two ``view-from-depth`` runs 3 s apart used to leave a v.npz of 1,669 vertices beside a v.ply of 1,048,576."""
    depth, intrinsics = depth_frame
    big = tmp_path / "big.png"
    Image.fromarray(np.full((240, 320), 900, np.uint16)).save(big)
    k = json.loads(intrinsics.read_text())
    (tmp_path / "big.json").write_text(json.dumps({**k, "width": 320, "height": 240}))
    outs = ["-o", str(tmp_path / "v.npz"), "-o", str(tmp_path / "v.ply")]
    first = subprocess.Popen(
        [*HEATDATA, "view-from-depth", str(big), "--intrinsics", str(tmp_path / "big.json"), *outs]
    )
    second = subprocess.run([*HEATDATA, "view-from-depth", str(depth), "--intrinsics", str(intrinsics), *outs])
    assert first.wait(timeout=300) == 0 and second.returncode == 0
    npz, ply = hd.View.load(tmp_path / "v.npz"), trimesh.load(tmp_path / "v.ply", process=False)
    assert npz.n_vertices == len(ply.vertices)
    assert sorted(p.name for p in tmp_path.iterdir() if is_partial(p)) == []


def test_a_group_is_renamed_together_or_not_at_all(tmp_path):
    with pytest.raises(RuntimeError), atomic_group([tmp_path / "a.txt", tmp_path / "b.txt"]) as (a, b):
        a.write_text("a")
        raise RuntimeError("the second failed")
    assert list(tmp_path.iterdir()) == []
    with atomic_group([tmp_path / "a.txt", tmp_path / "sub" / "b.txt"]) as (a, b):
        a.write_text("a")
        b.write_text("b")
    assert (tmp_path / "a.txt").read_text() == "a" and (tmp_path / "sub" / "b.txt").read_text() == "b"
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["a.txt", "b.txt", "sub"]


# -- sizes ----------------------------------------------------------------------------------------------------------


def test_a_depth_image_above_the_cap_is_refused_unread(tmp_path, caplog):
    """A flat 2048 x 2048 PNG of 13 kB took 5.8 GB; 4096 x 4096 failed with a memory traceback after 8 GB."""
    for side in (2048, 4096):
        Image.fromarray(np.full((side, side), 1000, np.uint16)).save(tmp_path / "flat.png")
        (tmp_path / "flat.json").write_text(
            json.dumps({"fx": 580, "fy": 580, "cx": side / 2, "cy": side / 2, "width": side, "height": side})
        )
        caplog.clear()
        code = main(["view-from-depth", str(tmp_path / "flat.png"), "--intrinsics", str(tmp_path / "flat.json"),
                     "-o", str(tmp_path / "v.npz")])  # fmt: skip
        assert code == 1 and len(error_lines(caplog)) == 1
        assert f"{side}x{side} pixels, above the cap of 2.1 Mpixel" in error_lines(caplog)[0]
    assert MAX_IMAGE_PIXELS >= 1920 * 1080  # a full-HD sensor fits


def npz_claiming(path: Path, shapes: dict[str, tuple[int, ...]]) -> None:
    """A .npz whose members' headers claim ``shapes`` and whose data are absent (a few bytes for any size)."""
    with zipfile.ZipFile(path, "w") as archive:
        for name, shape in shapes.items():
            header = io.BytesIO()
            np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": shape})
            archive.writestr(f"{name}.npy", header.getvalue())


@pytest.mark.parametrize(
    "shapes, needle",
    [
        ({"vertices": (50_000_000, 3)}, "its vertices hold 50,000,000 rows"),
        ({"faces": (3 * MAX_VIEW_VERTICES, 3)}, "its faces hold"),
        ({"repairs": (10**9,)}, "its repairs hold"),
        ({"vertices": (MAX_VIEW_VERTICES + 1, 3)}, "at most 2,097,152 vertices"),
        # a flat full-HD frame's view is not refused for its size (its arrays are absent here, so it is unreadable)
        ({"vertices": (1920 * 1080, 3), "faces": (4_141_202, 3)}, "not a readable heatdata view"),
    ],
)
def test_a_saved_view_too_large_is_refused_from_its_headers(tmp_path, shapes, needle):
    """A 1.2 MB .npz of 50M vertices took 2.5 GB before it was refused."""
    npz_claiming(tmp_path / "v.npz", shapes)
    with pytest.raises(hd.ViewError, match=needle):
        hd.View.load(tmp_path / "v.npz")


def test_sample_and_particle_counts_are_bounded(tmp_path, capsys):
    a = tmp_path / "a.ply"
    trimesh.creation.box().export(a)
    for argv, needle in (
        (["stitch", str(a), str(a), "-o", str(tmp_path / "s.ply"), "--samples", "100000000"], "[8, 2048]"),
        (["recognize", str(a), "--library", str(a), "--particles", "1000000000"], "[1, 1000000]"),
        (["describe", str(a), "--samples", "1000000000"], "[0, 4096]"),
    ):
        with pytest.raises(SystemExit) as exited:
            main(argv)
        assert exited.value.code == 2 and needle in capsys.readouterr().err
    with pytest.raises(hd.StitchError, match=r"samples must be a whole number in \[8, 2048\]"):
        hd.stitch(hd.load_model(a), hd.load_model(a), samples=10**8)
    from heatdata.recognition.multiview.filters import ParticleFilter

    with pytest.raises(hd.HeatdataError, match="particles must be a whole number in"):
        ParticleFilter(pd.DataFrame(), pd.DataFrame(), particles=10**9)
    with pytest.raises(hd.SpecError, match="option samples must be in 2..4096"):
        hd.DescriptorSpec("pvhk", samples=10**9)


# -- what the terminal and a program read ---------------------------------------------------------------------------


def test_printed_names_cannot_drive_the_terminal():
    assert printable("mug\x1b[2J\nforged line\r\x07\x9b") == "mug\\x1b[2J\\nforged line\\r\\x07\\x9b"
    assert printable("café 杯 ☕") == "café 杯 ☕"


def test_log_lines_escape_the_names_in_them(tmp_path):
    library = tmp_path / "evil\x1b[2J\nERROR forged.parquet"
    done = subprocess.run([*HEATDATA, "recognize", "f.png", "--library", str(library)], capture_output=True, text=True)
    assert done.returncode == 1 and "\x1b" not in done.stderr and done.stderr.count("\n") == 1, done.stderr
    assert "\\x1b[2J\\nERROR forged" in done.stderr


def test_json_intrinsics_are_read_as_json(tmp_path):
    """``"fx": 5.8e2`` (YAML 1.1 reads it as text) was refused; ``1`` + 400 zeros gave an OverflowError."""
    k = {"fx": "5.8e2", "fy": "5.8e2", "cx": "319.5", "cy": "239.5", "width": "640", "height": "480"}
    (tmp_path / "k.json").write_text("{" + ", ".join(f'"{key}": {v}' for key, v in k.items()) + "}")
    assert read_intrinsics(tmp_path / "k.json")["fx"] == 580.0
    (tmp_path / "k.json").write_text((tmp_path / "k.json").read_text().replace("5.8e2", "1" + "0" * 400, 1))
    with pytest.raises(hd.ViewError, match="bad intrinsics: fx=inf"):
        read_intrinsics(tmp_path / "k.json")
    (tmp_path / "k.yaml").write_text("fx: " + "1" + "0" * 400 + "\nfy: 1\ncx: 1\ncy: 1\nwidth: 2\nheight: 2\n")
    with pytest.raises(hd.ViewError, match="bad intrinsics: fx=inf"):
        read_intrinsics(tmp_path / "k.yaml")


def test_json_output_is_strict(tmp_path, capsys, sigterm):
    """``--json`` printed NaN (not JSON)."""
    from heatdata.cli.arguments import dump_json

    printed = dump_json({"a": float("nan"), "b": [np.float32(np.inf), 2**400, 10**400, np.int64(3)]})
    assert json.loads(printed) == {"a": None, "b": [None, float(2**400), None, 3]}
    box = tmp_path / "box.ply"
    trimesh.creation.box(extents=(0.2, 0.1, 0.15)).export(box)
    assert main(["render", str(box), "--out", str(tmp_path / "v.npz")]) == 0
    capsys.readouterr()
    assert main(["describe", str(tmp_path / "v.npz"), "--kind", "esf"]) == 0
    printed = capsys.readouterr().out

    def refuse(constant):
        raise AssertionError(f"{constant} is not JSON")

    json.loads(printed, parse_constant=refuse)


# -- other inputs ---------------------------------------------------------------------------------------------------


def test_a_motion_far_away_or_not_finite_says_so(tmp_path, caplog):
    """A 1e300 translation gave an IndexError; a NaN motion was reported as 'got shape (4, 4)'."""
    from heatdata.io.models import rigid_motion

    far = np.eye(4)
    far[0, 3] = 1e300
    with pytest.raises(hd.StitchError, match="translation 1e\\+300 is beyond 1e\\+06"):
        rigid_motion(far)
    with pytest.raises(hd.StitchError, match="of finite numbers, got 1 NaN or infinite"):
        rigid_motion(np.diag([np.nan, 1, 1, 1]))
    with pytest.raises(hd.StitchError, match="its 3x3 part is not a rotation"):
        rigid_motion(np.diag([2.0, 1, 1, 1]))
    with pytest.raises(hd.StitchError, match=r"got shape \(3, 3\)"):
        rigid_motion(np.eye(3))


def test_a_tiff_renamed_png_is_not_read_as_millimetres(tmp_path):
    """A 32-bit TIFF renamed .png was read as depths of 2,147 km."""
    Image.fromarray(np.full((24, 32), 2_147_483_647, np.int32)).save(tmp_path / "d.tiff")
    os.replace(tmp_path / "d.tiff", tmp_path / "d.png")
    with pytest.raises(hd.ViewError, match="must be a PNG, this is TIFF"):
        hd.read_depth(tmp_path / "d.png", _intrinsics(tmp_path, 32, 24))
    Image.fromarray(np.full((24, 32), 200, np.uint8)).save(tmp_path / "e.png")
    with pytest.raises(hd.ViewError, match="16-bit"):
        hd.read_depth(tmp_path / "e.png", _intrinsics(tmp_path, 32, 24))


def _intrinsics(folder: Path, width: int, height: int) -> Path:
    path = folder / "k.json"
    path.write_text(
        json.dumps({"fx": 30, "fy": 30, "cx": width / 2, "cy": height / 2, "width": width, "height": height})
    )
    return path


@pytest.mark.parametrize("face", ["f 0 2 3", "f 1/0 2/1 3/1", "f  2 0 3"])
def test_an_obj_face_index_0_is_refused(tmp_path, face):
    (tmp_path / "m.obj").write_text(f"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1 2 3\n{face}\n")
    with pytest.raises(hd.ModelError, match="line 6: a face index 0"):
        hd.load_model(tmp_path / "m.obj")
    (tmp_path / "m.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 10\nvt 0 0\nf 1/1 2/1 3/1\nf 1 2 4\n")
    assert len(hd.load_model(tmp_path / "m.obj").faces) == 2  # coordinates of 0 and 10 are not face indices


def test_a_rump_mesh_with_a_face_out_of_range_is_one_error():
    from heatdata.rump import hbrd

    vertices = np.random.default_rng(0).normal(size=(10, 3))
    with pytest.raises(hd.RumpError, match="face indices run from 0 to 10, not within the 10 vertices"):
        hbrd(vertices, np.array([[0, 1, 10]]), vertices[:4])
