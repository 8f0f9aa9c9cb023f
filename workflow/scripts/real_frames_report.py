"""The real frames' scores per folder and category, and the report page with each folder's worst frames (rule
real_frames_report)."""

from pathlib import Path

import pandas as pd

from heatdata.experiments.real_frames import by_category
from heatdata.log import setup_logging
from heatdata.reporting.pages import real_frames_page

setup_logging(path=snakemake.log[0])
tables = []
for folder, path in zip(snakemake.params.folders, snakemake.input.scores, strict=True):
    tables.append(by_category(pd.read_csv(path)).assign(folder=folder))
summary = pd.concat(tables, ignore_index=True)
summary = summary[["folder", *[c for c in summary.columns if c != "folder"]]]
summary.to_csv(snakemake.output.summary, index=False)
pictures = {folder: Path(p).read_bytes() for folder, p in zip(snakemake.params.folders, snakemake.input.worst)}
Path(snakemake.output.page).write_text(real_frames_page(summary, pictures, snakemake.params.settings))
