"""Libraries, precision tables and the workflow's step functions."""

import logging

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

import heatdata as hd
from heatdata.core.distances import mhd, weighted_mhd
from heatdata.experiments.describe import candidate_view_table, describe_view_table
from heatdata.experiments.views import render_object_views, view_plan
from heatdata.recognition.evaluate import evaluate_library_sizes, library_subset
from heatdata.recognition.metrics import precision_table


def fake_descriptors(objects=("a", "b"), n_train=8, n_test=4):
    """Descriptor rows whose values encode the object, so recognition is perfect."""
    rows = []
    for k, obj in enumerate(objects):
        for split, count in (("train", n_train), ("test", n_test)):
            for i in range(count):
                rows.append(
                    {
                        "object": obj,
                        "label": "box" if obj == "a" else "cup",
                        "split": split,
                        "view_id": f"{obj}/{split}/{i:03d}",
                        "azimuth": 360.0 * i / count,
                        "descriptor": "d",
                        "kind": "pvhk",
                        "values": [float(k)] * 8,
                    }
                )
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


def test_candidate_rows_of_rendered_views(catalog, caplog):
    row = catalog[catalog["object"] == "cupcake"].iloc[0].to_dict()
    frame = render_object_views(
        row, {"train": 2, "test": 1, "elevation": 30.0, "distance": 1.0, "noise": True, "seed": 0}
    )
    spec = hd.DescriptorSpec("pvhk", 16, "center", "polar")
    table = candidate_view_table(frame, spec, library_count=12, test_count=5)
    counts = table.groupby(["split", "descriptor"]).size()
    assert counts["train", "pvhk/polar/candidates/16"] == 24 and counts["test", "pvhk/polar/candidates/16"] == 5
    assert counts["train", "pvhk/polar/center/16"] == 2 and counts["test", "pvhk/polar/center/16"] == 1
    assert table.groupby("view_id")["source"].nunique().min() >= 6  # distinct sources
    single = describe_view_table(frame, [spec])
    own = table[table["source_rule"] == "center"].set_index("view_id")["values"]
    for view_id, values in single.set_index("view_id")["values"].items():  # one spectrum = one solve each
        np.testing.assert_allclose(own[view_id], values, atol=1e-5)
    with caplog.at_level(logging.WARNING, logger="heatdata.experiments.describe"):
        failed = candidate_view_table(frame, spec, library_count=10**6, test_count=5)
    assert "candidate descriptors failed" in caplog.text
    bad = failed[failed["split"] == "train"]
    assert len(bad) == 2 and bad["values"].map(lambda v: np.isnan(v).all()).all()
    assert bad["repairs"].map(lambda r: "vertices off its outer boundary" in r[-1]).all()


def fixed_time_rows():
    """FT-PVHK rows of objects a and b: test view a/test/000 at both objects' times.

    At b's time nothing of b's library is near it; but its row at a's time equals b's
    library exactly - a classifier that ignored ``time_object`` would answer b.
    """
    base = np.linspace(0.0, 1.0, 8)
    rows = [
        ("a", "train", "a/train/000", "a", base),
        ("b", "train", "b/train/000", "b", base + 0.5),
        ("a", "test", "a/test/000", "a", base + 0.45),  # 0.05 from b's library, 0.45 from a's
        ("a", "test", "a/test/000", "b", base + 3.0),  # 2.5 from b's library
    ]
    scale = {"a": 0.1, "b": 0.2}  # the objects' time scales (Alg. 5.1); the test view's 1/lambda_2 reaches both
    return pd.DataFrame(
        [
            {
                "object": obj,
                "label": obj,
                "split": split,
                "view_id": view,
                "azimuth": 0.0,
                "descriptor": "ft",
                "kind": "ft-pvhk",
                "time_object": time_object,
                "time": scale[time_object],
                "t_global": scale[obj] if split == "train" else 0.5,
                "values": values,
                "weights": np.ones(8),
            }
            for obj, split, view, time_object, values in rows
        ]
    )


def test_fixed_time_classification_compares_each_object_at_its_own_time():
    from heatdata.recognition.evaluate import classify

    rows = fixed_time_rows()
    predicted = classify(rows, "ft")
    assert len(predicted) == 1 and predicted["predicted_object"].item() == "a"
    assert predicted["distance"].item() == pytest.approx(mhd(rows["values"][2], rows["values"][0]))
    ignoring_time = classify(rows.assign(kind="pvhk", time_object=""), "ft")
    assert ignoring_time["predicted_object"].iloc[0] == "b"
    # part weights enter as eq. 5.14: down-weighting where the test view differs most changes the distance
    weights = np.where(np.arange(8) < 4, 1.0, 0.1)
    weighted = rows.assign(weights=[weights] * 4)
    expected = weighted_mhd(rows["values"][2], rows["values"][0], weights, weights)
    assert classify(weighted, "ft")["distance"].item() == pytest.approx(expected)
    with pytest.raises(hd.HeatdataError, match="no row at the time scale of object 'b'"):
        classify(rows.drop(index=3), "ft")


@pytest.mark.parametrize("t_global, plausible", [(0.5, "b"), (0.15, "a"), (0.05, "b")])
def test_the_plausible_rule_skips_objects_whose_time_scale_the_view_does_not_reach(t_global, plausible):
    """b's time scale (0.2) is reached by a view with 1/lambda_2 = 0.5, not by one with 0.15; 0.05 reaches none,
    and then every object is compared, as by the rule ``every``."""
    from heatdata.recognition.evaluate import classify

    rows = fixed_time_rows()
    rows.at[3, "values"] = rows.at[1, "values"] + 0.01  # at b's time the view is nearest b's library
    rows.loc[rows["split"] == "test", "t_global"] = t_global
    assert classify(rows, "ft", time_rule="every")["predicted_object"].item() == "b"
    assert classify(rows, "ft")["predicted_object"].item() == plausible
    with pytest.raises(hd.HeatdataError, match="unknown time_rule 'label'"):
        classify(rows, "ft", time_rule="label")
    with pytest.raises(hd.HeatdataError, match="lacks column.*t_global"):
        classify(rows.drop(columns="t_global"), "ft")


def random_table(seed=0, objects=("a", "b", "c"), n_train=6, n_test=4):
    """A PVHK and an FT-PVHK (each test view at every object's time) of random curves near each object's own."""
    rng = np.random.default_rng(seed)
    centre = {obj: rng.normal(size=8) for obj in objects}
    scale = {obj: 1.0 + k for k, obj in enumerate(objects)}  # time scales; a view's 1/lambda_2 reaches its own
    rows = []
    for obj in objects:
        for split, count in (("train", n_train), ("test", n_test)):
            for i in range(count):
                view = {
                    "object": obj,
                    "label": obj,
                    "split": split,
                    "view_id": f"{obj}/{split}/{i:03d}",
                    "azimuth": 360.0 * i / count,
                    "t_global": scale[obj] + rng.uniform(0.0, 1.5),
                }
                rows.append(
                    {
                        **view,
                        "descriptor": "d",
                        "kind": "pvhk",
                        "time_object": "",
                        "time": view["t_global"],
                        "values": centre[obj] + rng.normal(scale=0.8, size=8),
                        "weights": None,
                    }
                )
                for time_object in objects if split == "test" else [obj]:
                    rows.append(
                        {
                            **view,
                            "descriptor": "ft",
                            "kind": "ft-pvhk",
                            "time_object": time_object,
                            "time": scale[time_object],
                            "values": centre[obj] + rng.normal(scale=0.8, size=8),
                            "weights": rng.uniform(0.5, 1.0, size=8),
                        }
                    )
    return pd.DataFrame(rows)


@pytest.mark.parametrize("descriptor", ["d", "ft"])
def test_a_table_on_disk_is_classified_group_by_group_as_in_memory(tmp_path, descriptor, caplog):
    """Row groups of 5 rows cut the FT-PVHK's test views between groups: they wait for their other time scales."""
    from heatdata.recognition.evaluate import evaluate_table

    rows = random_table()
    failed = rows.index[(rows["descriptor"] == descriptor) & (rows["split"] == "train")][0]  # left out on both paths
    rows.at[failed, "values"] = np.full(len(rows.at[failed, "values"]), np.nan)
    path = tmp_path / "descriptors.parquet"
    pq.write_table(pa.Table.from_pandas(rows, preserve_index=False), path, row_group_size=5)
    expected = evaluate_library_sizes(rows, descriptor, [6, 2])
    with caplog.at_level(logging.WARNING):
        found = evaluate_table(path, descriptor, [6, 2])
    assert "1 library views have NaN values" in caplog.text
    key = ["library_size", "view_id"]
    pd.testing.assert_frame_equal(
        found.sort_values(key, ignore_index=True), expected.sort_values(key, ignore_index=True)
    )
    assert 0.3 < expected["correct"].mean() < 1.0  # neither trivial nor hopeless


@pytest.mark.parametrize("descriptor", ["d", "ft"])
def test_the_thesis_protocol_takes_the_library_among_the_test_views(tmp_path, descriptor):
    """5.5: library views are test views (at their own object's time scale), so each one finds itself."""
    from heatdata.recognition.evaluate import evaluate_table

    rows = random_table()
    path = tmp_path / "descriptors.parquet"
    pq.write_table(pa.Table.from_pandas(rows, preserve_index=False), path, row_group_size=5)
    every = evaluate_table(path, descriptor, [4], library_split="test")
    assert len(every) == 12 and every["correct"].all() and (every["distance"] == 0).all()
    assert (every["predicted_view_id"] == every["view_id"]).all()
    two = evaluate_table(path, descriptor, [2], library_split="test")
    itself = two[two["azimuth"].isin([0.0, 180.0])]  # the library's azimuths of 4 test views
    assert len(itself) == 6 and (itself["predicted_view_id"] == itself["view_id"]).all()
    assert (itself["distance"] == 0).all() and (two["distance"] > 0).sum() == 6


def test_a_table_on_disk_with_a_missing_time_scale_or_descriptor_is_refused(tmp_path):
    from heatdata.recognition.evaluate import evaluate_table

    rows = random_table()
    path = tmp_path / "descriptors.parquet"
    lost = (rows["view_id"] == "b/test/001") & (rows["time_object"] == "c")
    pq.write_table(pa.Table.from_pandas(rows[~lost], preserve_index=False), path, row_group_size=7)
    with pytest.raises(hd.HeatdataError, match="test view b/test/001 has no row at the time scale of object 'c'"):
        evaluate_table(path, "ft", [2])
    with pytest.raises(hd.HeatdataError, match="no library .* rows of descriptor 'nope'"):
        evaluate_table(path, "nope", [2])


def test_views_with_nan_descriptors_are_left_out_or_counted_wrong(caplog):
    from heatdata.recognition.evaluate import classify

    rows = fake_descriptors(n_train=4, n_test=3).assign(kind="pvst")
    rows.at[0, "values"] = [np.nan] * 8  # a library view of a
    rows.at[4, "values"] = [1.0] * 7 + [np.nan]  # a test view of a
    with caplog.at_level(logging.WARNING):
        predicted = classify(rows, "d")
    assert "1 library and 1 test views have NaN values" in caplog.text
    assert len(predicted) == 6 and predicted["correct"].sum() == 5
    failed = predicted[predicted["view_id"] == "a/test/000"].iloc[0]
    assert failed["predicted_object"] == "" and not failed["correct"] and np.isnan(failed["distance"])
    assert "a/train/000" not in set(predicted["predicted_view_id"])


def test_time_scales_and_fixed_time_rows_of_rendered_views(catalog):
    from heatdata.experiments.describe import view_table_time_scales

    frames = []
    for obj in ("cupcake", "plastic-cup"):
        row = catalog[catalog["object"] == obj].iloc[0].to_dict()
        frames.append(
            render_object_views(
                row, {"train": 3, "test": 1, "elevation": 30.0, "distance": 1.0, "noise": True, "seed": 0}
            )
        )
    specs = [hd.DescriptorSpec("pvhk", 16, "center", "polar"), hd.DescriptorSpec("ft-pvhk", 16, "center", "polar")]
    scales = pd.concat([view_table_time_scales(f, specs) for f in frames])
    assert scales["n_views"].tolist() == [3, 3] and scales["source_rule"].tolist() == ["center", "center"]
    table = describe_view_table(frames[0], specs, scales)
    pvhk, ft = table[table["kind"] == "pvhk"], table[table["kind"] == "ft-pvhk"]
    assert scales.iloc[0]["time_scale"] == pytest.approx(pvhk[pvhk["split"] == "train"]["t_global"].min())
    assert ft[ft["split"] == "train"]["time_object"].eq("cupcake").all()
    test = ft[ft["split"] == "test"]
    assert test["time_object"].tolist() == ["cupcake", "plastic-cup"]
    assert np.allclose(test["time"], scales["time_scale"])
    with pytest.raises(hd.HeatdataError, match="time scales"):
        describe_view_table(frames[0], specs)


def test_a_descriptor_failing_on_one_view_gives_nan_and_its_reason(square):
    from heatdata.descriptors.rows import descriptor_rows

    corner = int(square.boundary[0])
    specs = [hd.DescriptorSpec("pvhk", 8, corner), hd.DescriptorSpec("pvst", 8, corner)]
    table = descriptor_rows([square], pd.DataFrame({"split": ["test"], "seed": [0]}), specs)
    pvhk, pvst = table.iloc[0], table.iloc[1]
    assert np.all(np.isfinite(pvhk["values"])) and np.all(np.isnan(pvst["values"]))
    assert any("interior source" in r for r in pvst["repairs"])
