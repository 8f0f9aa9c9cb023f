"""Candidate-source descriptors of one object's views (rule candidates, thesis 6.2)."""

from threadpoolctl import threadpool_limits

from heatdata.descriptors import DescriptorSpec
from heatdata.experiments.describe import candidate_view_table
from heatdata.io.tables import DESCRIPTOR_SCHEMA, read_table, write_table
from heatdata.log import setup_logging

setup_logging(path=snakemake.log[0])
compact = snakemake.params.compact
views, meta = read_table(snakemake.input[0])
with threadpool_limits(snakemake.threads):
    table = candidate_view_table(
        views,
        DescriptorSpec.from_dict(compact["descriptor"]),
        library_count=compact["library_candidates"],
        test_count=compact["test_candidates"],
    )
write_table(table, snakemake.output[0], DESCRIPTOR_SCHEMA, {**meta, "compact": compact})
