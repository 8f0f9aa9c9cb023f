"""VFH through PCL's tools: the file round trip, the result, and a missing or failing tool."""

import os
import stat

import numpy as np
import pytest
from conftest import square_view

import heatdata as hd
from heatdata.descriptors import KINDS
from heatdata.descriptors.vfh import read_vfh, write_pcd

VFH = KINDS["vfh"]
needs_pcl = pytest.mark.skipif(VFH.unavailable() is not None, reason=str(VFH.unavailable()))


def test_pcd_is_written_as_pcl_reads_it(tmp_path):
    points = np.random.default_rng(0).random((7, 3))
    write_pcd(tmp_path / "a.pcd", points)
    raw = (tmp_path / "a.pcd").read_bytes()
    header, data = raw.split(b"DATA binary\n")
    assert b"POINTS 7" in header and np.array_equal(np.frombuffer(data, "<f4").reshape(7, 3), points.astype(np.float32))
    (tmp_path / "v.pcd").write_text("VERSION 0.7\nFIELDS vfh\nDATA ascii\n1 2 3\n")
    assert read_vfh(tmp_path / "v.pcd").tolist() == [1, 2, 3]
    (tmp_path / "bad.pcd").write_text("FIELDS x y z\nDATA binary\n")
    with pytest.raises(hd.ViewError, match="not the ASCII VFH"):
        read_vfh(tmp_path / "bad.pcd")


@needs_pcl
def test_vfh_of_a_view(mug):
    view = hd.render_view(mug, 30.0, 30.0, 1.0, seed=0)
    d, e = (hd.describe(v, [hd.DescriptorSpec("vfh")])[0] for v in (view, hd.render_view(mug, 120.0, 30.0, 1.0)))
    assert d.values.shape == (308,) and d.values.sum() == pytest.approx(1.0)
    assert d.values[:180].sum() > 0 and d.values[180:].sum() > 0  # shape bins and viewpoint bins
    assert 0 < hd.distance(d, e) < 1


def fake_tool(folder, name, code):
    path = folder / name
    path.write_text(f"#!/bin/sh\necho 'broken {name}' >&2\nexit {code}\n")
    path.chmod(path.stat().st_mode | stat.S_IEXEC)


def test_missing_tool_makes_vfh_unavailable(monkeypatch, tmp_path):
    monkeypatch.setenv("PATH", str(tmp_path))
    reason = hd.descriptors.available()["vfh"]
    assert "pcl-tools" in reason
    with pytest.raises(hd.ViewError, match="no vfh here.*pcl-tools"):
        hd.describe(square_view(11), [hd.DescriptorSpec("vfh")])


def test_failing_tool_is_an_error_naming_the_view(monkeypatch, tmp_path):
    fake_tool(tmp_path, "pcl_normal_estimation", 0)
    fake_tool(tmp_path, "pcl_vfh_estimation", 3)
    monkeypatch.setenv("PATH", f"{tmp_path}{os.pathsep}{os.environ['PATH']}")
    with pytest.raises(hd.ViewError, match="square: pcl_vfh_estimation exited with 3: broken"):
        hd.describe(square_view(11), [hd.DescriptorSpec("vfh")])
