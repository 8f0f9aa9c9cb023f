# Multi-view recognition (thesis ch. 4, config key multiview): Algorithm 4.1 over the run's views, from each
# object's most ambiguous test views, with the similarity bootstrap, the angular baseline and the active policy.


rule multiview:
    input:
        f"{RESULTS}/descriptors.parquet",
    output:
        trials=f"{RESULTS}/multiview/trials.parquet",
        similarity=f"{RESULTS}/multiview/similarity.parquet",
        summary=f"{RESULTS}/multiview/summary.csv",
        table=report(f"{RESULTS}/figures/multiview.html", caption="../report/multiview_table.rst",
                     category="Multi-view recognition"),
        figure=report(f"{RESULTS}/figures/multiview.png", caption="../report/multiview.rst",
                      category="Multi-view recognition"),
    params:
        settings=config["multiview"],
        descriptor=MULTIVIEW_DESCRIPTOR,
        version=VERSION,
    log:
        f"{RESULTS}/logs/multiview.log",
    benchmark:
        f"{RESULTS}/benchmarks/multiview.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 3000 * attempt,
        runtime=lambda wildcards, attempt: 120 * attempt,
    script:
        "../scripts/multiview.py"
