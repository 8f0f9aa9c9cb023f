"""Nearest-neighbour predictions of one descriptor at every library size of the run (rule classify)."""

from heatdata.io.tables import PREDICTION_SCHEMA, read_metadata, write_table
from heatdata.log import setup_logging
from heatdata.recognition.evaluate import evaluate_table

setup_logging(path=snakemake.log[0])
predictions = evaluate_table(
    snakemake.input[0],
    snakemake.params.descriptor,
    [int(size) for size in snakemake.params.sizes],
    time_rule=snakemake.params.time_rule,
)
write_table(predictions, snakemake.output[0], PREDICTION_SCHEMA, read_metadata(snakemake.input[0]))
