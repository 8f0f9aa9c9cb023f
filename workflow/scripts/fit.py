"""Fit a learned descriptor kind on every object's library views (rule fit_descriptor, e.g. SI-HKS's codebook)."""
from threadpoolctl import threadpool_limits

from heatdata.dataset import fit_view_tables, save_fitted
from heatdata.descriptors import DescriptorSpec
from heatdata.log import setup_logging
from heatdata.tables import read_table

setup_logging(path=snakemake.log[0])
frames = [read_table(path, filters=[("split", "==", "train")])[0] for path in snakemake.input]
spec = DescriptorSpec(snakemake.params.kind, **snakemake.params.descriptor)
with threadpool_limits(snakemake.threads):
    save_fitted(fit_view_tables(frames, spec), snakemake.output[0])
