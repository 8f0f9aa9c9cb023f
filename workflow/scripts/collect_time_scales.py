"""Every object's time scales in one table (rule collect_time_scales): what each describe job reads."""

import pandas as pd

from heatdata.log import setup_logging

setup_logging(path=snakemake.log[0])
pd.concat([pd.read_csv(path) for path in snakemake.input], ignore_index=True).to_csv(snakemake.output[0], index=False)
