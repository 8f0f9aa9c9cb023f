"""The measured ablation table named by config key ablation, as a page of the report (rule ablation)."""
from heatdata.log import setup_logging
from heatdata.report import ablation_page, read_ablation

setup_logging(path=snakemake.log[0])
with open(snakemake.output[0], "w") as out:
    out.write(ablation_page(read_ablation(snakemake.input[0]), snakemake.input[0]))
