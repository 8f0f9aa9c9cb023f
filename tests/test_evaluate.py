"""Libraries, precision tables and the workflow's step functions."""

import numpy as np
import pandas as pd
import pytest

import heatdata as hd
from heatdata.dataset import describe_view_table, render_object_views, view_plan
from heatdata.evaluate import evaluate_library_sizes, library_subset, precision_table


def fake_descriptors(objects=("a", "b"), n_train=8, n_test=4):
    """Descriptor rows whose values encode the object, so recognition is perfect."""
    rows = []
    for k, obj in enumerate(objects):
        for split, count in (("train", n_train), ("test", n_test)):
            for i in range(count):
                rows.append({"object": obj, "label": "box" if obj == "a" else "cup", "split": split,
                             "view_id": f"{obj}/{split}/{i:03d}", "azimuth": 360.0 * i / count,
                             "descriptor": "d", "values": [float(k)] * 8})
    return pd.DataFrame(rows)


def test_library_subset_is_evenly_spaced():
    subset = library_subset(fake_descriptors(n_train=8), 4)
    assert sorted(subset[subset["object"] == "a"]["azimuth"]) == [0.0, 90.0, 180.0, 270.0]
    assert len(library_subset(fake_descriptors(n_train=8), 3)) == 6
    with pytest.raises(hd.HeatdataError, match="larger than the 8 train views"):
        library_subset(fake_descriptors(n_train=8), 9)


def test_precision_per_object_and_class():
    predictions = evaluate_library_sizes(fake_descriptors(), "d", [8, 2])
    assert set(predictions["library_size"]) == {8, 2}
    table = precision_table(predictions)
    assert (table["precision"] == 1.0).all()
    assert set(table["level"]) == {"object", "class"} and "all" in set(table["group"])
    wrong = predictions.assign(predicted_object="a", predicted_label="box")
    table = precision_table(wrong).set_index(["level", "group", "library_size"])["precision"]
    assert table["object", "a", 8] == 1.0 and table["object", "b", 8] == 0.0 and table["object", "all", 8] == 0.5


def test_render_and_describe_steps(catalog):
    row = catalog[catalog["object"] == "cupcake"].iloc[0].to_dict()
    views = {"train": 3, "test": 2, "elevation": 30.0, "distance": 1.0, "noise": True, "seed": 0}
    frame = render_object_views(row, views)
    assert frame["split"].tolist() == ["train"] * 3 + ["test"] * 2
    assert frame["view_id"].tolist()[0] == "cupcake/train/000"
    table = describe_view_table(frame, [hd.DescriptorSpec("pvhk", 16, "center", "polar")])
    assert len(table) == 5 and table["values"].map(len).eq(16).all()
    plan = view_plan(["cupcake"], 3, 2)
    assert np.array_equal(frame["seed"], plan["seed"])
