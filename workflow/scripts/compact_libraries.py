"""Sources of the library views for each alpha and library size (rule compact_libraries, Alg. 6.3)."""

import pandas as pd
from threadpoolctl import threadpool_limits

from heatdata.experiments.compact import compact_libraries
from heatdata.io.tables import COMPACT_LIBRARY_SCHEMA, read_table, write_table
from heatdata.log import setup_logging

setup_logging(path=snakemake.log[0])
compact = snakemake.params.compact
columns = ["object", "label", "view_id", "split", "azimuth", "source_rule", "source", "values"]
parts = [read_table(path, columns=columns, filters=[("split", "==", "train")]) for path in snakemake.input]
candidates = pd.concat([frame for frame, _ in parts], ignore_index=True)
with threadpool_limits(snakemake.threads):
    libraries = compact_libraries(
        candidates,
        snakemake.params.sizes,
        compact["alphas"],
        solver=compact["solver"],
        distance=compact["distance"],
        norm=compact["norm"],
    )
write_table(libraries, snakemake.output[0], COMPACT_LIBRARY_SCHEMA, {**parts[0][1], "compact": compact})
