"""Figures and summary of the report (rule report_figures)."""

from heatdata.log import setup_logging
from heatdata.reporting.pages import draw_report

setup_logging(path=snakemake.log[0])
draw_report(
    snakemake.input.descriptors,
    snakemake.input.predictions,
    snakemake.input.precision,
    snakemake.input.catalog,
    snakemake.input.views,
    snakemake.output,
    primary=snakemake.params.primary,
    config=snakemake.params.config,
    libraries=snakemake.params.libraries,
    scenes_path=snakemake.input.scenes[0] if snakemake.input.scenes else None,
    scene_frame=snakemake.params.scene_frame,
)
