"""The ``docs_*`` targets: which run each reads, and the steps that write its tables and figures.

The targets are a table, ``workflow/docs_targets.yaml``, checked by ``workflow/schemas/docs_targets.schema.yaml``.
``workflow/rules/docs.smk`` makes one Snakemake rule of each, which runs its steps with
:func:`heatdata.experiments.publish.publish`; the tests read the same table to dry-run every target. Both files
belong to the repository's workflow, not to an installed package.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any, NamedTuple

import jsonschema
import yaml

from heatdata.descriptors import DEFAULT_DESCRIPTOR, file_name
from heatdata.errors import HeatdataError

WORKFLOW = Path(__file__).resolve().parents[2] / "workflow"
TARGETS_FILE = WORKFLOW / "docs_targets.yaml"
SCHEMA_FILE = WORKFLOW / "schemas" / "docs_targets.schema.yaml"
#: the library file the poses and open sets are measured with: the default descriptor's, 40 views an object
DEFAULT_LIBRARY = f"{file_name(DEFAULT_DESCRIPTOR.name)}-40.parquet"
#: what a target's paths and arguments may name, and what it stands for
PLACEHOLDERS = {"{default_library}": DEFAULT_LIBRARY}


class Target(NamedTuple):
    """A ``docs_*`` target: the results folder of the run it publishes (None: it reads no run), its config files,
    its inputs, the files it writes into docs/ and the steps of :func:`publish` that write them."""

    results: str | None
    configs: list[str]
    inputs: list[str]
    outputs: list[str]
    steps: list[dict]


def _filled(value: Any) -> Any:
    """``value`` with every placeholder of :data:`PLACEHOLDERS` in its strings replaced."""
    if isinstance(value, str):
        for placeholder, meaning in PLACEHOLDERS.items():
            value = value.replace(placeholder, meaning)
        return value
    if isinstance(value, list):
        return [_filled(item) for item in value]
    if isinstance(value, dict):
        return {key: _filled(item) for key, item in value.items()}
    return value


def read_targets(path: str | Path = TARGETS_FILE) -> dict[str, dict]:
    """The targets' table as written, checked against the schema (a :class:`HeatdataError` naming the target and
    key that fail)."""
    table = yaml.safe_load(Path(path).read_text())
    schema = yaml.safe_load(SCHEMA_FILE.read_text())
    error = jsonschema.exceptions.best_match(jsonschema.Draft202012Validator(schema).iter_errors(table))
    if error is not None:
        where = "/".join(map(str, error.absolute_path)) or "the table"
        raise HeatdataError(f"{path}: {where}: {error.message}")
    return table


def targets(objects: Sequence[str], results: str, path: str | Path = TARGETS_FILE) -> dict[str, Target]:
    """Every ``docs_*`` target of ``workflow/rules/docs.smk``; ``objects`` and ``results`` are the current run's (the
    rendered views of a run are inputs only when it is the current one)."""
    found = {}
    for name, entry in read_targets(path).items():
        views = entry.get("views")
        inputs = entry["inputs"] + ([f"{views}/views/{obj}.parquet" for obj in objects] if views == results else [])
        found[name] = Target(
            entry["results"], entry["configs"], _filled(inputs), entry["outputs"], _filled(entry["steps"])
        )
    return found
