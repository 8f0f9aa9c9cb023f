"""Render one object's views (rule render)."""

import json

from threadpoolctl import threadpool_limits

from heatdata.experiments.views import render_object_views
from heatdata.io.tables import VIEW_SCHEMA, write_table
from heatdata.log import setup_logging

setup_logging(path=snakemake.log[0])
with threadpool_limits(snakemake.threads):
    frame = render_object_views(json.loads(snakemake.params.row), dict(snakemake.params.views))
write_table(frame, snakemake.output[0], VIEW_SCHEMA, {"views": dict(snakemake.params.views)})
