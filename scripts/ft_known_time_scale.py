"""FT-PVHK precision when every test view is described at its true object's time scale.

Alg. 5.2 takes each view's own object's time scale as given; for a test view that is its
label, so this is an upper reference, not a recognizer. It reads a workflow run's
descriptor table (test views are described at every object's time scale, so the rows
at their own object's are there), and prints the precision per library size with and
without the part weights of eq. 5.14.

    .venv/bin/python scripts/ft_known_time_scale.py results/chairs/descriptors.parquet ft-pvhk/polar/center/64
"""

import argparse

import numpy as np

from heatdata.io.tables import read_table
from heatdata.recognition.evaluate import library_subset
from heatdata.recognition.nearest import nearest_neighbors


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("descriptors", help="descriptors.parquet of a workflow run")
    parser.add_argument("descriptor", help="an ft-pvhk descriptor name")
    parser.add_argument("--sizes", type=int, nargs="+", default=[5, 8, 12, 40])
    args = parser.parse_args()
    rows, _ = read_table(
        args.descriptors,
        filters=[("descriptor", "==", args.descriptor)],
        columns=["object", "split", "view_id", "azimuth", "time_object", "values", "weights"],
    )
    tests = rows[(rows["split"] == "test") & (rows["time_object"] == rows["object"])]
    queries, query_weights = np.stack(tests["values"].to_numpy()), np.stack(tests["weights"].to_numpy())
    print(f"{args.descriptor}: {len(tests)} test views at their own object's time scale")
    for size in args.sizes:
        library = library_subset(rows, size)
        values, weights = np.stack(library["values"].to_numpy()), np.stack(library["weights"].to_numpy())
        for name, kwargs in (
            ("weighted", {"query_weights": query_weights, "library_weights": weights}),
            ("unweighted", {}),
        ):
            nn = nearest_neighbors(queries, values, **kwargs)
            precision = np.mean(library["object"].to_numpy()[nn.index] == tests["object"].to_numpy())
            print(f"  {size:3d} library views, {name:10s}: {precision:.1%}")


if __name__ == "__main__":
    main()
