"""Reading a library-sized matrix column: ``heatdata.io.tables.read_matrix_table`` (row groups decoded side by
side, each through a reader of its own) against pyarrow's own whole-table read flattened into one array.

    .venv/bin/python benchmarks/bench_tables.py [--rows 400560] [--width 96]

The table is synthetic: ``--rows`` rows of ``--width`` float64 values in row groups of 16,384 rows, as a library file
holds them. Each way reads it 5 times in a fresh process of its own, which reports the median time and its peak
resident memory (the process's imports included).
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

SCHEMA = pa.schema([("name", pa.string()), ("values", pa.list_(pa.float64()))])


def pyarrow_read(path: str) -> np.ndarray:
    table = pq.read_table(path)
    return table.column("values").combine_chunks().flatten().to_numpy().reshape(table.num_rows, -1)


WAYS = {
    "read_matrix_table": lambda path: read_matrix_table(path, "values", schema=SCHEMA)[1],
    "pyarrow read_table + flatten": pyarrow_read,
}


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
    parser.add_argument("--rows", type=int, default=400_560)
    parser.add_argument("--width", type=int, default=96)
    parser.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(*args.child)
        return
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "library.parquet"
        values = np.random.default_rng(0).random((args.rows, args.width))
        frame = pd.DataFrame({"name": [f"v{k}" for k in range(args.rows)], "values": list(values)})
        write_table(frame, path, SCHEMA, row_group_size=16_384)
        del frame
        figures = []
        for way in WAYS:
            command = [sys.executable, __file__, "--child", way, str(path)]
            done = json.loads(subprocess.run(command, capture_output=True, text=True, check=True).stdout)
            assert done["shape"] == [args.rows, args.width]
            print(f"{way}: {done['seconds'] * 1000:.0f} ms, peak {done['peak_mb']:.0f} MB")
            figures += [
                (f"{args.rows:,} x {args.width}: {way}, median of 5", done["seconds"] * 1000, "ms"),
                (f"{args.rows:,} x {args.width}: {way}, peak memory", done["peak_mb"], "MB"),
            ]
    write(figures)


if __name__ == "__main__":
    main()
