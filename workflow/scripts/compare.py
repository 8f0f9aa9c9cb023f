"""Isomaps of every descriptor and the holed-box test (rule compare_descriptors, thesis 3.6)."""

from threadpoolctl import threadpool_limits

from heatdata.descriptors import DescriptorSpec
from heatdata.experiments.describe import load_fitted
from heatdata.experiments.holes import hole_sensitivity, hole_summary
from heatdata.io.tables import read_table
from heatdata.log import setup_logging
from heatdata.reporting.figures.holes import plot_holes
from heatdata.reporting.figures.recognition import plot_isomaps

setup_logging(path=snakemake.log[0])
comparison = snakemake.params.comparison
specs = load_fitted([DescriptorSpec.from_dict(d) for d in snakemake.params.descriptors], snakemake.params.fitted)
library, _ = read_table(
    snakemake.input.descriptors,
    columns=["descriptor", "kind", "object", "split", "azimuth", "values"],
    filters=[("split", "==", "train"), ("object", "in", comparison["isomap_objects"])],
)
plot_isomaps(library, [s.name for s in specs], comparison["isomap_objects"], snakemake.output.isomaps)
with threadpool_limits(snakemake.threads):
    table = hole_sensitivity(specs, comparison["boxes"], hole=comparison["hole"], azimuths=comparison["azimuths"])
table.to_csv(snakemake.output.holes, index=False)
plot_holes(hole_summary(table), snakemake.output.holes_figure)
