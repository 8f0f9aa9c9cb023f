"""One object's time scale for each FT-PVHK descriptor, from its library views (rule time_scale, Alg. 5.1)."""

from threadpoolctl import threadpool_limits

from heatdata.descriptors import DescriptorSpec
from heatdata.experiments.describe import view_table_time_scales
from heatdata.io.tables import read_table
from heatdata.log import setup_logging

setup_logging(path=snakemake.log[0])
views, _ = read_table(snakemake.input[0])
specs = [DescriptorSpec.from_dict(d) for d in snakemake.params.descriptors]
with threadpool_limits(snakemake.threads):
    view_table_time_scales(views, specs).to_csv(snakemake.output[0], index=False)
