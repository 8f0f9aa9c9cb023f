"""Algorithm 4.1's trials on the run's views (rule multiview, thesis 4.5)."""

from pathlib import Path

from threadpoolctl import threadpool_limits

from heatdata.experiments.multiview import multiview_experiment, trial_summary
from heatdata.io.tables import SIMILARITY_SCHEMA, TRIAL_SCHEMA, read_table, write_table
from heatdata.log import setup_logging
from heatdata.reporting.figures.multiview import plot_multiview
from heatdata.reporting.pages import trials_page

setup_logging(path=snakemake.log[0])
name = snakemake.params.descriptor
descriptors, meta = read_table(
    snakemake.input[0],
    columns=["descriptor", "kind", "object", "split", "azimuth", "values"],
    filters=[("descriptor", "==", name)],
)
with threadpool_limits(snakemake.threads):
    trials, similarity = multiview_experiment(descriptors, name, dict(snakemake.params.settings))
settings = {**meta, "multiview": dict(snakemake.params.settings), "descriptor": name}
write_table(trials, snakemake.output.trials, TRIAL_SCHEMA, settings)
write_table(similarity, snakemake.output.similarity, SIMILARITY_SCHEMA, settings)
summary = trial_summary(trials)
summary.to_csv(snakemake.output.summary, index=False)
Path(snakemake.output.table).write_text(trials_page(summary, name, len(trials)))
plot_multiview(
    summary,
    snakemake.output.figure,
    f"Algorithm 4.1 with {name}: runs from each object's most ambiguous test views ({len(trials)} runs)",
)
