# Compact libraries (thesis ch. 6, config key compact): candidate-source descriptors per object, the
# sources of the library views chosen by the LP of Alg. 6.3 for each alpha and library size, and the
# test views classified by Alg. 6.1 against each library and the initial (single-source) one.


rule candidates:
    input:
        f"{RESULTS}/views/{{object}}.parquet",
    output:
        f"{RESULTS}/compact/candidates/{{object}}.parquet",
    params:
        compact={key: config["compact"][key] for key in ("descriptor", "library_candidates", "test_candidates")},
        version=VERSION,
    log:
        f"{RESULTS}/logs/candidates/{{object}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/candidates/{{object}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 3000 * attempt,
        runtime=lambda wildcards, attempt: 60 * attempt,
    script:
        "../scripts/candidates.py"


rule compact_libraries:
    input:
        expand(f"{RESULTS}/compact/candidates/{{object}}.parquet", object=OBJECTS),
    output:
        f"{RESULTS}/compact/libraries.parquet",
    params:
        compact=config["compact"],
        sizes=config["library_sizes"],
        version=VERSION,
    log:
        f"{RESULTS}/logs/compact_libraries.log",
    benchmark:
        f"{RESULTS}/benchmarks/compact_libraries.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 4000 * attempt,
        runtime=lambda wildcards, attempt: 120 * attempt,
    script:
        "../scripts/compact_libraries.py"


rule evaluate_compact:
    input:
        candidates=expand(f"{RESULTS}/compact/candidates/{{object}}.parquet", object=OBJECTS),
        libraries=f"{RESULTS}/compact/libraries.parquet",
    output:
        predictions=f"{RESULTS}/compact/predictions.parquet",
        precision=report(f"{RESULTS}/compact/precision.csv", caption="../report/compact_precision_table.rst",
                         category="Compact libraries"),
        figure=report(f"{RESULTS}/figures/compact_precision.png", caption="../report/compact_precision.rst",
                      category="Compact libraries"),
    params:
        shortlist=config["compact"]["shortlist"],
        version=VERSION,
    log:
        f"{RESULTS}/logs/evaluate_compact.log",
    benchmark:
        f"{RESULTS}/benchmarks/evaluate_compact.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 4000 * attempt,
        runtime=lambda wildcards, attempt: 60 * attempt,
    script:
        "../scripts/evaluate_compact.py"
