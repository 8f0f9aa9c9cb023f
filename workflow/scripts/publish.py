"""A docs_* target: run its steps, write its tables and figures into docs/, record them in the manifest."""

from heatdata.experiments.publish import publish
from heatdata.log import setup_logging

setup_logging(path=snakemake.log[0])
publish(
    snakemake.params.steps,
    list(snakemake.output),
    snakemake.rule,
    snakemake.params.configs,
    snakemake.log[0],
    snakemake.params.manifest,
)
