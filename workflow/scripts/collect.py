"""One descriptor table for the run (rule collect_descriptors), streamed object by object."""

from heatdata.io.tables import concat_tables
from heatdata.log import setup_logging

setup_logging(path=snakemake.log[0])
concat_tables(snakemake.input, snakemake.output[0])
