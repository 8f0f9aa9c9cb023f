"""One descriptor table for the run (rule collect_descriptors)."""
import pandas as pd

from heatdata.cli import setup_logging
from heatdata.tables import DESCRIPTOR_SCHEMA, read_table, write_table

setup_logging(path=snakemake.log[0])
tables = [read_table(path) for path in snakemake.input]
write_table(pd.concat([t for t, _ in tables], ignore_index=True), snakemake.output[0], DESCRIPTOR_SCHEMA,
            tables[0][1])
