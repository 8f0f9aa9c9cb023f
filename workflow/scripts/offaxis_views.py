"""One object's test views rendered again off the optical axis (rule offaxis_views)."""

import json

from threadpoolctl import threadpool_limits

from heatdata.experiments.views import render_offaxis_views
from heatdata.io.tables import VIEW_SCHEMA, write_table
from heatdata.log import setup_logging

setup_logging(path=snakemake.log[0])
with threadpool_limits(snakemake.threads):
    frame = render_offaxis_views(
        json.loads(snakemake.params.row), dict(snakemake.params.views), snakemake.params.views_per_object
    )
write_table(frame, snakemake.output[0], VIEW_SCHEMA, {"views": dict(snakemake.params.views), "offaxis": True})
