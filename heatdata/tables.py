"""Parquet tables with explicit schemas and provenance metadata.

Every table heatdata writes carries, as key-value metadata, the heatdata version and
the run parameters (JSON) that produced it, so a result can be traced to its config.
The descriptor table has one row per view x source x descriptor kind; its columns are
documented in ``docs/tables.md``.
"""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from .errors import HeatdataError

DESCRIPTOR_SCHEMA = pa.schema([
    ("object", pa.string()),
    ("label", pa.string()),
    ("view_id", pa.string()),
    ("split", pa.string()),
    ("azimuth", pa.float64()),
    ("elevation", pa.float64()),
    ("distance", pa.float64()),
    ("seed", pa.int64()),
    ("n_vertices", pa.int64()),
    ("n_boundary", pa.int64()),
    ("descriptor", pa.string()),
    ("kind", pa.string()),
    ("sampling", pa.string()),
    ("source_rule", pa.string()),
    ("color_map", pa.string()),
    ("source", pa.int64()),
    ("time", pa.float64()),
    ("lambda2", pa.float64()),
    ("values", pa.list_(pa.float64())),
    ("positions", pa.list_(pa.float64())),
    ("repairs", pa.list_(pa.string())),
    ("seconds", pa.float64()),
])

PREDICTION_SCHEMA = pa.schema([
    ("descriptor", pa.string()),
    ("object", pa.string()),
    ("label", pa.string()),
    ("view_id", pa.string()),
    ("azimuth", pa.float64()),
    ("predicted_object", pa.string()),
    ("predicted_label", pa.string()),
    ("predicted_view_id", pa.string()),
    ("predicted_azimuth", pa.float64()),
    ("distance", pa.float64()),
    ("correct", pa.bool_()),
])


def write_table(frame: pd.DataFrame, path: str | Path, schema: pa.Schema, metadata: dict | None = None) -> None:
    """Write ``frame`` as Parquet with ``schema`` and JSON-encoded ``metadata``."""
    from . import __version__

    missing = [name for name in schema.names if name not in frame.columns]
    if missing:
        raise HeatdataError(f"{path}: table lacks column(s) {', '.join(missing)}")
    table = pa.Table.from_pandas(frame[schema.names], schema=schema, preserve_index=False)
    meta = {b"heatdata_version": __version__.encode(), b"heatdata_run": json.dumps(metadata or {}, sort_keys=True,
                                                                                   default=str).encode()}
    table = table.replace_schema_metadata({**(table.schema.metadata or {}), **meta})
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    pq.write_table(table, path)


def read_table(path: str | Path) -> tuple[pd.DataFrame, dict]:
    """Read a heatdata Parquet table and its run metadata."""
    path = Path(path)
    if not path.is_file():
        raise HeatdataError(f"{path}: no such table")
    try:
        table = pq.read_table(path)
    except Exception as exc:
        raise HeatdataError(f"{path}: not a readable Parquet table ({exc})") from exc
    raw = table.schema.metadata or {}
    meta = json.loads(raw.get(b"heatdata_run", b"{}"))
    meta["heatdata_version"] = raw.get(b"heatdata_version", b"").decode()
    return table.to_pandas(), meta
