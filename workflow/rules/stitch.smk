# JASNOM (thesis ch. 7, config key stitch): each listed pair of meshes aligned by its boundaries and stitched into
# one model, which the models stage then renders like any other (model_input in common.smk).


rule stitch:
    input:
        first=lambda wildcards: STITCHED[wildcards.object]["first"],
        second=lambda wildcards: STITCHED[wildcards.object]["second"],
    output:
        model=f"{RESULTS}/stitched/{{object}}.ply",
        summary=f"{RESULTS}/stitched/{{object}}.json",
        figure=report(f"{RESULTS}/figures/stitch/{{object}}.png", caption="../report/stitch.rst",
                      category="JASNOM stitching", subcategory="{object}"),
    params:
        pair=lambda wildcards: STITCHED[wildcards.object],
        settings={k: v for k, v in config["stitch"].items() if k != "pairs"},
        version=VERSION,
    log:
        f"{RESULTS}/logs/stitch/{{object}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/stitch/{{object}}.tsv"
    threads: 2
    resources:
        mem_mb=lambda wildcards, attempt: 2000 * attempt,
        runtime=lambda wildcards, attempt: 30 * attempt,
    script:
        "../scripts/stitch.py"
