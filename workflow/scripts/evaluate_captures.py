"""The captures recognized against the run's library views, every descriptor and library size (rule
evaluate_captures)."""

import pandas as pd

from heatdata.io.tables import PREDICTION_SCHEMA, read_table, write_table
from heatdata.log import setup_logging
from heatdata.recognition.evaluate import evaluate_library_sizes
from heatdata.recognition.metrics import precision_table
from heatdata.reporting.pages import captures_page

setup_logging(path=snakemake.log[0])
library, meta = read_table(snakemake.input.library, filters=[("split", "==", "train")])
captures = pd.concat([read_table(path)[0] for path in snakemake.input.captures], ignore_index=True)
rows = pd.concat([library, captures], ignore_index=True)
predictions = pd.concat(
    [
        evaluate_library_sizes(rows, name, snakemake.params.sizes, time_rule=snakemake.params.time_rule)
        for name in rows["descriptor"].unique()
    ],
    ignore_index=True,
)
write_table(predictions, snakemake.output.predictions, PREDICTION_SCHEMA, meta)
precision_table(predictions).to_csv(snakemake.output.precision, index=False)
with open(snakemake.output.page, "w") as out:
    out.write(captures_page(predictions, snakemake.params.primary))
