"""All predictions of the run and their precision table (rule evaluate)."""

import pandas as pd

from heatdata.io.tables import PREDICTION_SCHEMA, read_table, write_table
from heatdata.log import setup_logging
from heatdata.recognition.metrics import precision_table

setup_logging(path=snakemake.log[0])
parts = [read_table(path) for path in snakemake.input]
predictions = pd.concat([frame for frame, _ in parts], ignore_index=True)
write_table(predictions, snakemake.output.predictions, PREDICTION_SCHEMA, parts[0][1])
precision_table(predictions).to_csv(snakemake.output.precision, index=False)
