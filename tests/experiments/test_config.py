"""The workflow's config checks (heatdata.experiments.config), called as common.smk calls them."""

import subprocess
import sys
import warnings
from pathlib import Path

import pytest
import yaml
from snakemake.utils import validate

from heatdata.errors import ConfigError
from heatdata.experiments import config as checks

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = ROOT / "workflow" / "schemas" / "config.schema.yaml"


def run_config(**overrides) -> dict:
    """config/config.yaml with ``overrides``, aliases renamed and the schema's defaults filled in."""
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    config.update(overrides)
    config["catalog"] = str(ROOT / "data" / "models" / "catalog.csv")
    checks.accept_aliases(config)
    validate(config, str(SCHEMA))
    return config


def test_the_default_config_passes_and_names_its_objects():
    config = run_config()
    specs = checks.descriptor_specs(config)
    catalog = checks.run_catalog(config)
    checks.check_stages(config, catalog.index.tolist(), specs)
    assert checks.run_captures(config, catalog.index.tolist()) == {}
    assert catalog.index.tolist() == catalog["object"].tolist() and len(catalog) == 14
    assert [s.name for s in specs].count(config["primary_descriptor"]) == 1


@pytest.mark.parametrize(
    "overrides, message",
    [
        ({"objects": ["no-such-object"]}, r"objects: \['no-such-object'\] are not in the catalogue"),
        ({"primary_descriptor": "esf/seed=9"}, "primary_descriptor 'esf/seed=9' is not one of descriptors"),
        ({"descriptors": [{"kind": "pvhk"}, {"kind": "pvhk"}]}, "the same descriptor twice"),
        ({"descriptors": [{"kind": "pvhk", "samples": 2.5}]}, r"descriptors\[0\]: .*whole number"),
        ({"library_sizes": [400]}, r"library_sizes \[400\] exceed views.train"),
        ({"objects": ["beer-mug"], "color_twins": {"objects": ["bread"]}}, r"color_twins: colour twins of \['bread'\]"),
    ],
)
def test_each_check_names_its_key(overrides, message):
    config = run_config(**overrides)
    with pytest.raises(ConfigError, match=message):
        specs = checks.descriptor_specs(config)
        catalog = checks.run_catalog(config)
        checks.check_stages(config, catalog.index.tolist(), specs)


def test_old_spellings_are_renamed_with_a_warning():
    config = {"colour_twins": {"objects": ["beer-mug"]}, "rump": {"neighbours": 4}, "people": {}}
    with pytest.warns(DeprecationWarning, match="colour_twins is deprecated: spell it color_twins"):
        notes = checks.accept_aliases(config)
    assert config == {"color_twins": {"objects": ["beer-mug"]}, "rump": {"n_neighbors": 4}, "people": {}}
    assert notes == [
        "config key colour_twins is deprecated: spell it color_twins",
        "config key rump.neighbours is deprecated: spell it rump.n_neighbors",
    ]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the one spelling warns about nothing
        assert checks.accept_aliases(config) == []
    with pytest.raises(ConfigError, match="colour_twins is the old spelling of color_twins: give one of them"):
        checks.accept_aliases({"colour_twins": {}, "color_twins": {}})


def test_the_checks_import_no_plotting_and_no_stitching():
    code = (
        "import sys, heatdata.experiments.config; "
        "print(sorted(m for m in sys.modules if m.startswith(('matplotlib', 'heatdata.jasnom', 'heatdata.reporting'))))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
