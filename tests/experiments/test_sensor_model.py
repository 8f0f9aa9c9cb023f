"""The sensor measured on frames (heatdata.experiments.sensor_model), against frames whose noise, steps, holes and
flying pixels are known: a rendered table-top through chosen profiles, and the vendored real Kinect frame."""

import numpy as np
import pytest
from conftest import ROOT

import heatdata as hd
from heatdata.experiments.scenes import TABLE_HEIGHT, object_pose, room
from heatdata.experiments.sensor_model import fit_tau, measure_frame, pooled
from heatdata.views.depth import read_depth_frame
from heatdata.views.render import Placement, camera_pose, render_scene
from heatdata.views.sensor import SensorProfile

QUIET = {"shadows": False, "disparity_step": 0.0, "flying_pixels": 0.0, "dark": 0.0}


@pytest.fixture(scope="module")
def table_top():
    catalog = hd.read_catalog(ROOT / "data/models/catalog.csv").set_index("object")
    mug = hd.load_catalog_model(catalog.loc["beer-mug"].to_dict() | {"object": "beer-mug"})
    placed = [*room(1.2, 0.8, 0.05), Placement(mug, object_pose(mug, 0.0, 0.0, 30.0))]
    return placed, camera_pose(np.array([0.0, TABLE_HEIGHT, 0.0]), 0.0, 45.0, 0.9)


def measured(table_top, **fields):
    placed, camera = table_top
    frame = render_scene(placed, camera, sensor=SensorProfile(**fields), seed=0)
    return measure_frame(frame.depth, frame.intrinsics, frame.rgb)


def test_the_noise_a_profile_adds_is_measured_back_on_the_table(table_top):
    noisy = pooled([measured(table_top, tau=2e-3, **QUIET)], "rendered")
    assert fit_tau(noisy["noise"], min_windows=5) == pytest.approx(2e-3, rel=0.15)
    assert fit_tau(pooled([measured(table_top, tau=0.0, **QUIET)], "r")["noise"], min_windows=5) < 1e-4
    stepped = measured(table_top, tau=0.0, **(QUIET | {"depth_unit": 0.004}))
    assert np.nanmedian(stepped.windows["step"]) == pytest.approx(0.004, rel=1e-3)


def test_flying_pixels_are_the_ring_readings_between_object_and_table(table_top):
    clean = measured(table_top, tau=0.0, **QUIET).ring
    flying = measured(table_top, tau=0.0, **(QUIET | {"flying_pixels": 0.8})).ring
    # without flying pixels, only the mug's body seen through its handle lies between (1.5%)
    assert clean["between"] / clean["ring"] < 0.03 and clean["hole"] == 0
    assert flying["between"] / flying["ring"] > 3 * clean["between"] / clean["ring"]
    assert flying["halo"] <= flying["between"]
    shadowed = measured(table_top, tau=0.0, **(QUIET | {"shadows": True})).ring
    assert shadowed["hole"] / shadowed["ring"] > 0.05  # the projector's shadow beside the mug


def test_a_real_kinect_table_is_measured_near_the_thesis_noise():
    folder = ROOT / "tests" / "data" / "mosd"
    depth, rgb, k = read_depth_frame(
        folder / "learn20.depth.png", folder / "intrinsics.json", folder / "learn20.rgb.png"
    )
    found = pooled([measure_frame(depth, k, rgb)], "kinect")
    assert 0.7e-3 < fit_tau(found["noise"], unit=0.001, min_windows=5) < 2.5e-3  # 2.6.1: 1.42e-3
    assert (found["noise"]["step"] >= 0.001).all()  # whole millimetres at least
    assert set(found["ring"]) == {"sensor", "pixels", "hole", "object", "table", "between", "halo"}
    assert abs(sum(found["ring"][k] for k in ("hole", "object", "table", "between")) - 1.0) < 1e-9
    assert set(found["dark"].columns) >= {"luminance", "pixels", "holes", "share"}
