"""Write the catalogue this run uses, model files as absolute paths (rule catalog)."""

import io
from pathlib import Path

import pandas as pd

from heatdata.log import setup_logging

setup_logging(path=snakemake.log[0])
table = pd.read_json(io.StringIO(snakemake.params.rows), orient="records", dtype=False)
table["file"] = [str(Path(p).resolve()) for p in table.pop("path")]
table.to_csv(snakemake.output[0], index=False)
