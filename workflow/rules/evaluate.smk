# Libraries and evaluation: nearest-neighbour predictions, one job per descriptor x library size,
# precision tables and the report's figures.


rule classify:
    input:
        f"{RESULTS}/descriptors.parquet",
    output:
        temp(f"{RESULTS}/evaluation/parts/{{descriptor}}-{{size}}.parquet"),
    params:
        descriptor=lambda wildcards: SPEC_FILES[wildcards.descriptor].name,
        version=VERSION,
    wildcard_constraints:
        descriptor="|".join(map(re.escape, SPEC_FILES)),
        size=r"\d+",
    log:
        f"{RESULTS}/logs/classify/{{descriptor}}-{{size}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/classify/{{descriptor}}-{{size}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 4000 * attempt,
        runtime=lambda wildcards, attempt: 20 * attempt,
    script:
        "../scripts/classify.py"


rule evaluate:
    input:
        expand(f"{RESULTS}/evaluation/parts/{{descriptor}}-{{size}}.parquet",
               descriptor=SPEC_FILES, size=config["library_sizes"]),
    output:
        predictions=f"{RESULTS}/evaluation/predictions.parquet",
        precision=report(f"{RESULTS}/evaluation/precision.csv", caption="../report/precision_table.rst",
                         category="Precision"),
    params:
        version=VERSION,
    log:
        f"{RESULTS}/logs/evaluate.log",
    benchmark:
        f"{RESULTS}/benchmarks/evaluate.tsv"
    resources:
        mem_mb=lambda wildcards, attempt: 1000 * attempt,
        runtime=10,
    script:
        "../scripts/evaluate.py"


rule report_figures:
    input:
        descriptors=f"{RESULTS}/descriptors.parquet",
        predictions=f"{RESULTS}/evaluation/predictions.parquet",
        precision=f"{RESULTS}/evaluation/precision.csv",
        catalog=f"{RESULTS}/catalog.csv",
        models=[model_input(obj) for obj in OBJECTS[:8]],  # the objects drawn in views.png
    output:
        precision=report(f"{RESULTS}/figures/precision.png", caption="../report/precision.rst",
                         category="Precision"),
        confusion=report(directory(f"{RESULTS}/figures/confusion"), patterns=["{name}.png"],
                         caption="../report/confusion.rst", category="Confusion matrices"),
        isomap=report(f"{RESULTS}/figures/isomap.png", caption="../report/isomap.rst", category="Descriptors"),
        views=report(f"{RESULTS}/figures/views.png", caption="../report/views.rst", category="Descriptors"),
        global_derivative=report(f"{RESULTS}/figures/global_derivative.png",
                                 caption="../report/global_derivative.rst", category="Descriptors"),
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
