"""Untrusted input, round 4: outputs against every input, YAML that expands, numbers out of range, segmentation of
any frame, and what a library file's checks promise. (The index file beside a library:
recognition/test_index_file.py.)"""

import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_untrusted import one_line_error

from heatdata.cli import main
from heatdata.errors import StitchError, ViewError
from heatdata.io.bounded_yaml import MAX_YAML_BYTES, brief, load_yaml
from heatdata.jasnom.cost import check_weights
from heatdata.segmentation.plane import refined_plane
from heatdata.segmentation.segment import segment_frame
from heatdata.views.depth import cut_depth, read_intrinsics
from heatdata.views.view import check_intrinsics

# -- every output against every input -----------------------------------------------------------------------------


def test_an_output_named_like_any_input_is_refused_before_the_work(tmp_path, caplog, depth_frame):
    png, intrinsics = depth_frame
    frame, camera = tmp_path / "d.png", tmp_path / "d.json"
    shutil.copy(png, frame)
    shutil.copy(intrinsics, camera)
    library, camera_png, mask, rgb = (tmp_path / name for name in ("lib.png", "cam.png", "mask.png", "rgb.png"))
    mask_npz = tmp_path / "mask.npz"
    for path in (library, mask, rgb, mask_npz):
        shutil.copy(png, path)
    camera_png.write_text(camera.read_text())  # a camera file read as YAML because it is not .json
    camera_ply, scan_rgb = tmp_path / "cam.ply", tmp_path / "a.ply"
    camera_ply.write_text(camera.read_text())
    scan_rgb.write_bytes(png.read_bytes())
    recognize = ["recognize", str(frame), "--library", str(library)]
    cases = [
        [*recognize, "--overlay", str(library)],
        [*recognize, "--intrinsics", str(camera_png), "--overlay", str(camera_png)],
        [*recognize, "--mask", str(mask), "--overlay", str(mask)],
        [*recognize, "--rgb", str(rgb), "--overlay", str(rgb)],
        [*recognize, "--overlay", str(frame)],
        ["stitch", str(frame), str(frame), "--scans", "--intrinsics", str(camera_ply), "-o", str(camera_ply)],
        ["stitch", str(frame), str(frame), "--scans", "--rgb", str(scan_rgb), str(rgb), "-o", str(scan_rgb)],
        ["segment", str(frame), "--intrinsics", str(camera_png), "-o", str(camera_png)],
        ["segment", str(frame), "-o", str(tmp_path / "labels.png"), "--rgb", str(rgb), "--overlay", str(rgb)],
        ["view-from-depth", str(frame), "--mask", str(mask_npz), "-o", str(tmp_path / "v.ply"), "-o", str(mask_npz)],
    ]
    before = {p: p.read_bytes() for p in tmp_path.iterdir()}
    for argv in cases:
        caplog.clear()
        assert main(argv) == 1, argv
        one_line_error(caplog, "is also an input")
    assert {p: p.read_bytes() for p in tmp_path.iterdir()} == before


def test_a_refused_output_leaves_no_folder_behind(tmp_path, caplog, depth_frame):
    png, intrinsics = depth_frame
    library = tmp_path / "lib.parquet"
    library.write_bytes(b"")
    for argv in (
        ["recognize", str(png), "--library", str(library), "--overlay", str(tmp_path / "new" / "o.jpg")],
        ["segment", str(png), "-o", str(tmp_path / "new2" / "labels.tif")],
        ["stitch", str(png), str(png), "-o", str(tmp_path / "new3" / "m.ply")],  # refused: add --scans
    ):
        assert main(argv) == 1, argv
    assert sorted(p.name for p in tmp_path.iterdir()) == ["lib.parquet"]


SNAKEMAKE = Path(sys.executable).parent / "snakemake"

# -- YAML that expands, numbers out of range ---------------------------------------------------------------------

LAUGHS = "\n".join(
    [f"l0: &l0 [{', '.join(['lol'] * 9)}]"] + [f"l{i}: &l{i} [{', '.join([f'*l{i - 1}'] * 9)}]" for i in range(1, 9)]
)


def test_an_intrinsics_file_of_nested_aliases_is_refused_at_once(tmp_path):
    path = tmp_path / "cam.yaml"
    path.write_text(LAUGHS + "\nfx: *l8\nfy: 500\ncx: 320\ncy: 240\nwidth: 640\nheight: 480\n")
    started = time.perf_counter()
    with pytest.raises(ViewError, match="an alias") as caught:
        read_intrinsics(path)
    assert time.perf_counter() - started < 2 and len(str(caught.value)) < 500
    path.write_text("x" * (MAX_YAML_BYTES + 1))
    with pytest.raises(ViewError, match="is not an intrinsics file"):
        read_intrinsics(path)
    with pytest.raises(ViewError, match="more than the"):
        load_yaml("x" * (MAX_YAML_BYTES + 1), "text", ViewError)


@pytest.mark.parametrize("suffix", [".yaml", ".json"])
def test_a_size_of_401_digits_is_a_bad_intrinsic_not_an_overflow(tmp_path, suffix):
    path = tmp_path / f"cam{suffix}"
    digits = "9" * 401
    path.write_text(f'{{"fx": 500, "fy": 500, "cx": 320, "cy": 240, "width": {digits}, "height": 480}}')
    with pytest.raises(ViewError, match="bad intrinsics: width=inf"):
        read_intrinsics(path)


def test_a_value_named_in_a_message_is_cut_short():
    nested: list = ["lol"]
    for _ in range(30):
        nested = [nested] * 9  # 9^30 values by reference
    started = time.perf_counter()
    with pytest.raises(ViewError) as caught:
        check_intrinsics({"fx": nested, "fy": 1, "cx": 1, "cy": 1, "width": 2, "height": 2})
    assert time.perf_counter() - started < 1 and len(str(caught.value)) < 300
    assert len(brief("x" * 10**6)) < 60 and len(brief(10**4000)) < 60


def config_error(tmp_path, text: str) -> str:
    """The first line snakemake -n prints for a config file of ``text``, within 60 s."""
    path = tmp_path / "config.yaml"
    path.write_text(text)
    run = subprocess.run(
        [
            str(SNAKEMAKE),
            "-s",
            str(ROOT / "Snakefile"),
            "-n",
            "--cores",
            "1",
            "--directory",
            str(tmp_path),
            "--configfile",
            str(path),
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert run.returncode != 0, run.stdout[-2000:]
    return next(line for line in (run.stdout + run.stderr).splitlines() if "config error" in line)


@pytest.mark.workflow
def test_a_workflow_config_of_nested_aliases_is_refused_before_the_plan(tmp_path):
    started = time.perf_counter()
    line = config_error(tmp_path, LAUGHS + "\nscenes:\n  count: *l8\n")
    assert "an alias" in line and time.perf_counter() - started < 30 and len(line) < 500


@pytest.mark.workflow
@pytest.mark.parametrize(
    ("setting", "key"),
    [
        ("scenes: {table: [0.001, 0.8]}", "scenes.table.0"),
        ("scenes: {image_scale: 0.0001}", "scenes.image_scale"),
        ("views: {image_scale: 0.0001}", "views.image_scale"),
        ("scenes: {distance: [0.001, 1.5]}", "scenes.distance.0"),
        ("stitch: {alpha: 1.0e+300}", "stitch.alpha"),
        ("stitch: {robust: 1.0e+300}", "stitch.robust"),
    ],
)
def test_absurd_settings_are_refused_by_the_schema_before_any_job(tmp_path, setting, key):
    assert key in config_error(tmp_path, setting + "\n")


@pytest.mark.parametrize("option", ["--table", "--along", "--robust", "--beta", "--gamma", "--alpha"])
def test_stitch_weights_beyond_their_range_are_refused_by_the_parser(tmp_path, option, capsys, depth_frame):
    png, _ = depth_frame
    with pytest.raises(SystemExit):
        main(["stitch", str(png), str(png), "--scans", "-o", str(tmp_path / "m.ply"), option, "1e300"])
    assert "need a number" in capsys.readouterr().err
    with pytest.raises(StitchError, match=f"{option[2:]} must be a finite"):
        check_weights(**{option[2:]: 1e300})


# -- segmentation of any frame --------------------------------------------------------------------------------------


def test_a_mask_and_a_depth_range_together_keep_what_both_keep():
    depth = np.tile(np.linspace(0.5, 2.5, 40), (30, 1))
    mask = np.zeros(depth.shape, bool)
    mask[:, :20] = True
    cut, note = cut_depth(depth, mask, (1.0, 3.0), "frame")
    kept = np.isfinite(cut)
    assert np.array_equal(kept, mask & (depth >= 1.0)) and note.startswith("segmented by the mask and depth 1-3 m")


def test_ransac_drawing_three_points_of_one_spot_gives_no_plane():
    points = np.random.default_rng(0).normal(size=(50, 3))
    plane, inliers = refined_plane(points, [0.0, 0.0, 0.0, 1.0], 0.01)
    assert len(inliers) == 0 and np.isfinite(plane).all()


@st.composite
def frames(draw):
    """A small depth frame: squares at random depths, a plane seen by a few sampled readings, or both."""
    height, width = draw(st.sampled_from([(30, 40), (48, 64), (2, 3)]))
    depth = np.full((height, width), np.nan)
    if draw(st.booleans()):
        rows = np.arange(height)[:, None] * np.ones(width)
        plane = 1.0 + draw(st.floats(0.0, 0.02)) * rows
        keep = np.random.default_rng(draw(st.integers(0, 99))).random(depth.shape) < draw(
            st.sampled_from([0.002, 0.05, 1])
        )
        depth[keep] = plane[keep]
    for _ in range(draw(st.integers(0, 60))):
        v, u, size = draw(st.integers(0, height - 1)), draw(st.integers(0, width - 1)), draw(st.integers(1, 4))
        depth[v : v + size, u : u + size] = draw(st.floats(0.3, 5.0))
    return depth


@pytest.mark.slow
@settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck))
@given(frames(), st.sampled_from([None, (0.0, 1.5)]))
def test_no_frame_makes_segmentation_raise(depth, depth_range):
    height, width = depth.shape
    camera = {"fx": 0.8 * width, "fy": 0.8 * width, "cx": width / 2, "cy": height / 2, "width": width, "height": height}
    try:
        found = segment_frame(depth, camera, depth_range=depth_range)
    except ViewError:  # no reading at all, or none in the range: one line
        return
    assert all(segment.view.n_vertices > 0 for segment in found.segments)


@pytest.mark.parametrize(
    ("change", "needle"),
    [({"fx": 1e300}, "focal length above"), ({"cx": 1e300}, "principal point"), ({"cy": -5e6}, "principal point")],
)
def test_intrinsics_out_of_any_cameras_range_are_refused(change, needle):
    camera = {"fx": 500.0, "fy": 500.0, "cx": 320.0, "cy": 240.0, "width": 640, "height": 480}
    with pytest.raises(ViewError, match=needle):
        check_intrinsics(camera | change)
