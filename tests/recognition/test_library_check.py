"""Library files from elsewhere are checked as a whole when they load: every damaged field is one LibraryError line
naming the file and the field, never a traceback and never a silently different answer."""

import copy
import json
import os

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest
from conftest import ROOT
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import heatdata as hd
from heatdata.descriptors.hgd import VERTEX_BUDGET
from heatdata.errors import LibraryError
from heatdata.experiments.describe import describe_view_table, view_table_time_scales
from heatdata.experiments.views import render_object_views
from heatdata.recognition.library import _spec_metadata, build_library, write_library
from heatdata.recognition.library_check import spec_of

FT = hd.DescriptorSpec("ft-pvhk", 16, "center", "polar")
PVHK = hd.DescriptorSpec("pvhk", 16, "center", "polar")
OBJECTS = ("cupcake", "plastic-cup", "coffee-cup")


@pytest.fixture(scope="module")
def built() -> tuple[pd.DataFrame, dict]:
    """An FT-PVHK library of three embedded objects (3 library views each): rows and metadata."""
    catalog = hd.read_catalog(ROOT / "data/models/catalog.csv")
    views = {"train": 3, "test": 1, "elevation": 30.0, "distance": 1.0, "noise": True, "seed": 0}
    frames = [render_object_views(catalog[catalog["object"] == obj].iloc[0].to_dict(), views) for obj in OBJECTS]
    scales = pd.concat([view_table_time_scales(f, [PVHK, FT]) for f in frames])
    table = pd.concat([describe_view_table(f, [PVHK, FT], scales) for f in frames], ignore_index=True)
    return build_library(table, FT, 3, time_scales=scales, source="test")


def written(tmp_path, rows: pd.DataFrame, metadata: dict, name: str = "lib.parquet"):
    path = tmp_path / name
    write_library(rows, metadata, path)
    return path


def one_line_refusal(path, *needles: str) -> str:
    with pytest.raises(LibraryError) as caught:
        hd.load_library(path)
    message = str(caught.value)
    assert "\n" not in message and str(path) in message and len(message) < 400, message
    for needle in needles:
        assert needle in message, message
    return message


def test_an_untouched_library_loads(built, tmp_path):
    library = hd.load_library(written(tmp_path, *built))
    assert library.objects == sorted(OBJECTS) and library.time_scales is not None


def _set(key, value):
    def change(rows, meta):
        meta[key] = value
        return rows, meta

    return change


def _drop(key):
    def change(rows, meta):
        del meta[key]
        return rows, meta

    return change


def _values(cut):
    def change(rows, meta):
        return rows.assign(values=[v[:cut] for v in rows["values"]]), meta

    return change


def _scales(change_scales):
    def change(rows, meta):
        meta["time_scales"] = change_scales(meta["time_scales"])
        return rows, meta

    return change


def _spec(kind, options, fitted):
    def change(rows, meta):
        meta["spec"] = {"kind": kind, "options": options, "fitted": fitted, "name": meta["spec"]["name"]}
        return rows, meta

    return change


def _confidence(key, value):
    def change(rows, meta):
        meta["confidence"][key] = value
        return rows, meta

    return change


TWO_PARTS = {"parts": [{"kind": "pvhk", "samples": 16}, {"kind": "esf"}], "how": "learned"}
FIVE = [1.0] * 5
SIHKS = {"words": 4, "modes": 30, "frequencies": 6}
CODEBOOK = {"words": np.ones((4, 6)).tolist(), "scale": [1.0] * 6}

CASES = {
    # silent wrong answers before: the probe still matched
    "values cut from 16 to 10": (_values(10), "rows of [10] values; its probe has 16"),
    "empty values": (_values(0), "rows of [0] values"),
    "time scales of 1e300": (
        _scales(lambda s: [{**r, "time_scale": 1e300} for r in s]),
        "time_scale: 1e+300 is greater than the maximum",
    ),
    "time scales of a negative number": (_scales(lambda s: [{**r, "time_scale": -1.0} for r in s]), "time_scale"),
    "time scales of one object only": (_scales(lambda s: s[:1]), "time scales of 1 objects (1 entries) for 3"),
    "an object's time scale twice": (_scales(lambda s: s + s[:1]), "time scales of 3 objects (4 entries)"),
    "no time scales": (_scales(lambda s: []), "time scales of 0 objects"),
    "time scales null for a time-scaled kind": (_set("time_scales", None), "time_scales: missing for ft-pvhk"),
    "a combined spec of 5 weights for 2 parts": (
        _spec("combined", TWO_PARTS, {"scales": FIVE, "weights": FIVE, "coefficients": FIVE, "leave_one_out": 1.0}),
        "the fitted scales is (5,), not finite (2,)",
    ),
    "time_rule bogus": (_set("time_rule", "bogus"), "time_rule: 'bogus' is not one of"),
    # tracebacks before
    "no probe": (_drop("probe"), "'probe' is a required property"),
    "a probe of text": (_set("probe", "abc"), "probe: 'abc' is not of type 'array'"),
    "fitted text": (_spec("ft-pvhk", {"samples": 16}, "abc"), "spec.fitted: 'abc' is not of type"),
    "no heatdata_version": (_drop("heatdata_version"), "'heatdata_version' is a required property"),
    "an si-hks mean of the wrong shape": (
        _spec("si-hks", SIHKS, {**CODEBOOK, "mean": [0.0] * 5}),
        "the fitted mean is (5,), not finite (6,)",
    ),
    "an si-hks mean of NaN": (_spec("si-hks", SIHKS, {**CODEBOOK, "mean": [float("nan")] * 6}), "spec.fitted.mean"),
    "an unknown kind": (_spec("nope", {}, None), "spec: unknown descriptor kind"),
    "a library size of -7": (_set("library_size", -7), "library_size: -7 is less than the minimum of 1"),
    "a library size of 10**400": (_set("library_size", 10**400), "library_size"),
    "a library size below the views per object": (_set("library_size", 2), "an object has 3 library views"),
    "objects other than the rows'": (_set("objects", ["cupcake", "plastic-cup"]), "its metadata names 2"),
    "objects of text": (_set("objects", "cupcake"), "objects: 'cupcake' is not of type 'array'"),
    "an object of no name": (_set("objects", ["cupcake", ""]), "objects.1: not a name of 1 to 200 characters"),
    "an object twice": (_set("objects", ["cupcake", "cupcake"]), "objects: has non-unique elements"),
    "a NaN in the confidence": (_confidence("intercept", float("nan")), "confidence.intercept: not a finite number"),
    "a threshold of 2": (_confidence("threshold", 2.0), "confidence.threshold: 2.0 is greater than the maximum"),
    "sizes of another object": (_set("sizes", {"sofa": [1.0, 1.0, 1.0]}), "sizes of objects outside the library"),
    "a negative size": (_set("sizes", {"cupcake": [1.0, -1.0, 1.0]}), "sizes.cupcake.1"),
    "render not a mapping": (_set("render", [1, 2]), "render: [1, 2] is not of type 'object'"),
    "a surface of another object": (
        _set("surfaces", {"sofa": {"points": "", "normals": "", "center": [0, 0, 0], "diameter": 1, "spacing": 1}}),
        "surfaces of objects outside the library",
    ),
}


@pytest.mark.parametrize("case", CASES)
def test_a_damaged_field_is_one_line_naming_it(built, tmp_path, case):
    change, needle = CASES[case]
    rows, metadata = change(built[0].copy(), copy.deepcopy(built[1]))
    one_line_refusal(written(tmp_path, rows, metadata), "a damaged library file", needle)


def with_raw_metadata(path, raw: bytes) -> None:
    table = pq.read_table(path)
    pq.write_table(table.replace_schema_metadata({**table.schema.metadata, b"heatdata_run": raw}), path)


def test_metadata_nested_too_deep_or_of_another_layout_is_one_line(built, tmp_path):
    path = written(tmp_path, *built)
    with_raw_metadata(path, b'{"library": ' + b"[" * 100_000 + b"]" * 100_000 + b"}")
    one_line_refusal(path, "nested too deep")
    for layout, shown in (("1", "'1'"), (2, "2"), (True, "True")):
        meta = {**built[1], "format": layout}
        message = one_line_refusal(written(tmp_path, built[0], meta), f"a library of layout {shown}; this heatdata")
        assert "layout 1;" not in message


# -- fuzz -----------------------------------------------------------------------------------------------------------

JSON = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=6), inner, max_size=4),
    max_leaves=12,
)
FUZZ = settings(
    max_examples=int(os.environ.get("HEATDATA_FUZZ_EXAMPLES", "200")),
    deadline=None,
    database=None,
    derandomize=os.environ.get("HEATDATA_FUZZ_RANDOM") is None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)


def _paths(value, prefix=()):
    """Every key path into a JSON value."""
    yield prefix
    if isinstance(value, dict):
        for key, item in value.items():
            yield from _paths(item, (*prefix, key))
    elif isinstance(value, list):
        for index, item in enumerate(value[:3]):
            yield from _paths(item, (*prefix, index))


def _child(holder, key):
    """``holder[key]`` if there is one, else None."""
    if isinstance(holder, dict) and isinstance(key, str):
        return holder.get(key)
    if isinstance(holder, list) and isinstance(key, int) and key < len(holder):
        return holder[key]
    return None


@given(data=st.data())
@FUZZ
def test_fuzzed_metadata_loads_or_is_refused_as_a_library_error(built, tmp_path, data):
    """Replace or delete any field of the metadata (at any depth) with any JSON: the library loads and answers as
    before, or is refused with a LibraryError; never another exception."""
    rows, metadata = built[0], copy.deepcopy(built[1])
    metadata.pop("surfaces")  # its base64 samples are fuzzed by the surface's own reader
    paths = [p for p in _paths(metadata) if p]
    for _ in range(data.draw(st.integers(1, 3))):  # a later change may fall under an earlier one: then skipped
        *parents, last = data.draw(st.sampled_from(paths))
        holder = metadata
        for key in parents:
            holder = _child(holder, key)
        if isinstance(holder, dict) and data.draw(st.booleans()):
            holder.pop(last, None)
        elif _child(holder, last) is not None or isinstance(holder, dict):
            holder[last] = data.draw(JSON)
    path = tmp_path / "fuzzed.parquet"
    try:
        write_library(rows, json.loads(json.dumps(metadata, default=str)), path)
    except ValueError:  # json refuses a float it cannot write back (none: hypothesis's floats are JSON's)
        return
    try:
        library = hd.load_library(path)
    except LibraryError as exc:
        assert "\n" not in str(exc) and len(str(exc)) < 600
        return
    assert set(library.objects) == set(OBJECTS) and library.time_rule in ("plausible", "every")


def test_values_not_finite_or_a_negative_histogram_are_refused(built, tmp_path):
    rows, metadata = built
    for bad in (np.nan, np.inf):
        changed = rows.copy()
        values = np.array(changed.at[1, "values"], dtype=np.float64)
        values[3] = bad
        changed.at[1, "values"] = values
        one_line_refusal(written(tmp_path, changed, metadata), "values: 1 of", "NaN or infinite")
    catalog = hd.read_catalog(ROOT / "data/models/catalog.csv")
    views = {"train": 2, "test": 1, "elevation": 30.0, "distance": 1.0, "noise": True, "seed": 0}
    hgd = hd.DescriptorSpec("hgd")
    frames = [render_object_views(catalog[catalog["object"] == obj].iloc[0].to_dict(), views) for obj in OBJECTS[:2]]
    table = pd.concat([describe_view_table(f, [hgd]) for f in frames], ignore_index=True)
    rows, metadata = build_library(table, hgd, 2, source="test")
    assert hd.load_library(written(tmp_path, rows, metadata, "hgd.parquet")).objects == sorted(OBJECTS[:2])
    values = np.array(rows.at[0, "values"], dtype=np.float64)
    values[0] = -0.5
    rows.at[0, "values"] = values
    one_line_refusal(written(tmp_path, rows, metadata, "hgd.parquet"), "negative values; a hgd is a histogram")


def test_a_spec_saved_before_an_option_existed_reads_as_its_kind_described_then():
    spec = hd.DescriptorSpec("hgd", color="hue-saturation")
    saved = _spec_metadata(spec)
    assert spec_of(saved) == spec and spec.get("vertices") == VERTEX_BUDGET
    older = {**saved, "options": {k: v for k, v in saved["options"].items() if k != "vertices"}}
    assert spec_of(older) == spec.replace(vertices=0)  # every vertex, as the HGD described before its budget
    every = _spec_metadata(spec.replace(vertices=0))
    assert spec_of(every) == spec.replace(vertices=0) and every["name"] == "hgd/color=hue-saturation/vertices=0"
