"""PCD files as PCL writes them (heatdata.frames.pcd): a real Kinect frame in every DATA kind, unorganized clouds put
back on their pixels, what heatdata writes read by PCL, and bad files refused in one line."""

import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import heatdata as hd
from heatdata.frames.clouds import read_cloud_grid
from heatdata.frames.pcd import read_pcd, write_pcd
from heatdata.views.depth import read_intrinsics

MOSD = Path(__file__).parents[1] / "data" / "mosd"
FRAME = MOSD / "learn20.pcd"
PCL_CONVERT = shutil.which("pcl_convert_pcd_ascii_binary")


def test_a_binary_compressed_kinect_frame_reads_with_its_grid_colours_and_labels():
    cloud = read_pcd(FRAME)
    assert cloud.organized and cloud.points.shape == (480, 640, 3)
    readings = np.isfinite(cloud.points).all(axis=2)
    assert 150_000 < readings.sum() < 307_200  # NaN where the Kinect saw nothing
    assert set(cloud.fields) == {"label"} and cloud.fields["label"].shape == (480, 640)
    assert cloud.colors is not None and 0 <= cloud.colors.min() and cloud.colors.max() <= 1
    # the PNG frame made from the same cloud: the same depths, in millimetres
    depth = hd.read_depth_frame(MOSD / "learn20.depth.png", MOSD / "intrinsics.json")[0]
    assert np.allclose(depth[readings], cloud.points[readings][:, 2], atol=6e-4)


@pytest.mark.skipif(PCL_CONVERT is None, reason="PCL's tools (scripts/setup.sh --tests installs pcl-tools)")
@pytest.mark.parametrize("kind", [0, 1])  # PCL's own ascii and binary
def test_ascii_and_binary_pcd_written_by_pcl_read_the_same(tmp_path, kind):
    converted = tmp_path / "frame.pcd"
    subprocess.run([PCL_CONVERT, str(FRAME), str(converted), str(kind)], check=True, capture_output=True)
    assert f"DATA {'ascii' if kind == 0 else 'binary'}" in converted.read_bytes()[:400].decode("ascii", "replace")
    a, b = read_pcd(FRAME), read_pcd(converted)
    assert np.array_equal(np.isnan(a.points), np.isnan(b.points))
    assert np.allclose(np.nan_to_num(a.points), np.nan_to_num(b.points), atol=1e-6)
    assert np.allclose(a.colors, b.colors) and np.array_equal(a.fields["label"], b.fields["label"])


def test_an_unorganized_cloud_with_intrinsics_is_the_organized_frame(tmp_path):
    from pypcd4 import Encoding, PointCloud

    organized = read_pcd(FRAME)
    readings = np.isfinite(organized.points).all(axis=2)
    flat = PointCloud.from_xyzrgb_points(
        np.column_stack([organized.points[readings], PointCloud.encode_rgb(organized.colors[readings] * 255)])
    )
    flat.save(tmp_path / "flat.pcd", encoding=Encoding.BINARY_COMPRESSED)
    with pytest.raises(hd.ViewError, match=r"unorganized cloud .* \(--intrinsics\)"):
        read_cloud_grid(tmp_path / "flat.pcd")
    points, colors, k = read_cloud_grid(tmp_path / "flat.pcd", intrinsics=read_intrinsics(MOSD / "intrinsics.json"))
    assert points.shape == (480, 640, 3) and k["fx"] == 525.0
    assert np.array_equal(np.isfinite(points).all(axis=2), readings)
    assert np.allclose(points[readings], organized.points[readings], atol=1e-6)
    assert np.allclose(colors[readings], organized.colors[readings], atol=1 / 255)


def test_what_heatdata_writes_pcl_reads(tmp_path):
    organized = read_pcd(FRAME)
    written = write_pcd(tmp_path / "out.pcd", organized.points, organized.colors)
    assert b"DATA binary_compressed" in written.read_bytes()[:400]
    again = read_pcd(written)
    assert np.allclose(np.nan_to_num(again.points), np.nan_to_num(organized.points)) and again.organized
    assert np.allclose(again.colors, organized.colors)
    pcd2ply = shutil.which("pcl_pcd2ply")
    if pcd2ply is None:
        pytest.skip("PCL's tools (scripts/setup.sh --tests installs pcl-tools)")
    out = subprocess.run([pcd2ply, str(written), str(tmp_path / "out.ply")], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert "Loading" in out.stdout and "307200 points" in out.stdout and "Available dimensions: x y z rgb" in out.stdout


def _pcd(header: str, body: bytes = b"") -> bytes:
    return header.strip().encode() + b"\n" + body


HEADER = """VERSION 0.7
FIELDS x y z
SIZE 4 4 4
TYPE F F F
COUNT 1 1 1
WIDTH {w}
HEIGHT {h}
VIEWPOINT 0 0 0 1 0 0 0
POINTS {n}
DATA {data}"""


@pytest.mark.parametrize(
    "content, message",
    [
        (_pcd(HEADER.format(w=4, h=2, n=8, data="binary"), np.ones(10, "<f4").tobytes()), "truncated|cannot read"),
        (_pcd(HEADER.format(w=4, h=2, n=8, data="binary_scrambled")), "DATA 'binary_scrambled'"),
        (_pcd(HEADER.format(w=4, h=2, n=8, data="ascii"), b"nan nan nan\n" * 8), "all NaN"),
        (_pcd(HEADER.format(w=4, h=2, n=9, data="ascii"), b"1 1 1\n" * 9), "9 POINTS for a grid of WIDTH 4 x HEIGHT 2"),
        (_pcd(HEADER.format(w=4, h=2, n=8, data="binary_compressed"), b"\x10\x00\x00\x00\x60"), "cannot read"),
        (b"\x89PNG not a cloud", "not a PCD file"),
    ],
)
def test_a_bad_pcd_is_one_clear_line_naming_the_file(tmp_path, content, message):
    path = tmp_path / "bad.pcd"
    path.write_bytes(content)
    with pytest.raises(hd.ViewError, match=message) as error:
        read_pcd(path)
    assert str(path) in str(error.value) and "\n" not in str(error.value)


def test_view_from_depth_writes_a_pcd_of_the_frame_as_the_sensor_gave_it(tmp_path):
    from heatdata.cli import main

    out = tmp_path / "view.pcd"
    args = [str(MOSD / "learn20.depth.png"), "--intrinsics", str(MOSD / "intrinsics.json")]
    assert main(["view-from-depth", *args, "--rgb", str(MOSD / "learn20.rgb.png"), "-o", str(out)]) == 0
    cloud = read_pcd(out)
    assert cloud.organized and cloud.points.shape == (480, 640, 3) and cloud.colors is not None
    view = hd.read_depth(MOSD / "learn20.depth.png", MOSD / "intrinsics.json", MOSD / "learn20.rgb.png")
    on = np.isfinite(cloud.points).all(axis=2)
    assert on.sum() == view.n_vertices  # each vertex on its own pixel, NaN elsewhere
    pixels = np.round(view.pixels).astype(int)
    assert np.allclose(cloud.points[pixels[:, 1], pixels[:, 0]], view.vertices, atol=1e-6)
    assert np.allclose(cloud.colors[pixels[:, 1], pixels[:, 0]], view.colors, atol=1 / 255)


def test_an_ascii_block_cut_to_one_point_is_truncated_not_a_traceback(tmp_path):
    header = "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 32\nHEIGHT 24\n"
    path = tmp_path / "cut.pcd"
    path.write_text(header + "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 768\nDATA ascii\n-0.51667 -0.38333 1")
    with pytest.raises(hd.ViewError, match="cut.pcd"):
        read_pcd(path)
