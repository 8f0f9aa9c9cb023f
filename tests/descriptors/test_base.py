"""The registry of descriptor kinds and DescriptorSpec: every kind through one interface, clear errors."""

import dataclasses
import pickle
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import square_view

import heatdata as hd
from heatdata.core.distances import mhd
from heatdata.descriptors import KINDS, kind_of
from heatdata.descriptors.sources import candidate_descriptors

ROOT = Path(__file__).resolve().parents[2]


def test_every_kind_is_registered_and_reported():
    assert (
        set(hd.DESCRIPTORS)
        == set(KINDS)
        == {"pvhk", "c-pvhk", "ft-pvhk", "pvst", "si-hks", "fpfh", "vfh", "esf", "hgd", "combined", "pointnet"}
    )
    for name, kind in KINDS.items():
        assert kind.name == name and kind.summary and kind.distance_name


def test_availability_is_what_this_machine_has(monkeypatch):
    """Only the VFH needs a tool (PCL's): it is reported missing, with the fix, exactly when the tool is."""
    import shutil

    from heatdata.descriptors import available, vfh

    assert [name for name, reason in hd.DESCRIPTORS.items() if reason is not None] == (
        [] if all(shutil.which(t) for t in vfh.TOOLS) else ["vfh"]
    )
    monkeypatch.setattr(shutil, "which", lambda tool: None)  # a machine without pcl-tools
    reasons = available()
    assert reasons["vfh"].startswith("pcl_normal_estimation, pcl_vfh_estimation not found: install Debian's pcl-tools")
    assert all(reason is None for name, reason in reasons.items() if name != "vfh")
    spec = hd.DescriptorSpec("vfh")
    with pytest.raises(hd.ViewError, match="no vfh here: .*pcl-tools"):
        hd.describe(square_view(21), [spec])


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_each_kind_describes_a_view_through_describe(kind, mug):
    if hd.DESCRIPTORS[kind] is not None:
        pytest.skip(hd.DESCRIPTORS[kind])
    view = hd.render_view(mug, 30.0, 30.0, 1.0, seed=0)
    options = {
        "c-pvhk": {"color_map": "c3"},
        "si-hks": {"words": 8, "modes": 30},
        "pvst": {"source": "interior"},
        "combined": {"parts": [{"kind": "hgd"}, {"kind": "esf"}]},
        "pointnet": {"points": 64, "steps": 2},
    }.get(kind, {})
    other = dataclasses.replace(hd.render_view(mug, 120.0, 30.0, 1.0, seed=1), object_id="other")  # a second object
    spec = hd.fit_spec(hd.DescriptorSpec(kind, **options), [view, other])
    (d,) = hd.describe(view, [spec], times=[0.01])
    assert d.kind == kind and d.values.shape == (spec.impl.size(spec, view),) and np.all(np.isfinite(d.values))
    assert hd.distance(d, d) == pytest.approx(0.0, abs=1e-6)


def test_spec_errors_name_the_kind_and_option():
    with pytest.raises(hd.SpecError, match="unknown descriptor kind 'shot'.*esf"):
        hd.DescriptorSpec("shot")
    with pytest.raises(hd.SpecError, match="an esf takes no samples"):
        hd.DescriptorSpec("esf", samples=64)
    with pytest.raises(hd.SpecError, match="pvhk: option samples must be a whole number"):
        hd.DescriptorSpec("pvhk", samples=2.5)
    with pytest.raises(hd.SpecError, match="at most 3 options"):
        hd.DescriptorSpec("pvhk", 64, "center", "polar", "c3")
    with pytest.raises(hd.SpecError, match="given twice"):
        hd.DescriptorSpec("pvhk", 64, samples=32)
    with pytest.raises(hd.SpecError, match="option source"):
        hd.DescriptorSpec("pvhk", source="middle")
    with pytest.raises(AttributeError, match="immutable"):
        hd.DescriptorSpec().samples = 3


def test_specs_compare_hash_pickle_and_replace():
    spec = hd.DescriptorSpec("pvst", 64, "center", "polar")
    assert spec == hd.DescriptorSpec("pvst", samples=64, source="center", sampling="polar", threshold=0.75)
    assert len({spec, pickle.loads(pickle.dumps(spec))}) == 1
    assert spec.replace(threshold=0.5).name == "pvst/polar/center/64/T0.5"
    assert hd.DescriptorSpec("esf", seed=3).name == "esf/seed=3" and hd.DescriptorSpec("esf").name == "esf"
    assert hd.fit_spec(spec, []) is spec  # nothing to learn


def test_distance_is_the_kinds_own_and_refuses_mixed_kinds():
    view = square_view(21)
    pvhk, esf = hd.describe(view, [hd.DescriptorSpec("pvhk", 16), hd.DescriptorSpec("esf")])
    other = hd.pvhk(view, 16, "center")
    assert hd.distance(pvhk, other) == pytest.approx(mhd(pvhk.values, other.values), rel=1e-6)
    assert hd.distance(esf, esf) == 0.0
    with pytest.raises(hd.HeatdataError, match="no distance between a pvhk and an esf"):
        hd.distance(pvhk, esf)


def test_histogram_kinds_have_no_heat_source():
    with pytest.raises(hd.SpecError, match="no heat source"):
        candidate_descriptors(square_view(21), [200], hd.DescriptorSpec("esf"))
    assert {k for k, v in KINDS.items() if v.multi_source} == {"pvhk", "c-pvhk", "ft-pvhk", "pvst"}
    assert {k for k, v in KINDS.items() if v.fitted} == {"si-hks", "combined", "pointnet"} and kind_of(
        "ft-pvhk"
    ).time_scaled


def test_config_schema_leaves_kinds_to_the_registry():
    """No kind list in the schema to fall out of step: the workflow checks kinds against the registry."""
    schema = yaml.safe_load((ROOT / "workflow" / "schemas" / "config.schema.yaml").read_text())
    for kind in (
        schema["properties"]["descriptors"]["items"]["properties"]["kind"],
        schema["properties"]["compact"]["properties"]["descriptor"]["properties"]["kind"],
    ):
        assert kind == {"type": "string", "description": kind["description"]}


NEEDED = {"c-pvhk": {"color_map": "c3"}, "combined": {"parts": [{"kind": "hgd"}, {"kind": "pvhk", "samples": 32}]}}


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_a_spec_crosses_a_file_as_plain_data_and_comes_back_equal(kind):
    import json

    spec = hd.DescriptorSpec(kind, **NEEDED.get(kind, {}))
    data = json.loads(json.dumps(spec.to_dict()))  # plain data: what a config, a table's metadata or a process holds
    again = hd.DescriptorSpec.from_dict(data)
    assert again == spec and again.name == spec.name and again.to_dict() == data and again.fitted is None
    assert data["kind"] == kind and "fitted" not in data


def test_a_fitted_spec_crosses_with_its_fit():
    spec = hd.DescriptorSpec("si-hks", words=2, frequencies=1)
    fitted = spec.with_fitted({"words": [[0.0], [1.0]], "mean": [0.5], "scale": [2.0]})
    data = fitted.to_dict()
    assert data["fitted"] == {"words": [[0.0], [1.0]], "mean": [0.5], "scale": [2.0]}
    again = hd.DescriptorSpec.from_dict(data)
    assert again == fitted and np.array_equal(again.fitted["words"], [[0.0], [1.0]])
    assert hd.DescriptorSpec.from_dict({"kind": "esf", "triplets": 2000}).name == "esf/triplets=2000"  # a config entry
    with pytest.raises(hd.SpecError, match="a mapping of kind and options"):
        hd.DescriptorSpec.from_dict(["esf"])


def test_descriptor_spec_validation():
    with pytest.raises(hd.SpecError, match="kind"):
        hd.DescriptorSpec("shot")
    with pytest.raises(hd.SpecError, match="color_map"):
        hd.DescriptorSpec("c-pvhk")
    with pytest.raises(hd.SpecError, match="sampling"):
        hd.DescriptorSpec(sampling="random")
