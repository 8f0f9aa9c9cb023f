"""Describe one object's views (rule describe); FT-PVHK at the objects' time scales, fitted kinds as fitted."""

import pandas as pd
from threadpoolctl import threadpool_limits

from heatdata.descriptors import DescriptorSpec
from heatdata.experiments.describe import describe_view_table, load_fitted
from heatdata.io.tables import DESCRIPTOR_SCHEMA, read_table, write_table
from heatdata.log import setup_logging

setup_logging(path=snakemake.log[0])
views, meta = read_table(snakemake.input.views)
specs = [DescriptorSpec.from_dict(d) for d in snakemake.params.descriptors]
specs = load_fitted(specs, snakemake.params.fitted)
scales = pd.concat([pd.read_csv(p) for p in snakemake.input.time_scales]) if snakemake.input.time_scales else None
with threadpool_limits(snakemake.threads):
    table = describe_view_table(views, specs, scales)
write_table(table, snakemake.output[0], DESCRIPTOR_SCHEMA, {**meta, "descriptors": snakemake.params.descriptors})
