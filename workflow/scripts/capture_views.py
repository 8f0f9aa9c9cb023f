"""One object's captured depth images as views (rule capture_views)."""

from heatdata.experiments.views import capture_view_table
from heatdata.io.tables import VIEW_SCHEMA, write_table
from heatdata.log import setup_logging

setup_logging(path=snakemake.log[0])
settings = snakemake.params.settings
frame = capture_view_table(
    snakemake.params.captures,
    snakemake.params.label,
    depth_range=settings["depth_range"],
    max_depth_jump=settings["max_depth_jump"],
)
write_table(frame, snakemake.output[0], VIEW_SCHEMA, {"captures": dict(settings)})
