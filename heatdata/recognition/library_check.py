"""A library file checked as a whole when it loads: its metadata against a schema, then against its rows.

A library file comes from elsewhere (a colleague, a cluster, a download), so nothing in it is trusted.
:func:`check_library` validates every metadata field with a JSON Schema (:data:`METADATA_SCHEMA`: types, ranges,
a time rule among the allowed ones), refuses a number that is not finite, and then checks what a schema cannot
say: the objects equal the rows' objects, every row's values are as long as the probe's, a time-scaled kind has one
time scale per object, sizes and surfaces name the library's objects. The descriptor spec's fitted arrays are
checked when the spec is made (:meth:`heatdata.descriptors.Kind.fitted_shapes`). Every failure is a
:class:`~heatdata.errors.LibraryError` of one line.
"""

from __future__ import annotations

import math
from typing import Any

import jsonschema
import numpy as np
import pandas as pd

from heatdata.descriptors import DescriptorSpec
from heatdata.errors import HeatdataError, LibraryError
from heatdata.recognition.evaluate import TIME_RULES

#: the most library views per object a library file may hold (one every 0.1 degree)
MAX_LIBRARY_SIZE = 3600
#: the largest time scale (Alg. 5.1) a library may give an object: that of an object tens of metres across
MAX_TIME_SCALE = 1e3
#: object names are at most this long
MAX_NAME = 200

_NUMBER = {"type": "number"}
_NAME = {"type": "string", "minLength": 1, "maxLength": MAX_NAME}

#: the JSON Schema of a library file's metadata (:func:`heatdata.build_library`'s)
METADATA_SCHEMA: dict[str, Any] = {
    "type": "object",
    "required": ["format", "heatdata_version", "spec", "library_size", "objects", "time_rule", "probe"],
    "properties": {
        "format": {"type": "integer"},
        "heatdata_version": {"type": "string", "minLength": 1, "maxLength": 64},
        "spec": {
            "type": "object",
            "required": ["kind", "options", "name"],
            "properties": {
                "kind": _NAME,
                "options": {"type": "object"},
                "fitted": {"type": ["object", "null"], "additionalProperties": {"type": ["array", "number"]}},
                "name": {"type": "string", "minLength": 1, "maxLength": 1000},
            },
        },
        "library_size": {"type": "integer", "minimum": 1, "maximum": MAX_LIBRARY_SIZE},
        "objects": {"type": "array", "items": _NAME, "minItems": 1, "uniqueItems": True},
        "time_scales": {
            "type": ["array", "null"],
            "items": {
                "type": "object",
                "required": ["object", "time_scale"],
                "properties": {
                    "object": _NAME,
                    "time_scale": {"type": "number", "exclusiveMinimum": 0, "maximum": MAX_TIME_SCALE},
                },
            },
        },
        "time_rule": {"enum": list(TIME_RULES)},
        "render": {"type": "object"},
        "probe": {"type": "array", "items": _NUMBER, "minItems": 1},
        "source": {"type": "string"},
        "sizes": {
            "type": "object",
            "additionalProperties": {
                "type": "array",
                "items": {"type": "number", "exclusiveMinimum": 0, "maximum": 100},
                "minItems": 3,
                "maxItems": 3,
            },
        },
        "confidence": {
            "type": ["object", "null"],
            "required": ["coef", "intercept", "threshold", "known", "unknown", "auroc"],
            "properties": {
                "coef": {"type": "array", "items": _NUMBER, "minItems": 2, "maxItems": 2},
                "intercept": _NUMBER,
                "threshold": {"type": "number", "minimum": 0, "maximum": 1},
                "known": {"type": "integer", "minimum": 0},
                "unknown": {"type": "integer", "minimum": 0},
                "auroc": {"type": "number", "minimum": 0, "maximum": 1},
            },
        },
        "surfaces": {
            "type": "object",
            "additionalProperties": {
                "type": "object",
                "required": ["points", "normals", "center", "diameter", "spacing"],
                "properties": {
                    "points": {"type": "string"},
                    "normals": {"type": "string"},
                    "center": {"type": "array", "items": _NUMBER, "minItems": 3, "maxItems": 3},
                    "diameter": {"type": "number", "exclusiveMinimum": 0},
                    "spacing": {"type": "number", "exclusiveMinimum": 0},
                    "coloured": {"type": "boolean"},
                },
            },
        },
    },
}

_VALIDATOR = jsonschema.Draft202012Validator(METADATA_SCHEMA)


def shortened(text: str, limit: int = 160) -> str:
    """``text`` cut to ``limit`` characters (a damaged field can be megabytes long)."""
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _not_finite(value: Any, where: str) -> str | None:
    """The key of the first number in ``value`` that is not finite (NaN, infinite), or None."""
    stack = [(value, where)]
    while stack:
        item, key = stack.pop()
        if isinstance(item, dict):
            stack.extend((v, f"{key}.{k}") for k, v in item.items())
        elif isinstance(item, list):
            stack.extend((v, f"{key}[{i}]") for i, v in enumerate(item))
        elif isinstance(item, float) and not math.isfinite(item):
            return key
    return None


def check_metadata(metadata: dict) -> None:
    """Validate a library file's metadata against :data:`METADATA_SCHEMA`, and every number in it but the probe's
    as finite (the probe may hold a NaN its descriptor gives).

    Parameters
    ----------
    metadata : dict
        The file's ``library`` metadata.

    Raises
    ------
    LibraryError
        The first field that is wrong, named by its key.
    """
    objects = metadata.get("objects")
    if isinstance(objects, list) and len(objects) > 1:  # 10,000 names: checked here by the schema's rule, 100x faster
        unnamed = next((k for k, o in enumerate(objects) if not (isinstance(o, str) and 0 < len(o) <= MAX_NAME)), None)
        if unnamed is not None:
            raise LibraryError(f"objects.{unnamed}: not a name of 1 to {MAX_NAME} characters")
        if len(set(objects)) != len(objects):
            raise LibraryError("objects: has non-unique elements")
        metadata = {**metadata, "objects": objects[:1]}
    try:
        error = jsonschema.exceptions.best_match(_VALIDATOR.iter_errors(metadata))
    except RecursionError:
        raise LibraryError("its metadata nest too deep") from None
    if error is not None:
        key = ".".join(str(part) for part in error.absolute_path) or "the metadata"
        raise LibraryError(f"{key}: {shortened(error.message)}")
    bad = _not_finite({k: v for k, v in metadata.items() if k != "probe"}, "metadata")
    if bad:
        raise LibraryError(f"{bad.removeprefix('metadata.')}: not a finite number")


def check_rows(rows: pd.DataFrame, metadata: dict, values: np.ndarray | None = None) -> None:
    """Check the rows of a library file against its (schema-valid) metadata.

    Parameters
    ----------
    rows : pandas.DataFrame
        Its :data:`heatdata.io.tables.DESCRIPTOR_SCHEMA` rows.
    metadata : dict
        Its metadata, valid by :func:`check_metadata`.
    values : (len(rows), M) float64, optional
        The rows' values as one array, when they were read as one (so all are M long).

    Raises
    ------
    LibraryError
        Rows of another descriptor or split, values not as long as the probe's, weights not as long as the
        values, objects other than the metadata's, more views per object than the library size, or time scales,
        sizes or surfaces of other objects.
    """
    name = metadata["spec"]["name"]
    if not rows["descriptor"].eq(name).all():
        raise LibraryError(f"rows of descriptors {sorted(set(rows['descriptor']) - {name})}, not only {name}")
    if not rows["split"].isin(["train", "similarity"]).all():
        raise LibraryError(f"rows of splits {sorted(set(rows['split']))}, not train and similarity")
    length = len(metadata["probe"])
    lengths = (
        {values.shape[1]}
        if values is not None
        else {len(v) if isinstance(v, np.ndarray) else -1 for v in rows["values"]}
    )
    if lengths != {length}:
        raise LibraryError(f"rows of {sorted(lengths)} values; its probe has {length}")
    given = rows["weights"][rows["weights"].notna()]
    weights = {len(w) for w in given}
    if weights - {length}:
        raise LibraryError(f"rows of {sorted(weights)} weights for {length} values")
    train = rows[rows["split"] == "train"]
    objects = set(metadata["objects"])
    named = set(train["object"].unique())
    if named != objects:
        raise LibraryError(f"its library views are of {len(named)} objects, its metadata names {len(objects)}")
    outside = set(rows["object"].unique()) - objects
    if outside:
        raise LibraryError(f"its similarity views name objects outside the library: {sorted(outside)[:5]}")
    most = int(train.groupby("object")["view_id"].nunique().max())
    if most > metadata["library_size"]:
        raise LibraryError(f"an object has {most} library views; the library size is {metadata['library_size']}")
    scales = metadata.get("time_scales")
    if scales is not None:
        scaled = [row["object"] for row in scales]
        if len(scaled) != len(set(scaled)) or set(scaled) != objects:
            raise LibraryError(f"time scales of {len(set(scaled))} objects ({len(scaled)} entries) for {len(objects)}")
    for key in ("sizes", "surfaces"):
        others = set(metadata.get(key) or {}) - objects
        if others:
            raise LibraryError(f"{key} of objects outside the library: {sorted(others)[:5]}")


def spec_of(meta: dict) -> DescriptorSpec:
    """The descriptor spec a library's metadata stores (its ``spec``), fitted arrays checked.

    An option the spec lacks (added to its kind since the file was written) takes the value that describes as the
    kind did then (:attr:`heatdata.descriptors.base.Option.before`), so that a query is described as the library's
    views were.

    Parameters
    ----------
    meta : dict
        The metadata's ``spec``: ``kind``, ``options``, ``fitted``, ``name``.

    Returns
    -------
    DescriptorSpec

    Raises
    ------
    LibraryError
        An unknown kind, bad options or fit, or a spec whose name is not the stored one.
    """
    try:
        spec = DescriptorSpec.from_dict({**meta["options"], "kind": meta["kind"], "fitted": meta.get("fitted")})
    except (HeatdataError, TypeError, ValueError) as exc:
        raise LibraryError(f"spec: {shortened(str(exc))}") from None
    if spec.name != meta["name"]:
        raise LibraryError(f"spec: reads as {spec.name}, not {shortened(meta['name'])}")
    written_before = {
        option.name: option.before
        for option in spec.impl.options
        if option.before is not None and option.name not in meta["options"]
    }
    return spec.replace(**written_before) if written_before else spec


def check_values(values: np.ndarray, spec: DescriptorSpec) -> None:
    """Check a library's values: finite everywhere (a view with NaN values is left out when a library is built), and
    not negative where the kind's values are a histogram (its index compares their square roots).

    Parameters
    ----------
    values : (N, M) float
        The rows' values.
    spec : DescriptorSpec
        The library's descriptor.

    Raises
    ------
    LibraryError
    """
    finite = np.isfinite(values).all(axis=1)
    if not finite.all():
        raise LibraryError(f"values: {int((~finite).sum())} of {len(values)} rows hold NaN or infinite values")
    if spec.impl.index_space == "hellinger":
        negative = (values < 0).any(axis=1)
        if negative.any():
            rows = f"{int(negative.sum())} of {len(values)} rows"
            raise LibraryError(f"values: {rows} hold negative values; a {spec.kind} is a histogram")


def check_library(rows: pd.DataFrame, metadata: dict, path: object, values: np.ndarray | None = None) -> DescriptorSpec:
    """:func:`check_metadata`, :func:`spec_of` and :func:`check_rows`, with ``path`` in the message.

    Parameters
    ----------
    rows : pandas.DataFrame
        The file's rows.
    metadata : dict
        Its metadata.
    path : str or Path
        The file, for the message.
    values : (len(rows), M) float64, optional
        As :func:`check_rows`'s.

    Returns
    -------
    DescriptorSpec
        Its descriptor.

    Raises
    ------
    LibraryError
        ``"<path>: a damaged library file: <key>: <what is wrong>"``.
    """
    try:
        check_metadata(metadata)
        spec = spec_of(metadata["spec"])
        if spec.impl.time_scaled != (metadata.get("time_scales") is not None):
            raise LibraryError(f"time_scales: {'missing for' if spec.impl.time_scaled else 'given to'} {spec.name}")
        check_rows(rows, metadata, values)
        if values is not None:
            check_values(values, spec)
        foreign = spec.impl.foreign_fit(spec, metadata["objects"])
        if foreign:
            raise LibraryError(f"spec: {foreign}")
    except LibraryError as exc:
        raise LibraryError(f"{path}: a damaged library file: {exc}") from None
    return spec
