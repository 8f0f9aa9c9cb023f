# Models: the catalogue the run uses (embedded set, an imported Sweet Home 3D library or a user folder).


rule catalog:
    output:
        f"{RESULTS}/catalog.csv",
    params:
        rows=CATALOG.to_json(orient="records"),
        version=VERSION,
    log:
        f"{RESULTS}/logs/catalog.log",
    benchmark:
        f"{RESULTS}/benchmarks/catalog.tsv"
    resources:
        mem_mb=500,
        runtime=5,
    script:
        "../scripts/catalog.py"
