"""Render one scene of the run's objects on a table, with its truth (rule scene)."""

import json

from heatdata.experiments.scenes import render_scene_files
from heatdata.log import setup_logging

setup_logging(path=snakemake.log[0])
rows = [json.loads(row) for row in snakemake.params.rows]
render_scene_files(rows, dict(snakemake.params.settings), snakemake.params.index, snakemake.output.depth)
