"""The report's landing summary (rule front_page)."""

from pathlib import Path

import pandas as pd

from heatdata.log import setup_logging
from heatdata.reporting.pages import front_page, precision_by_size

setup_logging(path=snakemake.log[0])
table = precision_by_size(pd.read_csv(snakemake.input.precision), snakemake.params.order)
overlays = {Path(p).stem: Path(p).read_bytes() for p in snakemake.input.overlays}
Path(snakemake.output[0]).write_text(front_page(table, snakemake.params.primary, overlays))
