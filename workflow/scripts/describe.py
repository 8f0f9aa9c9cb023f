"""Describe one object's views (rule describe); FT-PVHK at the objects' time scales."""
import pandas as pd
from threadpoolctl import threadpool_limits

from heatdata.log import setup_logging
from heatdata.dataset import describe_view_table
from heatdata.descriptors import DescriptorSpec
from heatdata.tables import DESCRIPTOR_SCHEMA, read_table, write_table

setup_logging(path=snakemake.log[0])
views, meta = read_table(snakemake.input.views)
specs = [DescriptorSpec(**d) for d in snakemake.params.descriptors]
scales = pd.concat([pd.read_csv(p) for p in snakemake.input.time_scales]) if snakemake.input.time_scales else None
with threadpool_limits(snakemake.threads):
    table = describe_view_table(views, specs, scales)
write_table(table, snakemake.output[0], DESCRIPTOR_SCHEMA, {**meta, "descriptors": snakemake.params.descriptors})
