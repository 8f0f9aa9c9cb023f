"""Reading a library-sized matrix column: ``heatdata.io.tables.read_matrix_table`` (its row groups cut into a few
contiguous spans, each decoded by a reader of its own sharing the parsed footer) against pyarrow's own whole-table
read flattened into one array, on two layouts of the same size.

    .venv/bin/python benchmarks/bench_tables.py [--rows 400320] [--width 96]

The tables are synthetic: ``--rows`` rows of ``--width`` float64 values, every tenth a similarity row (split
``similarity``) among the library views (``train``), which the reader puts first (``first=("split", "train")``, as
``load_library`` does):

- ``workflow``: written by heatdata (``write_table``), row groups of 16,384 rows, the library views first;
- ``another tool``: written by pyarrow's ``ParquetWriter`` a table of 360 rows at a time (1,112 row groups at the
  default size), the similarity rows between the views.

Each way reads each table 5 times in a fresh process of its own, which reports the median time and its peak resident
memory (the process's imports included). The targets: the other tool's file in at most 2 s and 1.5 GB, the
workflow's in at most 1.5 s; the script exits 1 when one is missed.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
from record import write

from heatdata.io.tables import read_matrix_table, write_table

SCHEMA = pa.schema([("name", pa.string()), ("split", pa.string()), ("values", pa.list_(pa.float64()))])
#: (target seconds, target peak MB) of read_matrix_table per layout
TARGETS = {"workflow": (1.5, None), "another tool": (2.0, 1500.0)}


def pyarrow_read(path: str) -> np.ndarray:
    """The whole table read and flattened, then the library views taken (a copy where they are not one block)."""
    table = pq.read_table(path)
    values = table.column("values").combine_chunks().flatten().to_numpy().reshape(table.num_rows, -1)
    train = table.column("split").to_numpy(zero_copy_only=False) == "train"
    return values if train.all() else values[train]


def library_read(path: str) -> np.ndarray:
    """As ``load_library`` reads a library: the library views first, then taken as a slice (no copy)."""
    frame, values, _ = read_matrix_table(path, "values", schema=SCHEMA, first=("split", "train"))
    return values[: int(frame["split"].eq("train").sum())]


WAYS = {
    "read_matrix_table": library_read,
    "pyarrow read_table + flatten": pyarrow_read,
}


def write_layouts(folder: Path, rows: int, width: int) -> dict[str, Path]:
    """The two files of :data:`TARGETS`: the same rows as the workflow writes them, and as another tool does."""
    values = np.random.default_rng(0).random((rows, width))
    split = np.where(np.arange(rows) % 10 == 9, "similarity", "train")
    frame = pd.DataFrame({"name": [f"v{k}" for k in range(rows)], "split": split, "values": list(values)})
    paths = {"workflow": folder / "workflow.parquet", "another tool": folder / "other.parquet"}
    ordered = frame.iloc[np.argsort(split != "train", kind="stable")]
    write_table(ordered, paths["workflow"], SCHEMA, row_group_size=16_384)
    with pq.ParquetWriter(paths["another tool"], SCHEMA) as writer:
        for start in range(0, rows, 360):
            writer.write_table(pa.Table.from_pandas(frame.iloc[start : start + 360], SCHEMA, preserve_index=False))
    return paths


def child(way: str, path: str) -> None:
    times = []
    for _ in range(5):
        start = time.perf_counter()
        values = WAYS[way](path)
        times.append(time.perf_counter() - start)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps({"seconds": float(np.median(times)), "peak_mb": peak, "shape": list(values.shape)}))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=400_320)
    parser.add_argument("--width", type=int, default=96)
    parser.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(*args.child)
        return
    missed = []
    with tempfile.TemporaryDirectory() as folder:
        paths = write_layouts(Path(folder), args.rows, args.width)
        views = args.rows - args.rows // 10
        figures = []
        for layout, path in paths.items():
            groups = pq.ParquetFile(path).num_row_groups
            for way in WAYS:
                command = [sys.executable, __file__, "--child", way, str(path)]
                done = json.loads(subprocess.run(command, capture_output=True, text=True, check=True).stdout)
                assert done["shape"] == [views, args.width]
                name = f"{args.rows:,} x {args.width}, {layout} ({groups:,} row groups): {way}"
                print(f"{name}: {done['seconds'] * 1000:.0f} ms, peak {done['peak_mb']:.0f} MB")
                figures += [
                    (f"{name}, median of 5", done["seconds"] * 1000, "ms"),
                    (f"{name}, peak memory", done["peak_mb"], "MB"),
                ]
                seconds, peak = TARGETS[layout]
                if way == "read_matrix_table" and (
                    done["seconds"] > seconds or (peak is not None and done["peak_mb"] > peak)
                ):
                    missed.append(f"{layout}: {done['seconds']:.2f} s, {done['peak_mb']:.0f} MB")
    write(figures)
    if missed:
        sys.exit(f"target missed: {'; '.join(missed)}")


if __name__ == "__main__":
    main()
