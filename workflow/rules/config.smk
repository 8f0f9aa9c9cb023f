# The config, read as the schema types it and validated against it before any rule is defined; an error is one
# line naming the key.
from pathlib import Path

import jsonschema
import yaml
from snakemake.exceptions import WorkflowError
from snakemake.logging import logger
from snakemake.utils import validate

from heatdata.errors import ConfigError
from heatdata.io.bounded_yaml import load_yaml
from heatdata.experiments.config import accept_aliases


def load_schema(path):
    """A schema of workflow/schemas, read once (snakemake's validate reads its file at every call)."""
    with open(workflow.source_path(path)) as file:
        return yaml.safe_load(file)


SCHEMA = load_schema("../schemas/config.schema.yaml")


def typed(value, schema):
    """--config key={...} hands nested values over as strings (YAML's BaseLoader): read them by the schema's types."""
    if isinstance(value, dict):
        return {k: typed(v, schema.get("properties", {}).get(k, {})) for k, v in value.items()}
    if isinstance(value, list):
        return [typed(v, schema.get("items", {})) for v in value]
    types = schema.get("type", [])
    # a number or boolean where the schema allows one, or where it says nothing (a descriptor's kind-specific options)
    untyped = not types and "enum" not in schema
    if isinstance(value, str) and (untyped or {"integer", "number", "boolean"} & set(
            [types] if isinstance(types, str) else types)):
        parsed = load_yaml(value, "--config", ConfigError)
        return value if parsed is None or isinstance(parsed, (str, dict, list)) else parsed
    return value


try:
    # each config file read again, bounded and without YAML's aliases, before anything walks the config: 400 bytes of
    # nested aliases stand for 10^9 values, and the typing below and the schema would walk every one
    for path in workflow.configfiles:
        load_yaml(Path(path).read_text(), str(path), ConfigError)
    for note in accept_aliases(config):  # the old spellings, renamed with a warning
        logger.warning(note)
    config.update(typed(dict(config), SCHEMA))
except ConfigError as exc:
    raise WorkflowError(f"config error: {exc}") from None


def schema_message(error, where=""):
    """A jsonschema error as one line naming the key (``where``: what was validated, before it)."""
    key = ".".join(str(part) for part in error.absolute_path) or "the config"
    return WorkflowError(f"config error: {where}{key}: {error.message}")


def schema_error(exc):
    """The one line of :func:`schema_message` for snakemake's validate's WorkflowError, or None."""
    cause = exc.__cause__ or exc.__context__
    while cause is not None and not isinstance(cause, jsonschema.ValidationError):
        cause = cause.__cause__ or cause.__context__
    return None if cause is None else schema_message(cause)


try:
    validate(config, "../schemas/config.schema.yaml")
except WorkflowError as exc:  # one line naming the key, not the whole schema
    raise (schema_error(exc) or exc) from None
