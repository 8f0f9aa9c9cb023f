# Models: the catalogue the run uses (embedded set, a Sweet Home 3D library or a user folder),
# and the extraction of Sweet Home 3D models, one job per object.


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


rule extract_model:
    input:
        lambda wildcards: CATALOG.at[wildcards.object, "archive"],
    output:
        directory(f"{RESULTS}/models/{{object}}"),
    params:
        model=lambda wildcards: CATALOG.at[wildcards.object, "file"],
        version=VERSION,
    log:
        f"{RESULTS}/logs/extract_model/{{object}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/extract_model/{{object}}.tsv"
    resources:
        mem_mb=500,
        runtime=5,
    script:
        "../scripts/extract_model.py"
