"""Parquet tables with explicit schemas and provenance metadata.

Every table heatdata writes carries, as key-value metadata, the heatdata version and
the run parameters (JSON) that produced it, so a result can be traced to its config.
The descriptor table has one row per view x source x descriptor kind; its columns are
documented in ``docs/tables.md``.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.parquet as pq

from heatdata.errors import HeatdataError
from heatdata.io.files import atomic, require_file

#: the columns of a descriptor table (a run's ``descriptors.parquet``, a library file): one row per view and
#: descriptor (and time object, for a time-scaled kind); ``values`` the descriptor, ``repairs`` what was mended
DESCRIPTOR_SCHEMA = pa.schema(
    [
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
        ("time_object", pa.string()),
        ("lambda2", pa.float64()),
        ("t_global", pa.float64()),
        ("values", pa.list_(pa.float64())),
        ("positions", pa.list_(pa.float64())),
        ("weights", pa.list_(pa.float64())),
        ("repairs", pa.list_(pa.string())),
        ("seconds", pa.float64()),
    ]
)


VIEW_SCHEMA = pa.schema(
    [
        ("view_id", pa.string()),
        ("object", pa.string()),
        ("label", pa.string()),
        ("split", pa.string()),
        ("seed", pa.int64()),
        ("azimuth", pa.float64()),
        ("elevation", pa.float64()),
        ("distance", pa.float64()),
        ("n_vertices", pa.int64()),
        ("vertices", pa.list_(pa.float64())),
        ("faces", pa.list_(pa.int32())),
        ("colors", pa.list_(pa.float32())),
        ("pose", pa.list_(pa.float64())),
        ("intrinsics", pa.string()),
        ("repairs", pa.list_(pa.string())),
    ]
)


PREDICTION_SCHEMA = pa.schema(
    [
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
        ("library_size", pa.int64()),
    ]
)


COMPACT_LIBRARY_SCHEMA = pa.schema(
    [
        ("object", pa.string()),
        ("label", pa.string()),
        ("library_size", pa.int64()),
        ("descriptor", pa.string()),
        ("view_id", pa.string()),
        ("azimuth", pa.float64()),
        ("source", pa.int64()),
        ("values", pa.list_(pa.float64())),
        ("cost", pa.float64()),
        ("seconds", pa.float64()),
    ]
)


#: one run of Algorithm 4.1 (heatdata.experiments.multiview.multiview_trials)
TRIAL_SCHEMA = pa.schema(
    [
        ("descriptor", pa.string()),
        ("library_views", pa.int64()),
        ("object", pa.string()),
        ("start", pa.float64()),
        ("particles", pa.int64()),
        ("bootstrap", pa.string()),
        ("policy", pa.string()),
        ("repetition", pa.int64()),
        ("estimate", pa.string()),
        ("correct", pa.bool_()),
        ("identified", pa.bool_()),
        ("converged", pa.bool_()),
        ("degrees", pa.float64()),
        ("stops", pa.int64()),
        ("restarts", pa.int64()),
        ("comparisons", pa.int64()),
        ("exhaustive", pa.int64()),
        ("seconds", pa.float64()),
    ]
)


#: one object found in a scene, or one object of a scene no detection found (heatdata.experiments.scenes.score_scene)
DETECTION_SCHEMA = pa.schema(
    [
        ("scene", pa.string()),
        ("descriptor", pa.string()),
        ("detection", pa.int64()),
        ("object", pa.string()),
        ("label", pa.string()),
        ("distance", pa.float64()),
        ("confidence", pa.float64()),
        ("known", pa.bool_()),
        ("azimuth", pa.float64()),
        ("pixels", pa.int64()),
        ("centroid", pa.list_(pa.float64())),
        ("bbox", pa.list_(pa.int64())),
        ("notes", pa.list_(pa.string())),
        ("mask", pa.binary()),
        ("truth", pa.string()),
        ("truth_label", pa.string()),
        ("iou", pa.float64()),
        ("correct", pa.bool_()),
        ("truth_pixels", pa.int64()),
        ("occluded", pa.float64()),
        ("cut", pa.bool_()),
        ("threshold", pa.float64()),
        ("verified", pa.bool_()),
        ("posed", pa.string()),
        ("fitness", pa.float64()),
        ("rmse", pa.float64()),
        ("explained", pa.float64()),
        ("in_front", pa.float64()),
        ("pose", pa.list_(pa.float64())),
        ("add_s", pa.float64()),
        ("add_s_ok", pa.bool_()),
        ("translation_error", pa.float64()),
        ("rotation_error", pa.float64()),
        ("symmetric", pa.bool_()),
        ("seconds", pa.float64()),
        ("seconds_without_pose", pa.float64()),
    ]
)


#: mu(s, s') of eq. 4.6 (heatdata.recognition.multiview.appearance.learn_similarity)
SIMILARITY_SCHEMA = pa.schema(
    [
        ("library_views", pa.int64()),
        ("object", pa.string()),
        ("azimuth", pa.float64()),
        ("similar_object", pa.string()),
        ("similar_azimuth", pa.float64()),
        ("similarity", pa.float64()),
        ("similar_alpha", pa.float64()),
    ]
)


def write_table(
    frame: pd.DataFrame,
    path: str | Path,
    schema: pa.Schema,
    metadata: dict | None = None,
    *,
    row_group_size: int | None = None,
) -> None:
    """Write ``frame`` as Parquet with ``schema`` and JSON-encoded ``metadata``.

    Parameters
    ----------
    frame : pandas.DataFrame
        The rows, with the schema's columns.
    path : str or Path
        The ``.parquet`` to write.
    schema : pyarrow.Schema
        One of this module's schemas (:data:`DESCRIPTOR_SCHEMA`, ...).
    metadata : dict, optional
        The run's settings, stored as JSON (:func:`read_metadata`).
    row_group_size : int, optional
        Rows per Parquet row group (pyarrow's default: about a million); smaller groups are decoded in parallel.
    """
    from heatdata.version import __version__

    missing = [name for name in schema.names if name not in frame.columns]
    if missing:
        raise HeatdataError(f"{path}: table lacks column(s) {', '.join(missing)}")
    table = pa.Table.from_pandas(frame[schema.names], schema=schema, preserve_index=False)
    meta = {
        b"heatdata_version": __version__.encode(),
        b"heatdata_run": json.dumps(metadata or {}, sort_keys=True, default=str).encode(),
    }
    table = table.replace_schema_metadata({**(table.schema.metadata or {}), **meta})
    with atomic(path) as temporary:
        pq.write_table(table, temporary, row_group_size=row_group_size)


def read_table(
    path: str | Path,
    *,
    columns: list[str] | None = None,
    filters: list | None = None,
    schema: pa.Schema | None = None,
) -> tuple[pd.DataFrame, dict]:
    """Read a heatdata Parquet table and its run metadata.

    ``columns`` and ``filters`` (pyarrow's, e.g. ``[("descriptor", "==", name)]``) read
    only part of a large table; filtered, it is read one row group at a time, so memory
    holds one group and the rows kept (``pq.read_table`` with filters decodes them all;
    ``benchmarks/README.md`` measures the difference).

    Parameters
    ----------
    path : str or Path
        A table heatdata wrote.
    columns : list of str, optional
        The columns to read (default all).
    filters : list of tuple, optional
        pyarrow's row filters, e.g. ``[("descriptor", "==", name)]``.
    schema : pyarrow.Schema, optional
        The table the caller needs (:data:`DESCRIPTOR_SCHEMA`, ...): a file without its columns is refused.

    Returns
    -------
    frame : pandas.DataFrame
        The rows kept.
    metadata : dict
        The run's settings and heatdata's version.

    Raises
    ------
    HeatdataError
        No such file, not a Parquet table, or without the columns of ``schema``.
    """
    file = _open(path)
    if schema is not None:
        missing = [name for name in schema.names if name not in file.schema_arrow.names]
        if missing:
            raise HeatdataError(f"{path}: not the table this needs: it lacks column(s) {', '.join(missing)}")
    try:
        if filters:
            parts = list(_row_groups(file, columns, filters))
            table = pa.concat_tables(parts) if parts else _empty(file, columns)
        else:
            table = file.read(columns=columns)
        frame = table.to_pandas()
    except Exception as exc:
        raise HeatdataError(f"{path}: not a readable Parquet table ({exc})") from exc
    return frame, _run_metadata(file, path)


def read_matrix_table(
    path: str | Path,
    matrix: str,
    *,
    schema: pa.Schema,
    skip: tuple[str, ...] = (),
    first: tuple[str, object] | None = None,
) -> tuple[pd.DataFrame, np.ndarray | None, dict]:
    """:func:`read_table` for a large table whose list column ``matrix`` holds rows of equal length: that column as
    one (N, M) array, without a Python object per row built and then copied.

    The frame's ``matrix`` column holds views of the array's rows. A table whose rows differ in length (or hold a
    null) is read as :func:`read_table` reads it, and the array is None. With ``first``, the rows whose column
    equals a value come first (each part in the file's order): each row is decoded straight into its place, so a
    caller that needs those rows as one block (a library's views) gets a slice of the array, not a second copy.

    Parameters
    ----------
    path : str or Path
        A table heatdata wrote.
    matrix : str
        A column of ``list<double>``.
    schema : pyarrow.Schema
        The table the caller needs: a file without its columns is refused.
    skip : tuple of str
        Columns not to read (they are left out of the frame).
    first : (column, value), optional
        The rows to put first.

    Returns
    -------
    frame : pandas.DataFrame
    values : (N, M) float64 or None
    metadata : dict
        As :func:`read_table`'s.

    Raises
    ------
    HeatdataError
        As :func:`read_table`.
    """
    file = _open(path)
    missing = [name for name in schema.names if name not in file.schema_arrow.names]
    if missing:
        raise HeatdataError(f"{path}: not the table this needs: it lacks column(s) {', '.join(missing)}")
    columns = [name for name in file.schema_arrow.names if name not in skip]
    try:
        frame = file.read(columns=[c for c in columns if c != matrix]).to_pandas()
        order = None
        if first is not None:
            chosen = frame[first[0]].eq(first[1]).to_numpy()
            if not chosen[: int(chosen.sum())].all():  # not already first
                order = np.concatenate([np.flatnonzero(chosen), np.flatnonzero(~chosen)])
                frame = frame.iloc[order].reset_index(drop=True)
        values = _matrix(file, matrix, path, order)
        if values is None:
            whole = file.read(columns=[matrix]).to_pandas()[matrix].to_numpy()
            frame.insert(columns.index(matrix), matrix, whole if order is None else whole[order])
        else:
            frame.insert(columns.index(matrix), matrix, list(values))
    except Exception as exc:
        raise HeatdataError(f"{path}: not a readable Parquet table ({exc})") from exc
    return frame, values, _run_metadata(file, path)


#: readers decoding a matrix column side by side
MATRIX_READERS = 4


def _matrix(file: pq.ParquetFile, column: str, path: str | Path, order: np.ndarray | None) -> np.ndarray | None:
    """A list column of equal-length rows as one (N, M) float64 array, row ``order[i]`` of the file as row ``i`` (the
    file's order without ``order``); None when its rows differ in length or one is null.

    The row groups are cut into :data:`MATRIX_READERS` contiguous spans, each decoded by a reader of its own sharing
    ``file``'s parsed footer, without arrow's thread pool: a Parquet file reader is not thread-safe (four threads
    sharing ``file`` hung within 300 reads of a 20-group table), and a reader per row group parsed the whole footer
    again each time (a 400,320-row file of 1,112 groups took 4.6 s, 48 s on busy cores).
    """
    import concurrent.futures
    import itertools
    import os

    leaves = [file.metadata.schema.column(k).path for k in range(file.metadata.num_columns)]
    leaf = leaves.index(f"{column}.list.element") if f"{column}.list.element" in leaves else None
    if leaf is None:
        return None
    metadata = file.metadata

    def lengths(group: int) -> tuple[int, int]:
        stats = metadata.row_group(group)
        return stats.num_rows, stats.column(leaf).num_values

    groups = [lengths(g) for g in range(file.num_row_groups)]
    rows = sum(g[0] for g in groups)
    if not rows:
        return None
    widths = {g[1] / g[0] for g in groups if g[0]}
    if len(widths) != 1 or not float(next(iter(widths))).is_integer():
        return None
    width = int(next(iter(widths)))
    out = np.empty((rows, width))
    starts = np.concatenate([[0], np.cumsum([g[0] for g in groups])])
    place = None
    if order is not None:
        place = np.empty(rows, np.int64)
        place[order] = np.arange(rows)

    def fill(span: range) -> bool:
        with pq.ParquetFile(path, metadata=metadata) as reader:
            for group in span:
                part = reader.read_row_group(group, columns=[column], use_threads=False).column(0)
                if _common_width(part) != width:
                    return False
                at = starts[group]
                for chunk in part.chunks:
                    block = chunk.flatten().to_numpy(zero_copy_only=False).reshape(-1, width)
                    if place is None:
                        out[at : at + len(chunk)] = block
                    else:
                        out[place[at : at + len(chunk)]] = block
                    at += len(chunk)
        return True

    workers = max(1, min(MATRIX_READERS, os.cpu_count() or 1, len(groups)))
    cuts = np.linspace(0, len(groups), workers + 1).round().astype(int)
    spans = [range(int(a), int(b)) for a, b in itertools.pairwise(cuts) if b > a]
    with concurrent.futures.ThreadPoolExecutor(max_workers=len(spans)) as pool:
        filled = list(pool.map(fill, spans))
    return out if all(filled) else None


def _common_width(column: pa.ChunkedArray) -> int | None:
    """The length every row of a list column has; None when their lengths differ, one is null, or it has no row."""
    if column.null_count or len(column) == 0:
        return None
    extent = pc.min_max(pc.list_value_length(column))
    width = extent["min"].as_py()
    return width if width == extent["max"].as_py() else None


def iter_table(
    path: str | Path, *, columns: list[str] | None = None, filters: list | None = None
) -> Iterator[pd.DataFrame]:
    """The rows of a heatdata table one Parquet row group at a time, filtered as in :func:`read_table`.

    For tables larger than memory: a run's descriptor table has one row group per object
    (:func:`concat_tables` writes each object's table as it comes), so this yields one
    object's rows at a time. Groups with no row kept are skipped.

    Parameters
    ----------
    path : str or Path
        A table heatdata wrote.
    columns : list of str, optional
        The columns to read (default all).
    filters : list of tuple, optional
        pyarrow's row filters, e.g. ``[("descriptor", "==", name)]``.
    """
    file = _open(path)
    try:
        for table in _row_groups(file, columns, filters or []):
            if table.num_rows:
                yield table.to_pandas()
    except Exception as exc:
        raise HeatdataError(f"{path}: not a readable Parquet table ({exc})") from exc


def iter_matrix_table(
    path: str | Path, matrix: str, *, columns: list[str] | None = None, filters: list | None = None
) -> Iterator[tuple[pd.DataFrame, np.ndarray]]:
    """:func:`iter_table` for a large table whose list column ``matrix`` holds rows of equal length: each row group
    as a frame without that column and the column as one (rows, M) float64 array, without a Python object per row.

    Parameters
    ----------
    path : str or Path
        A table heatdata wrote.
    matrix : str
        A column of ``list<double>``, among ``columns``.
    columns : list of str, optional
        The columns to read (default all).
    filters : list of tuple, optional
        pyarrow's row filters, as in :func:`read_table`.

    Yields
    ------
    frame : pandas.DataFrame
        The group's rows kept, without ``matrix``.
    values : (rows, M) float64

    Raises
    ------
    HeatdataError
        Not a readable table, or a group whose ``matrix`` rows differ in length or hold a null.
    """
    file = _open(path)
    try:
        for table in _row_groups(file, columns, filters or []):
            if not table.num_rows:
                continue
            column = table.column(matrix)
            width = _common_width(column)
            if width is None:
                raise HeatdataError(f"{path}: rows of {matrix!r} of different lengths, or empty, in one row group")
            values = pc.list_flatten(column).to_numpy().astype(np.float64, copy=False)
            yield table.drop_columns([matrix]).to_pandas(), values.reshape(table.num_rows, width)
    except HeatdataError:
        raise
    except Exception as exc:
        raise HeatdataError(f"{path}: not a readable Parquet table ({exc})") from exc


def read_metadata(path: str | Path) -> dict:
    """The run metadata of a heatdata table (as :func:`read_table` returns it), without reading its rows.

    Parameters
    ----------
    path : str or Path
        A table heatdata wrote.

    Returns
    -------
    dict
    """
    return _run_metadata(_open(path), path)


def _open(path: str | Path) -> pq.ParquetFile:
    path = require_file(path, "table")
    try:
        return pq.ParquetFile(path)
    except Exception as exc:
        raise HeatdataError(f"{path}: not a readable Parquet table ({exc})") from exc


def _row_groups(file: pq.ParquetFile, columns: list[str] | None, filters: list) -> Iterator[pa.Table]:
    """Each row group of ``file`` with only the rows ``filters`` keep and only ``columns``."""
    expression = pq.filters_to_expression(filters) if filters else None
    needed = None if columns is None or not filters else sorted(set(columns) | _filter_columns(filters))
    for k in range(file.num_row_groups):
        table = file.read_row_group(k, columns=needed)
        if expression is not None:
            table = table.filter(expression)
        yield table.select(columns) if columns is not None else table


def _empty(file: pq.ParquetFile, columns: list[str] | None) -> pa.Table:
    table = file.schema_arrow.empty_table()
    return table.select(columns) if columns is not None else table


def _run_metadata(file: pq.ParquetFile, path: str | Path) -> dict:
    """The run parameters a heatdata table carries, with ``heatdata_version``."""
    raw = file.schema_arrow.metadata or {}
    try:
        meta = json.loads(raw.get(b"heatdata_run", b"{}"))
        if not isinstance(meta, dict):
            raise ValueError(f"a {type(meta).__name__}, not a mapping")
        meta["heatdata_version"] = raw.get(b"heatdata_version", b"").decode()
    except ValueError as exc:  # JSONDecodeError and UnicodeDecodeError are ValueErrors
        raise HeatdataError(f"{path}: the table's heatdata metadata is damaged ({exc})") from None
    except RecursionError:
        raise HeatdataError(f"{path}: the table's heatdata metadata is damaged (nested too deep)") from None
    return meta


def _filter_columns(filters: list) -> set[str]:
    """The column names of pyarrow's DNF ``filters`` (a list of tuples, or a list of such lists)."""
    groups = filters if filters and isinstance(filters[0], list) else [filters]
    return {name for group in groups for name, _, _ in group}


def concat_tables(paths: list[str | Path], out: str | Path) -> None:
    """Concatenate heatdata tables of one schema into ``out``, one input in memory at a time.

    The output keeps the first table's metadata.

    Parameters
    ----------
    paths : list of str or Path
        Tables of one schema.
    out : str or Path
        The table to write, one row group per input.
    """
    if not paths:
        raise HeatdataError(f"{out}: no tables to concatenate")
    Path(out).parent.mkdir(parents=True, exist_ok=True)
    schema = pq.read_schema(paths[0])
    with pq.ParquetWriter(out, schema) as writer:
        for path in paths:
            table = pq.read_table(path)
            if not table.schema.equals(schema, check_metadata=False):
                raise HeatdataError(f"{path}: its schema differs from {paths[0]}'s")
            writer.write_table(table.replace_schema_metadata(schema.metadata))


ABLATION_COLUMNS = ("factor", "measured", "effect", "command")


def read_ablation(path: str | Path) -> pd.DataFrame:
    """A measured ablation table (one row per factor: ``factor, measured, effect, command``) from a CSV.

    Parameters
    ----------
    path : str or Path
        The CSV (``config/experiments/chairs_ablation.csv``).

    Returns
    -------
    pandas.DataFrame
        Its four columns, as strings.

    Raises
    ------
    HeatdataError
        The file is missing or unreadable, lacks a column, or has no rows.
    """
    try:
        table = pd.read_csv(path, dtype=str, keep_default_na=False)
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise HeatdataError(f"{path}: not a readable ablation table ({exc})") from exc
    missing = [column for column in ABLATION_COLUMNS if column not in table.columns]
    if missing:
        raise HeatdataError(f"{path}: an ablation table needs the columns {list(ABLATION_COLUMNS)}; missing {missing}")
    if table.empty:
        raise HeatdataError(f"{path}: the ablation table has no rows")
    return table[list(ABLATION_COLUMNS)]
