"""The pointnet kind: the network's shapes and invariances analytically, then trained on library views, described,
stored in a library file, and refused when its weights were trained on other objects."""

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT, square_view

import heatdata as hd
from heatdata.descriptors import pointnet
from heatdata.descriptors.rows import descriptor_rows
from heatdata.errors import LibraryError
from heatdata.experiments.describe import describe_view_table, fit_view_tables
from heatdata.experiments.views import render_object_views, render_views, view_plan
from heatdata.recognition.evaluate import classify
from heatdata.recognition.library import build_library, write_library
from heatdata.views.view import kinect_intrinsics

OBJECTS = ("beer-mug", "milk-carton", "bread")
SPEC = hd.DescriptorSpec("pointnet", points=256, steps=150, train_views=8)


def random_fit(spec, objects=OBJECTS, seed=0):
    rng = np.random.default_rng(seed)
    fit = {name: rng.normal(0, 0.3, shape) for name, shape in pointnet.layer_shapes(spec).items()}
    return {**fit, "objects": pointnet.objects_digest(objects)}


def test_the_layers_are_as_wide_as_the_spec_says():
    shapes = pointnet.layer_shapes(hd.DescriptorSpec("pointnet", embedding=16))
    assert shapes["point0_w"] == (6, 64) and shapes["point2_w"] == (128, 256) and shapes["dense1_w"] == (256, 16)
    assert pointnet.layer_shapes(hd.DescriptorSpec("pointnet", width=1024))["dense0_w"] == (1024, 256)
    assert pointnet.layer_shapes(hd.DescriptorSpec("pointnet", color="none"))["point0_w"] == (3, 64)
    assert hd.DescriptorSpec("pointnet").impl.fitted_shapes(hd.DescriptorSpec("pointnet"))["objects"] == (32,)
    assert hd.DescriptorSpec("pointnet", color="none", train_views=40).name == "pointnet/color=none/train_views=40"


def test_the_digest_names_the_objects_not_their_order():
    assert np.array_equal(pointnet.objects_digest(["a", "b"]), pointnet.objects_digest(["b", "a", "a"]))
    assert not np.array_equal(pointnet.objects_digest(["a", "b"]), pointnet.objects_digest(["a", "c"]))


def test_the_embedding_does_not_depend_on_the_order_of_the_points():
    spec = hd.DescriptorSpec("pointnet", embedding=8)
    params = random_fit(spec)
    clouds = np.random.default_rng(1).normal(0, 0.1, (2, 50, 6))
    shuffled = clouds[:, np.random.default_rng(2).permutation(50)]
    assert np.allclose(pointnet.embed(params, clouds), pointnet.embed(params, shuffled))
    assert pointnet.embed(params, clouds).shape == (2, 8)


def test_a_view_is_its_canonical_points_centred_with_colours_less_a_half():
    view = square_view(11)
    spec = hd.DescriptorSpec("pointnet")
    points = pointnet.view_points(view, spec, view.n_vertices, 0)  # every vertex, drawn once
    assert points.shape == (121, 6) and points.dtype == np.float32
    assert np.allclose(points[:, :3].mean(axis=0), 0.0, atol=1e-6)
    assert np.allclose(np.sort(points[:, 3]), np.sort(view.colors[:, 0] - 0.5), atol=1e-6)
    assert pointnet.view_points(view, hd.DescriptorSpec("pointnet", color="none"), 500, 0).shape == (500, 3)
    same = pointnet.view_points(view, spec, 64, 3)
    assert np.array_equal(same, pointnet.view_points(view, spec, 64, 3))  # seeded: a view is always described alike


def test_it_must_be_trained_first_and_on_two_objects_at_least():
    with pytest.raises(hd.SpecError, match="trained on library views first"):
        hd.describe(square_view(11), [SPEC])
    with pytest.raises(hd.ViewError, match="views of 2 objects or more"):
        hd.fit_spec(SPEC, [square_view(11), square_view(13)])


@pytest.fixture(scope="module")
def trained():
    """Three embedded objects, 8 library views and 4 test views each; the pointnet trained on the library views."""
    catalog = hd.read_catalog(ROOT / "data/models/catalog.csv")
    views = {"train": 8, "test": 4, "elevation": 30.0, "distance": 1.0, "noise": True, "seed": 0, "image_scale": 0.5}
    frames = [render_object_views(catalog[catalog["object"] == obj].iloc[0].to_dict(), views) for obj in OBJECTS]
    spec = fit_view_tables(frames, SPEC)
    table = pd.concat([describe_view_table(f, [spec]) for f in frames], ignore_index=True)
    return spec, table


@pytest.mark.slow
def test_trained_on_the_library_views_it_names_the_test_views(trained):
    spec, table = trained
    assert set(spec.fitted) == set(spec.impl.fitted_shapes(spec))
    assert np.array_equal(spec.fitted["objects"], pointnet.objects_digest(OBJECTS))
    answers = classify(table, spec.name)
    assert len(answers) == 12 and answers["correct"].mean() >= 0.9, answers[["object", "predicted_object"]]


@pytest.mark.slow
def test_a_library_keeps_its_weights_and_refuses_weights_of_other_objects(trained, tmp_path):
    spec, table = trained
    rows, metadata = build_library(table, spec, 8, source="test")
    write_library(rows, metadata, tmp_path / "lib.parquet")
    library = hd.load_library(tmp_path / "lib.parquet")
    assert library.spec == spec and all(np.array_equal(library.spec.fitted[k], spec.fitted[k]) for k in spec.fitted)

    foreign = {**metadata, "spec": {**metadata["spec"], "fitted": random_fit(spec, ("a", "b"))}}
    foreign["spec"]["fitted"] = {k: v.tolist() for k, v in foreign["spec"]["fitted"].items()}
    write_library(rows, foreign, tmp_path / "foreign.parquet")
    with pytest.raises(LibraryError, match="trained on other objects than the library's 3"):
        hd.load_library(tmp_path / "foreign.parquet")

    other = random_fit(spec)  # the library's objects, but not the weights it described its probe with
    changed = {**metadata, "spec": {**metadata["spec"], "fitted": {k: v.tolist() for k, v in other.items()}}}
    write_library(rows, changed, tmp_path / "changed.parquet")
    with pytest.raises(LibraryError, match="probe"):
        hd.load_library(tmp_path / "changed.parquet")


@pytest.mark.slow
def test_an_object_off_the_optical_axis_gets_the_answer_it_gets_at_the_centre(trained):
    """The other kinds' test (test_invariance.py) on the trained network: 15 cm off the axis at 1 m."""
    spec, table = trained
    library = table[table["split"] == "train"]
    camera = kinect_intrinsics(0.5)
    catalog = hd.read_catalog(ROOT / "data/models/catalog.csv")
    answers = {}
    for name, shift in {"centred": (0.0, 0.0), "off-axis": (0.15 * camera["fx"], 0.0)}.items():
        views, plans = [], []
        for obj in OBJECTS:
            plan = view_plan([obj], 8, 4, seed=0)
            plan = plan[plan["split"] == "test"]
            model = hd.load_catalog_model(catalog[catalog["object"] == obj].iloc[0].to_dict())
            views += render_views(model, plan, noise=False, intrinsics=camera, offsets=np.tile(shift, (len(plan), 1)))
            plans.append(plan)
        rows = descriptor_rows(views, pd.concat(plans), [spec])
        answers[name] = classify(pd.concat([library, rows], ignore_index=True), spec.name)
    assert answers["off-axis"]["correct"].mean() >= answers["centred"]["correct"].mean() - 1 / 12
    same = np.mean(answers["off-axis"]["predicted_object"].to_numpy() == answers["centred"]["predicted_object"])
    assert same >= 11 / 12, answers
