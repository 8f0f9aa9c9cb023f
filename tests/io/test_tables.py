"""Parquet tables: schema, metadata, errors."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

import heatdata as hd
from heatdata.io.tables import PREDICTION_SCHEMA, iter_matrix_table, read_matrix_table, read_table, write_table


def prediction_rows():
    return pd.DataFrame(
        {
            "descriptor": ["pvhk"],
            "object": ["a"],
            "label": ["cup"],
            "view_id": ["a/test/000"],
            "azimuth": [1.5],
            "predicted_object": ["a"],
            "predicted_label": ["cup"],
            "predicted_view_id": ["a/train/000"],
            "predicted_azimuth": [0.0],
            "distance": [0.25],
            "correct": [True],
            "library_size": [40],
        }
    )


def test_round_trip_with_metadata(tmp_path):
    path = tmp_path / "p.parquet"
    write_table(prediction_rows(), path, PREDICTION_SCHEMA, {"seed": 3})
    frame, meta = read_table(path)
    assert frame.equals(prediction_rows())
    assert meta["seed"] == 3 and meta["heatdata_version"] == hd.__version__


def test_missing_column_and_bad_files(tmp_path):
    with pytest.raises(hd.HeatdataError, match="lacks column"):
        write_table(prediction_rows().drop(columns="correct"), tmp_path / "p.parquet", PREDICTION_SCHEMA)
    with pytest.raises(hd.HeatdataError, match="no such table"):
        read_table(tmp_path / "none.parquet")
    (tmp_path / "bad.parquet").write_text("nope")
    with pytest.raises(hd.HeatdataError, match="not a readable Parquet"):
        read_table(tmp_path / "bad.parquet")


def test_views_round_trip(tmp_path, mug):
    from heatdata.experiments.views import view_plan
    from heatdata.io.tables import VIEW_SCHEMA
    from heatdata.views.frames import frame_to_views, views_to_frame

    plan = view_plan(["beer-mug"], 2, 1, distance=1.4)
    views = [hd.render_view(mug, r.azimuth, r.elevation, r.distance, seed=r.seed) for r in plan.itertuples()]
    write_table(views_to_frame(views, plan), tmp_path / "v.parquet", VIEW_SCHEMA)
    frame, _ = read_table(tmp_path / "v.parquet")
    back = frame_to_views(frame)
    assert frame["split"].tolist() == ["train", "train", "test"]
    for a, b in zip(views, back, strict=True):
        assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
        assert np.array_equal(hd.pvhk(a).values, hd.pvhk(b).values)


def test_concatenate_and_read_part_of_a_table(tmp_path):
    from heatdata.io.tables import concat_tables

    parts = []
    for k, name in enumerate(("a", "b")):
        rows = prediction_rows().assign(object=name, descriptor=["pvhk", "pvst"][k])
        write_table(rows, tmp_path / f"{name}.parquet", PREDICTION_SCHEMA, {"part": name})
        parts.append(tmp_path / f"{name}.parquet")
    concat_tables(parts, tmp_path / "all.parquet")
    frame, meta = read_table(tmp_path / "all.parquet")
    assert frame["object"].tolist() == ["a", "b"] and meta["part"] == "a"
    only, _ = read_table(tmp_path / "all.parquet", columns=["object"], filters=[("descriptor", "==", "pvst")])
    assert only.to_dict("list") == {"object": ["b"]}
    # row group by row group (two here), as pyarrow's own filtered read; metadata kept, "in" and OR-ed groups too
    both, meta = read_table(tmp_path / "all.parquet", filters=[("object", "in", ["a", "b"])])
    assert both["object"].tolist() == ["a", "b"] and meta["part"] == "a"
    either, _ = read_table(
        tmp_path / "all.parquet", columns=["descriptor"], filters=[[("object", "==", "b")], [("distance", "<", 0.0)]]
    )
    assert either.to_dict("list") == {"descriptor": ["pvst"]}
    none, _ = read_table(tmp_path / "all.parquet", columns=["object"], filters=[("object", "==", "z")])
    assert none.empty and list(none.columns) == ["object"]
    write_table(pd.DataFrame({"x": [1.0]}), tmp_path / "other.parquet", pa.schema([("x", pa.float64())]))
    with pytest.raises(hd.HeatdataError, match="schema differs"):
        concat_tables([parts[0], tmp_path / "other.parquet"], tmp_path / "bad.parquet")


MATRIX_SCHEMA = pa.schema([("name", pa.string()), ("values", pa.list_(pa.float64())), ("extra", pa.list_(pa.string()))])
VALUES = np.arange(60, dtype=np.float64).reshape(20, 3)


def write_matrix(path, row_group_size: int, metadata: dict | None = None) -> pd.DataFrame:
    """:data:`VALUES` as a table of rows v0 .. v19 with an extra list column, in row groups of ``row_group_size``."""
    frame = pd.DataFrame({"name": [f"v{k}" for k in range(20)], "values": list(VALUES), "extra": [["x"]] * 20})
    write_table(frame, path, MATRIX_SCHEMA, metadata, row_group_size=row_group_size)
    return frame


@pytest.mark.parametrize("groups", [1, 3, 100])
def test_a_matrix_column_reads_as_one_array_in_row_groups(tmp_path, groups):
    frame = write_matrix(tmp_path / "m.parquet", max(1, 20 // groups), {"seed": 1})
    back, matrix, meta = read_matrix_table(tmp_path / "m.parquet", "values", schema=MATRIX_SCHEMA, skip=("extra",))
    assert np.array_equal(matrix, VALUES) and meta["seed"] == 1 and list(back.columns) == ["name", "values"]
    assert all(np.shares_memory(row, matrix) for row in back["values"])  # the frame's rows are views of the array
    assert list(back["name"]) == list(frame["name"])


def test_a_matrix_column_of_many_row_groups_reads_again_and_again(tmp_path):
    # the row groups are decoded side by side; through one shared reader this hung within 300 reads in three tries
    # of three, so 400 reads run in a child process (beside this file, to import its table) that must finish in time
    write_matrix(tmp_path / "m.parquet", 1)
    script = """
import sys
import numpy as np
from test_tables import MATRIX_SCHEMA, VALUES
from heatdata.io.tables import read_matrix_table
for _ in range(400):
    _, matrix, _ = read_matrix_table(sys.argv[1], "values", schema=MATRIX_SCHEMA, skip=("extra",))
    assert np.array_equal(matrix, VALUES)
"""
    child = [sys.executable, "-c", script, tmp_path / "m.parquet"]
    subprocess.run(child, check=True, timeout=90, cwd=Path(__file__).parent)


@pytest.mark.parametrize("groups", [1, 20])
def test_chosen_rows_come_first_each_decoded_into_its_place(tmp_path, groups):
    frame = write_matrix(tmp_path / "m.parquet", max(1, 20 // groups))
    odd = [f"v{k}" for k in range(1, 20, 2)]
    frame["name"] = frame["name"].where(~frame["name"].isin(odd), "odd")
    write_table(frame, tmp_path / "m.parquet", MATRIX_SCHEMA, row_group_size=max(1, 20 // groups))
    back, matrix, _ = read_matrix_table(tmp_path / "m.parquet", "values", schema=MATRIX_SCHEMA, first=("name", "odd"))
    order = np.r_[1:20:2, 0:20:2]
    assert np.array_equal(matrix, VALUES[order]) and list(back["name"][:10]) == ["odd"] * 10
    assert list(back["name"][10:]) == [f"v{k}" for k in range(0, 20, 2)]
    assert all(
        np.shares_memory(row, matrix) and np.array_equal(row, VALUES[k]) for row, k in zip(back["values"], order)
    )
    ragged = pd.DataFrame({"name": ["a", "odd"], "values": [np.ones(3), np.zeros(2)], "extra": [[], []]})
    write_table(ragged, tmp_path / "r.parquet", MATRIX_SCHEMA)
    back, matrix, _ = read_matrix_table(tmp_path / "r.parquet", "values", schema=MATRIX_SCHEMA, first=("name", "odd"))
    assert matrix is None and list(back["name"]) == ["odd", "a"] and [len(v) for v in back["values"]] == [2, 3]


def test_a_file_of_a_thousand_row_groups_reads_each_once(tmp_path, monkeypatch):
    """A file another tool wrote with a row group per few rows: the footer is parsed once, not once per group (the
    time is benchmarks/bench_tables.py's)."""
    rows = 3000
    values = np.random.default_rng(0).random((rows, 4))
    table = pa.table({"name": [f"v{k}" for k in range(rows)], "values": list(values), "extra": [["x"]] * rows})
    pq.write_table(table.cast(MATRIX_SCHEMA), tmp_path / "m.parquet", row_group_size=3)
    opened = []
    original = pq.ParquetFile.__init__

    def counting(self, source, *args, **kwargs):
        opened.append(kwargs.get("metadata") is not None)
        original(self, source, *args, **kwargs)

    monkeypatch.setattr(pq.ParquetFile, "__init__", counting)
    _, matrix, _ = read_matrix_table(tmp_path / "m.parquet", "values", schema=MATRIX_SCHEMA)
    assert np.array_equal(matrix, values) and pq.ParquetFile(tmp_path / "m.parquet").num_row_groups == 1000
    assert len(opened) - 1 <= 4 and opened.count(False) <= 2  # one parse of the footer, and a reader per span


def test_a_ragged_matrix_column_reads_row_by_row(tmp_path):
    frame = pd.DataFrame({"name": ["a", "b"], "values": [np.ones(3), np.ones(2)], "extra": [[], []]})
    write_table(frame, tmp_path / "r.parquet", MATRIX_SCHEMA)
    back, matrix, _ = read_matrix_table(tmp_path / "r.parquet", "values", schema=MATRIX_SCHEMA)
    assert matrix is None and [len(v) for v in back["values"]] == [3, 2]
    with pytest.raises(hd.HeatdataError, match="lacks column"):
        read_matrix_table(tmp_path / "r.parquet", "values", schema=PREDICTION_SCHEMA)


def test_a_matrix_column_iterates_as_one_array_a_row_group_at_a_time(tmp_path):
    write_matrix(tmp_path / "m.parquet", 7)
    odd = [("name", "in", [f"v{k}" for k in range(1, 20, 2)])]
    parts = list(iter_matrix_table(tmp_path / "m.parquet", "values", columns=["name", "values"], filters=odd))
    assert [len(rows) for rows, _ in parts] == [3, 4, 3]  # groups of 7, 7 and 6 rows, every other one kept
    assert all(list(rows.columns) == ["name"] for rows, _ in parts)
    assert np.array_equal(np.concatenate([matrix for _, matrix in parts]), VALUES[1::2])
    assert [name for rows, _ in parts for name in rows["name"]] == [f"v{k}" for k in range(1, 20, 2)]
    ragged = pd.DataFrame({"name": ["a", "b"], "values": [np.ones(3), np.ones(2)], "extra": [[], []]})
    write_table(ragged, tmp_path / "r.parquet", MATRIX_SCHEMA)
    with pytest.raises(hd.HeatdataError, match="different lengths"):
        list(iter_matrix_table(tmp_path / "r.parquet", "values"))
