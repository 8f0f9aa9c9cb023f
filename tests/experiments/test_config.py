"""The workflow's config checks (heatdata.experiments.config), called as common.smk calls them."""

import subprocess
import sys
import warnings
from pathlib import Path
from types import SimpleNamespace

import pytest
import yaml
from snakemake.utils import validate
from test_workflow import tiny_config

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


def checked(config: dict) -> None:
    """Every check of common.smk, in its order."""
    specs = checks.descriptor_specs(config)
    catalog = checks.run_catalog(config)
    checks.check_results(config, catalog)
    if config["stitch"]["pairs"]:
        catalog = checks.stitched_objects(config, catalog)
    checks.check_stages(config, catalog.index.tolist(), specs)
    checks.run_captures(config, catalog.index.tolist())


def tiny(**overrides) -> dict:
    """The workflow tests' tiny config with ``overrides``, validated: the schema's defaults filled in."""
    config = tiny_config(**overrides)
    validate(config, str(SCHEMA))
    return config


@pytest.mark.parametrize(
    "overrides, message",
    [
        ({"library_sizes": [8, 50]}, "library_sizes [50] exceed views.train = 8"),
        ({"color_twins": {"objects": ["bread"]}}, "color_twins: colour twins of ['bread']: not in the catalogue"),
        ({"primary_descriptor": "pvhk/polar/center/64"}, "primary_descriptor 'pvhk/polar/center/64' is not one"),
        ({"compact": {"enabled": True}, "library_sizes": [8, 1]}, "two or more views around the circle"),
        ({"compact": {"enabled": True}, "objects": ["beer-mug"]}, "give two or more objects"),
        ({"descriptors": [{"kind": "shot"}]}, "descriptors[0]: unknown descriptor kind 'shot'"),
        ({"multiview": {"enabled": True, "descriptor": "ft-pvhk/polar/center/32"}}, "a time-scaled kind"),
        (
            {"multiview": {"enabled": True, "library_views": [12]}},
            "multiview.library_views [12] exceed views.train = 8",
        ),
        ({"descriptors": [{"kind": "esf", "samples": 64}]}, "descriptors[0]: an esf takes no samples"),
        (
            {"compact": {"enabled": True, "descriptor": {"kind": "esf"}}},
            "compact.descriptor: an esf has no heat source",
        ),
        ({"comparison": {"enabled": True, "isomap_objects": ["unicorn"]}}, "comparison.isomap_objects: ['unicorn']"),
        ({"ablation": "/no/ablation.csv"}, "ablation: /no/ablation.csv: not a readable ablation table"),
        (
            {
                "stitch": {
                    "pairs": [
                        {
                            "object": "x",
                            "first": str(ROOT / "README.md"),
                            "second": str(ROOT / "README.md"),
                            "motion": [[1, 0, 0, 0], [0, -1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],
                        }
                    ]
                }
            },
            "stitch.pairs[0].motion is not a rigid motion",
        ),
        ({"stitch": {"pairs": [{"object": "beer-mug", "first": "README.md", "second": "README.md"}]}}, "already one"),
        ({"captures": {"dir": str(ROOT / "tests")}}, "captures.dir: "),
    ],
)
def test_a_bad_run_is_one_config_error_naming_its_key(overrides, message):
    with pytest.raises(ConfigError) as caught:
        checked(tiny(**overrides))
    assert message in str(caught.value) and "\n" not in str(caught.value)


MODELS = ROOT / "data" / "models"


@pytest.mark.parametrize(
    "overrides, message",
    [
        # results: data/models rewrote the input catalogue (15 objects became 3) with exit status 0
        ({"results": str(MODELS)}, f"results: {MODELS} holds catalog ({MODELS / 'catalog.csv'}), which the run reads"),
        ({"results": str(ROOT / "data")}, "holds catalog"),
        ({"results": str(MODELS / "beer-mug")}, "holds the catalogue's model of beer-mug"),
        ({"results": ""}, "results: give the folder for the run's outputs (it is empty)"),
        ({"results": " "}, "it is empty"),
        ({"results": "/"}, "results: / is a folder above the working one"),
        ({"results": str(ROOT / "README.md")}, "README.md is a file, not a folder"),
        ({"models_dir": str(MODELS), "objects": [], "results": str(MODELS / "out")}, "lies inside models_dir"),
        (
            {"captures": {"dir": str(ROOT / "tests")}, "results": str(ROOT / "tests" / "out")},
            "lies inside captures.dir",
        ),
    ],
)
def test_the_results_folder_never_holds_an_input(overrides, message, monkeypatch):
    monkeypatch.chdir(ROOT)
    config = tiny(**overrides)
    with pytest.raises(ConfigError) as caught:
        checks.check_results(config, checks.run_catalog(config))
    assert message in str(caught.value) and "\n" not in str(caught.value)
    monkeypatch.chdir(ROOT / "docs")
    with pytest.raises(ConfigError, match="results: . is the working folder"):
        checks.check_results(tiny(results="."), checks.run_catalog(tiny()))
    checks.check_results(tiny(results="results/run"), checks.run_catalog(tiny()))


@pytest.mark.parametrize(
    "overrides, key",
    [
        ({"views": {"train": 10**9}}, "views.train"),
        ({"views": {"test": 10**12}}, "views.test"),
        ({"stitch": {"samples": 10**9}}, "stitch.samples"),
        ({"multiview": {"particles": [10**9]}}, "multiview.particles.0"),
        ({"library_sizes": [10**6]}, "library_sizes.0"),
    ],
)
def test_counts_beyond_what_the_machine_holds_are_refused_by_the_schema(overrides, key):
    """views.train: 1e9, views.test: 1e12 and samples: 1e9 passed the check; the render job died with SystemError."""
    from jsonschema import ValidationError

    with pytest.raises(Exception) as caught:
        tiny(**overrides)
    cause = caught.value.__cause__ or caught.value.__context__
    while cause is not None and not isinstance(cause, ValidationError):
        cause = cause.__cause__ or cause.__context__
    assert ".".join(map(str, cause.absolute_path)) == key and "is greater than the maximum" in cause.message
    with pytest.raises(ConfigError, match=r"descriptors\[0\]: pvhk: option samples must be in 2..4096"):
        checks.descriptor_specs(tiny(descriptors=[{"kind": "pvhk", "samples": 10**9}]))


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
    with pytest.warns(DeprecationWarning) as warned:
        notes = checks.accept_aliases(config)
    assert config == {"color_twins": {"objects": ["beer-mug"]}, "rump": {"n_neighbors": 4}, "people": {}}
    assert (
        notes
        == [str(w.message) for w in warned]
        == [
            "config key colour_twins is deprecated: spell it color_twins",
            "config key rump.neighbours is deprecated: spell it rump.n_neighbors",
        ]
    )
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


def test_the_camera_distance_is_metres_or_fit():
    assert tiny(views={"distance": "fit"})["views"]["distance"] == "fit"
    assert tiny(views={"distance": 2.5})["views"]["distance"] == 2.5
    for wrong in ("far", 0, -1.0):
        with pytest.raises(Exception, match=r"(?s)is not valid under any.*\['views'\]\['properties'\]\['distance'\]"):
            tiny(views={"distance": wrong})


def test_the_report_sorts_confusion_figures_by_library_size_as_numbers():
    labels = checks.confusion_labels([40, 12, 8, 5])
    sizes = [labels(SimpleNamespace(level="objects", size=s))["library views"] for s in ("40", "12", "8", "5")]
    assert sorted(sizes) == ["05", "08", "12", "40"]  # the report sorts labels as text: "12" < "40" < "5" < "8"
    assert checks.confusion_labels([8, 4])(SimpleNamespace(level="classes", size="8")) == {
        "matrix": "classes",
        "library views": "8",
    }


def test_the_runs_units_and_up_axis_reach_every_model_that_names_none(tmp_path):
    import trimesh

    trimesh.creation.box(extents=(60.0, 60.0, 200.0)).export(tmp_path / "bottle.stl")
    folder = checks.run_catalog(run_config(models_dir=str(tmp_path), models_units="mm", models_up_axis="z"))
    assert folder[["units", "up_axis"]].values.tolist() == [["mm", "z"]]
    embedded = checks.run_catalog(run_config(models_up_axis="z"))
    assert set(embedded["up_axis"]) == {"z"} and set(embedded["units"]) == {"m"}
    with pytest.raises(Exception, match="'x' is not one of"):
        run_config(models_up_axis="x")
