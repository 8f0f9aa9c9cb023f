# Libraries and evaluation: nearest-neighbour precision per library size, figures for the report.


rule evaluate:
    input:
        f"{RESULTS}/descriptors.parquet",
    output:
        predictions=f"{RESULTS}/evaluation/predictions.parquet",
        precision=report(f"{RESULTS}/evaluation/precision.csv", caption="../report/precision_table.rst",
                         category="Precision"),
    params:
        library_sizes=config["library_sizes"],
        version=VERSION,
    log:
        f"{RESULTS}/logs/evaluate.log",
    benchmark:
        f"{RESULTS}/benchmarks/evaluate.tsv"
    threads: 2
    resources:
        mem_mb=lambda wildcards, attempt: 3000 * attempt,
        runtime=lambda wildcards, attempt: 30 * attempt,
    script:
        "../scripts/evaluate.py"


rule report_figures:
    input:
        descriptors=f"{RESULTS}/descriptors.parquet",
        predictions=f"{RESULTS}/evaluation/predictions.parquet",
        precision=f"{RESULTS}/evaluation/precision.csv",
        catalog=f"{RESULTS}/catalog.csv",
    output:
        precision=report(f"{RESULTS}/figures/precision.png", caption="../report/precision.rst",
                         category="Precision"),
        confusion=report(directory(f"{RESULTS}/figures/confusion"), patterns=["{name}.png"],
                         caption="../report/confusion.rst", category="Confusion matrices"),
        isomap=report(f"{RESULTS}/figures/isomap.png", caption="../report/isomap.rst", category="Descriptors"),
        views=report(f"{RESULTS}/figures/views.png", caption="../report/views.rst", category="Descriptors"),
        summary=report(f"{RESULTS}/summary.md", caption="../report/summary.rst", category="Run"),
    params:
        primary=config["primary_descriptor"],
        config=config,
        version=VERSION,
    log:
        f"{RESULTS}/logs/report_figures.log",
    benchmark:
        f"{RESULTS}/benchmarks/report_figures.tsv"
    resources:
        mem_mb=lambda wildcards, attempt: 3000 * attempt,
        runtime=20,
    script:
        "../scripts/report_figures.py"
