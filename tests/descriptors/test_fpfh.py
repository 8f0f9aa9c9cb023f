"""FPFH pooled over a view: a plane's analytic histogram, bad input."""

import numpy as np
import pytest
from conftest import square_view

import heatdata as hd


def test_plane_fpfh_has_one_bin_per_sub_histogram():
    """On a plane every pair of normals is parallel and perpendicular to the joining line: the three
    angle features take one value each, so the pooled histogram is 1/3 in one bin of each 11-bin part."""
    d = hd.describe(square_view(41, 0.004), [hd.DescriptorSpec("fpfh")])[0]
    assert d.values.shape == (33,) and d.values.sum() == pytest.approx(1.0)
    top = np.sort(d.values)[::-1]
    assert np.allclose(top[:3], 1 / 3, atol=1e-3) and top[3] < 1e-3
    assert sorted(np.argsort(d.values)[::-1][:3] // 11) == [0, 1, 2]


def test_bent_surface_spreads_the_histogram():
    plane = square_view(41, 0.004)
    bent = hd.View.from_arrays(
        plane.vertices + np.c_[0 * plane.vertices[:, :2], 20 * plane.vertices[:, 0] ** 2], plane.faces
    )
    a, b = (hd.describe(v, [hd.DescriptorSpec("fpfh")])[0] for v in (plane, bent))
    assert np.sort(b.values)[::-1][:3].sum() < 0.92 and hd.distance(a, b) > 0.04  # measured 0.89, 0.056


def test_fpfh_options_and_small_views():
    with pytest.raises(hd.SpecError, match="radius"):
        hd.DescriptorSpec("fpfh", radius=-1)
    with pytest.raises(hd.ViewError, match="too few"):
        hd.describe(square_view(6), [hd.DescriptorSpec("fpfh")])


def test_views_with_read_only_arrays():
    """Views read from Parquet tables hold read-only arrays, which open3d refuses unless copied."""
    plane = square_view(21, 0.004)
    vertices, faces = plane.vertices.copy(), plane.faces.copy()
    vertices.setflags(write=False)
    faces.setflags(write=False)
    frozen = hd.View(vertices=vertices, faces=faces, colors=plane.colors, intrinsics=plane.intrinsics)
    (d,) = hd.describe(frozen, [hd.DescriptorSpec("fpfh")])
    assert np.allclose(d.values, hd.describe(plane, [hd.DescriptorSpec("fpfh")])[0].values)
