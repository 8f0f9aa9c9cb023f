# The docs_* targets: every table in docs/results and figure in docs/images is written by one of them,
# from the run of its config files, and recorded in docs/results/MANIFEST.csv (file, target, config, commit, wall
# time, machine). Run one as
#     snakemake --cores 2 --configfile config/experiments/chairs.yaml docs_chairs
# The real runs take minutes to hours and stay manual; tests/experiments/test_docs_targets.py dry-runs every one.
# A target that compares two runs (320x240 against 640x480, seeds) reads the other run's results too: run that
# config first. Steps are heatdata.experiments.publish's: an analysis script of scripts/, a table cut from a run's
# precision, a figure copied from a run, tables of several runs labelled; the targets are the table
# workflow/docs_targets.yaml (read and checked by heatdata.experiments.docs_targets), which the tests read too.
from heatdata.experiments import docs_targets, publish


DOCS_TARGETS = docs_targets.targets(OBJECTS, RESULTS)


def docs_run(target, results, configs, paths):
    """The inputs of a docs target, once this run is the one the target publishes (an error naming its configs)."""

    def inputs(wildcards):
        if results is not None and RESULTS != results:
            raise WorkflowError(
                f"{target} publishes the run in {results}; give its config files: --configfile {' '.join(configs)}"
            )
        return paths

    return inputs


for docs_target, (docs_results, docs_configs, docs_inputs, docs_outputs, docs_steps) in DOCS_TARGETS.items():

    rule:
        name: docs_target
        input:
            docs_run(docs_target, docs_results, docs_configs, docs_inputs),
        output:
            docs_outputs,
        params:
            steps=docs_steps,
            configs=docs_configs,
            manifest=publish.MANIFEST,
        log:
            f"{RESULTS}/logs/{docs_target}.log",
        benchmark:
            f"{RESULTS}/benchmarks/{docs_target}.tsv"
        threads: 2
        resources:
            mem_mb=lambda wildcards, attempt: 8000 * attempt,
            runtime=lambda wildcards, attempt: 240 * attempt,
        script:
            "../scripts/publish.py"
