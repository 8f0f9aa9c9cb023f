"""Fit a learned descriptor kind on every object's library views (rule fit_descriptor, e.g. SI-HKS's codebook)."""

from threadpoolctl import threadpool_limits

from heatdata.descriptors import DescriptorSpec
from heatdata.experiments.describe import capped_steps, fit_view_tables, save_fitted
from heatdata.io.tables import read_table
from heatdata.log import setup_logging

setup_logging(path=snakemake.log[0])
frames = [read_table(path, filters=[("split", "==", "train")])[0] for path in snakemake.input]
spec = capped_steps(DescriptorSpec(snakemake.params.kind, **snakemake.params.descriptor), snakemake.params.steps_limit)
with threadpool_limits(snakemake.threads):
    save_fitted(fit_view_tables(frames, spec), snakemake.output[0])
