"""The measured ablation table named by config key ablation, as a page of the report (rule ablation)."""

from heatdata.io.tables import read_ablation
from heatdata.log import setup_logging
from heatdata.reporting.pages import ablation_page

setup_logging(path=snakemake.log[0])
with open(snakemake.output[0], "w") as out:
    out.write(ablation_page(read_ablation(snakemake.input[0]), snakemake.input[0]))
