"""Untrusted input, round 4: outputs against every input, YAML that expands, numbers out of range, segmentation of
any frame, and what a library file's checks promise. (The index file beside a library:
recognition/test_index_file.py.)"""

import shutil

import pytest
from test_untrusted import one_line_error

from heatdata.cli import main

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
