# Render: the planned partial views of one object (views x mesh arrays, Parquet).


rule render:
    input:
        model=lambda wildcards: model_input(wildcards.object),
    output:
        f"{RESULTS}/views/{{object}}.parquet",
    params:
        row=catalog_row,
        views=config["views"],
        version=VERSION,
    log:
        f"{RESULTS}/logs/render/{{object}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/render/{{object}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 3000 * attempt,
        runtime=lambda wildcards, attempt: 20 * attempt,
    script:
        "../scripts/render.py"
