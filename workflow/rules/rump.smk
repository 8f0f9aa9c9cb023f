# Body condition (thesis ch. 8, config key rump): HBRD on a proxy population of MakeHuman bodies across the
# weight range, ordered and classified (no goat scans reach this machine: bodies, not goats).


rule rump:
    output:
        descriptors=f"{RESULTS}/rump/descriptors.csv",
        figure=report(f"{RESULTS}/figures/rump.png", caption="../report/rump.rst", category="Body condition (ch. 8)"),
        page=report(f"{RESULTS}/figures/rump.html", caption="../report/rump_table.rst",
                    category="Body condition (ch. 8)"),
    params:
        settings=config["rump"],
        version=VERSION,
    log:
        f"{RESULTS}/logs/rump.log",
    benchmark:
        f"{RESULTS}/benchmarks/rump.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 3000 * attempt,
        runtime=lambda wildcards, attempt: 60 * attempt,
    script:
        "../scripts/rump.py"
