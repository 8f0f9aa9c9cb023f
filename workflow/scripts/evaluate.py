"""Nearest-neighbour precision for every descriptor and library size (rule evaluate)."""
from heatdata.cli import setup_logging
from heatdata.evaluate import evaluate_run
from heatdata.tables import PREDICTION_SCHEMA, read_table, write_table

setup_logging(path=snakemake.log[0])
descriptors, meta = read_table(snakemake.input[0])
predictions, precision = evaluate_run(descriptors, list(snakemake.params.library_sizes), jobs=snakemake.threads)
write_table(predictions, snakemake.output.predictions, PREDICTION_SCHEMA, meta)
precision.to_csv(snakemake.output.precision, index=False)
