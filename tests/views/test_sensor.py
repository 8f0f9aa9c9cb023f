"""The sensor profile: the Kinect's noise, projector shadows, disparity steps, flying pixels and dark surfaces,
each against an analytic answer."""

import numpy as np
import pytest
from conftest import colored_box

import heatdata as hd
from heatdata.views.render import Placement, render_scene
from heatdata.views.sensor import SENSORS, SensorProfile, depth_edges, quantize_depth


def flat(name, extents, color):
    box = colored_box(extents)
    return hd.Model.untextured(name, np.asarray(box.vertices), np.asarray(box.faces), color)


def at(z, x=0.0):
    pose = np.eye(4)
    pose[:3, 3] = [x, 0.0, z]
    return pose


CAMERA = np.eye(4)  # at the origin looking down +z, x right, y down


def test_disparity_steps_are_about_three_millimetres_at_one_metre():
    depth = np.linspace(0.99, 1.01, 2001)[None, :]
    measured = quantize_depth(depth, 580.0, 0.075, 1 / 8)
    steps = np.unique(np.round(measured, 9))
    gaps = np.diff(steps)
    assert gaps.mean() == pytest.approx(1.0**2 * (1 / 8) / (580.0 * 0.075), rel=0.03)  # dz = z^2 dd / (f b)
    assert np.abs(measured - depth).max() <= gaps.max() / 2 + 1e-9
    disparity = 580.0 * 0.075 / measured
    assert np.allclose(disparity * 8, np.round(disparity * 8))  # on the 1/8 pixel grid


def test_the_projector_shadow_is_the_band_left_of_a_box_its_width_analytic():
    wall = flat("wall", (3.0, 3.0, 0.01), (0.8, 0.8, 0.8))
    box = flat("box", (0.2, 0.2, 0.2), (0.8, 0.2, 0.2))
    frame = render_scene(
        [Placement(wall, at(2.0)), Placement(box, at(1.1))],
        CAMERA,
        sensor=SensorProfile(tau=0.0, disparity_step=0.0, flying_pixels=0.0, dark=0.0),
    )
    row = 240
    missing = np.flatnonzero(np.isnan(frame.depth[row]) & (frame.labels[row] == 0))
    assert len(missing) and missing.max() < 319.5  # left of the box, on the wall
    # the projector 7.5 cm right of the camera: the ray from it over the box's front left corner (x = -0.1,
    # z = 1.0) meets the wall (its face at z = 1.995) further left than the camera's ray over the same corner
    wall_z = 1.995
    shadow_left = 0.075 + (-0.1 - 0.075) * wall_z / 1.0
    camera_left = -0.1 * wall_z / 1.0
    assert len(missing) == pytest.approx(580.0 * (camera_left - shadow_left) / wall_z, abs=1.5)
    assert not np.isnan(frame.depth[row][frame.labels[row] == 1]).any()  # the box itself is lit


def test_flying_pixels_lie_between_the_two_sides_of_an_edge():
    depth = np.full((40, 40), 2.0)
    depth[:, :20] = 1.0
    edge, other = depth_edges(depth)
    assert edge[:, 19].all() and edge[:, 20].all() and not edge[:, :19].any() and not edge[:, 21:].any()
    profile = SensorProfile(tau=0.0, shadows=False, disparity_step=0.0, flying_pixels=1.0, dark=0.0)
    measured = profile.measure(depth, None, 580.0, np.random.default_rng(0))
    moved = measured[:, 19:21]
    assert ((moved > 1.0) & (moved < 2.0)).all()
    assert np.array_equal(measured[:, :19], depth[:, :19]) and np.array_equal(measured[:, 21:], depth[:, 21:])


def test_dark_surfaces_give_no_depth():
    depth = np.ones((4, 4))
    colors = np.full((4, 4, 3), 0.5)
    colors[0, 0] = 0.01
    profile = SensorProfile(tau=0.0, shadows=False, disparity_step=0.0, flying_pixels=0.0, dark=0.04)
    measured = profile.measure(depth, colors, 580.0, np.random.default_rng(0))
    assert np.isnan(measured[0, 0]) and np.isfinite(measured).sum() == 15


def test_the_noise_profile_renders_the_views_every_run_renders(mug):
    before = hd.render_view(mug, 40.0, 30.0, 1.0, seed=3)
    profiled = hd.render_view(mug, 40.0, 30.0, 1.0, seed=3, sensor="noise")
    assert np.array_equal(before.vertices, profiled.vertices)
    ideal = hd.render_view(mug, 40.0, 30.0, 1.0, sensor="ideal")
    assert np.array_equal(ideal.vertices, hd.render_view(mug, 40.0, 30.0, 1.0, noise=False).vertices)


def test_the_kinect_profile_loses_readings_and_steps_the_depth(mug):
    noise = hd.render_view(mug, 40.0, 30.0, 1.0, seed=3, sensor="noise", components="all")
    kinect = hd.render_view(mug, 40.0, 30.0, 1.0, seed=3, sensor="kinect", components="all")
    assert kinect.n_vertices < noise.n_vertices  # the handle's shadow on the body, the rim's edges
    disparity = 580.0 * 0.075 / kinect.vertices[:, 2]
    assert np.allclose(disparity * 8, np.round(disparity * 8), atol=1e-6)


def test_profiles_by_name_and_by_fields():
    assert SensorProfile.named("kinect") == SENSORS["kinect"]
    assert SensorProfile.named(None) == SENSORS["noise"]
    assert SensorProfile.named({"profile": "kinect", "dark": 0.0}).dark == 0.0
    assert SensorProfile.named({"flying_pixels": 0.2}).shadows  # from the Kinect's
    for bad in ("kinnect", {"darkness": 1}, 3):
        with pytest.raises(hd.RenderError):
            SensorProfile.named(bad)
    for fields in ({"tau": -1.0}, {"flying_pixels": 1.5}, {"dark": 1.0}, {"baseline": 0.0}, {"tau": float("nan")}):
        with pytest.raises(hd.RenderError, match="bad sensor profile"):
            SensorProfile(**fields)


def test_a_realsense_stores_whole_millimetres_with_less_noise_than_a_kinect(mug):
    realsense = hd.render_view(mug, 40.0, 30.0, 0.7, seed=3, sensor="realsense", components="all")
    z = realsense.vertices[:, 2]
    assert np.allclose(z * 1000, np.round(z * 1000), atol=1e-6)  # whole millimetres, as a uint16 PNG holds them
    assert SENSORS["realsense"].tau < SENSORS["kinect"].tau < SENSORS["noise"].tau
    unit = SensorProfile(tau=0.0, shadows=False, disparity_step=0.0, flying_pixels=0.0, dark=0.0, depth_unit=0.001)
    measured = unit.measure(np.array([[1.2344, 1.2346, np.nan]]), None, 580.0, np.random.default_rng(0))
    assert np.allclose(measured[0, :2], [1.234, 1.235]) and np.isnan(measured[0, 2])
    with pytest.raises(hd.RenderError, match="depth_unit"):
        SensorProfile(depth_unit=-0.001)
