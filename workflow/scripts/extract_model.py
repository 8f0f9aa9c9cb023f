"""Extract one Sweet Home 3D model folder (rule extract_model)."""

from heatdata.io.sh3f import extract_sh3f_model
from heatdata.log import setup_logging

setup_logging(path=snakemake.log[0])
extract_sh3f_model(snakemake.input[0], snakemake.params.model, snakemake.output[0])
