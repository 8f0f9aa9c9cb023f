"""JASNOM's defaults: the workflow's schema says the same."""

from heatdata.jasnom.seam import stitch


def test_the_workflow_schema_defaults_are_the_library_defaults():
    import inspect
    from pathlib import Path

    import yaml

    schema = yaml.safe_load((Path(__file__).parents[2] / "workflow/schemas/config.schema.yaml").read_text())
    keys = schema["properties"]["stitch"]["properties"]
    signature = inspect.signature(stitch).parameters
    for name in ("alpha", "beta", "gamma", "samples"):
        assert keys[name]["default"] == signature[name].default, name
    for name in ("along", "robust"):  # unset: the library chooses by the kind of input (cuts or scans)
        assert "default" not in keys[name] and signature[name].default is None
    assert keys["pairs"]["items"]["properties"]["scans"]["default"] is signature["scans"].default
