# heatdata's workflow lives in workflow/ (Snakemake workflow catalog layout); this file lets `snakemake` run from the
# repository root and puts the default and Slurm profiles where Snakemake looks for them (profiles/).
include: "workflow/Snakefile"


# default_target in an included file is ignored (snakemake issue #2773): the root's default is rule all's inputs
rule default:
    default_target: True
    input:
        rules.all.input,
