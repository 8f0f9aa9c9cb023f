"""Test views against every compact library and the initial one (rule evaluate_compact, Alg. 6.1)."""

import pandas as pd
from threadpoolctl import threadpool_limits

from heatdata.io.tables import PREDICTION_SCHEMA, read_table, write_table
from heatdata.log import setup_logging
from heatdata.recognition.evaluate import evaluate_compact
from heatdata.recognition.metrics import precision_table
from heatdata.reporting.figures.recognition import plot_precision

setup_logging(path=snakemake.log[0])
columns = ["object", "label", "view_id", "split", "azimuth", "source_rule", "source", "values"]
tests = pd.concat(
    [
        read_table(path, columns=columns, filters=[("split", "==", "test"), ("source_rule", "==", "candidates")])[0]
        for path in snakemake.input.candidates
    ],
    ignore_index=True,
)
libraries, meta = read_table(snakemake.input.libraries)
with threadpool_limits(snakemake.threads):
    predictions = evaluate_compact(tests, libraries, shortlist=snakemake.params.shortlist)
write_table(predictions, snakemake.output.predictions, PREDICTION_SCHEMA, meta)
precision = precision_table(predictions)
precision.to_csv(snakemake.output.precision, index=False)
plot_precision(precision, snakemake.output.figure)
