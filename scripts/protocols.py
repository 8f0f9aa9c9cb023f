"""Object precision of a run's descriptors under both test protocols (issue 17; thesis 5.5).

``separate`` (the workflow's, the headline): the library views are rendered apart from the test views, at
other angles (the test views sit 1.5 deg off the library's grid) and with fresh noise. ``thesis``: as 5.5
words it, the library views are chosen among the test views and every test view is queried, so each library
view finds itself. It reads a workflow run's descriptor table (nothing is rendered or described again) and
writes one row per descriptor, library size and protocol.

    .venv/bin/python scripts/protocols.py results/chairs/descriptors.parquet --out docs/results/chairs_protocols.csv
"""

import argparse
import time

import pandas as pd
import pyarrow.parquet as pq

from heatdata.experiments.publish import print_precision
from heatdata.log import setup_logging
from heatdata.recognition.evaluate import evaluate_table

PROTOCOLS = {"separate": "train", "thesis": "test"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("descriptors", help="descriptors.parquet of a workflow run")
    parser.add_argument("--descriptor", nargs="+", help="descriptor names (default: every one in the table)")
    parser.add_argument("--sizes", type=int, nargs="+", default=[40, 12, 8, 5])
    parser.add_argument("--out", help="CSV to write")
    args = parser.parse_args()
    setup_logging()
    names = args.descriptor or sorted(
        pq.read_table(args.descriptors, columns=["descriptor"]).column("descriptor").unique().to_pylist()
    )
    rows = []
    for name in names:
        for protocol, split in PROTOCOLS.items():
            start = time.perf_counter()
            predictions = evaluate_table(args.descriptors, name, args.sizes, library_split=split)
            for size, group in predictions.groupby("library_size"):
                rows.append(
                    {
                        "descriptor": name,
                        "library_size": size,
                        "protocol": protocol,
                        "test_views": len(group),
                        "precision": round(float(group["correct"].mean()), 4),
                    }
                )
            print(f"{name} {protocol}: {time.perf_counter() - start:.0f} s", flush=True)
    table = pd.DataFrame(rows)
    print_precision(table, ["descriptor", "protocol"], args.out)


if __name__ == "__main__":
    main()
