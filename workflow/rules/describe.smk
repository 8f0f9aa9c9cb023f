# Describe: PVHK / C-PVHK descriptor tables, one job per object, then one table for the run.


rule describe:
    input:
        f"{RESULTS}/views/{{object}}.parquet",
    output:
        f"{RESULTS}/descriptors/{{object}}.parquet",
    params:
        descriptors=config["descriptors"],
        version=VERSION,
    log:
        f"{RESULTS}/logs/describe/{{object}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/describe/{{object}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 2000 * attempt,
        runtime=lambda wildcards, attempt: 30 * attempt,
    script:
        "../scripts/describe.py"


rule collect_descriptors:
    input:
        expand(f"{RESULTS}/descriptors/{{object}}.parquet", object=OBJECTS),
    output:
        f"{RESULTS}/descriptors.parquet",
    params:
        version=VERSION,
    log:
        f"{RESULTS}/logs/collect_descriptors.log",
    benchmark:
        f"{RESULTS}/benchmarks/collect_descriptors.tsv"
    resources:
        mem_mb=lambda wildcards, attempt: 2000 * attempt,
        runtime=10,
    script:
        "../scripts/collect.py"
