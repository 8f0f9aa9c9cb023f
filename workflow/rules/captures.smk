# Captures (thesis 2.1, config key captures): depth images from a sensor, one folder per object, read into views,
# described as rendered test views are and recognized against the run's library views.


rule capture_views:
    input:
        lambda wildcards: list(dict.fromkeys(path for c in CAPTURES[wildcards.object]  # a shared camera once
                                             for path in (c["depth"], c["intrinsics"], c["rgb"], c["mask"]) if path)),
    output:
        f"{RESULTS}/captures/views/{{object}}.parquet",
    params:
        captures=lambda wildcards: CAPTURES[wildcards.object],
        label=lambda wildcards: CATALOG.at[wildcards.object, "label"],
        settings=config["captures"],
        version=VERSION,
    wildcard_constraints:
        object="|".join(map(re.escape, CAPTURES)) or "no-capture",
    log:
        f"{RESULTS}/logs/capture_views/{{object}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/capture_views/{{object}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 2000 * attempt,
        runtime=lambda wildcards, attempt: 10 * attempt,
    script:
        "../scripts/capture_views.py"


rule describe_captures:
    input:
        views=f"{RESULTS}/captures/views/{{object}}.parquet",
        fitted=[f"{RESULTS}/fitted/{name}.npz" for name in FITTED],
        time_scales=TIME_SCALES,
    output:
        f"{RESULTS}/captures/descriptors/{{object}}.parquet",
    params:
        descriptors=config["descriptors"],
        fitted={s.name: f"{RESULTS}/fitted/{name}.npz" for name, s in FITTED.items()},
        version=VERSION,
    wildcard_constraints:
        object="|".join(map(re.escape, CAPTURES)) or "no-capture",
    log:
        f"{RESULTS}/logs/describe_captures/{{object}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/describe_captures/{{object}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 2000 * attempt,
        runtime=lambda wildcards, attempt: 60 * attempt,
    script:
        "../scripts/describe.py"


rule evaluate_captures:
    input:
        library=f"{RESULTS}/descriptors.parquet",
        captures=expand(f"{RESULTS}/captures/descriptors/{{object}}.parquet", object=CAPTURES),
    output:
        predictions=f"{RESULTS}/captures/predictions.parquet",
        precision=f"{RESULTS}/captures/precision.csv",
        page=report(f"{RESULTS}/figures/captures.html", caption="../report/captures.rst", category="Captures"),
    params:
        sizes=config["library_sizes"],
        primary=config["primary_descriptor"],
        time_rule=config["time_scale_rule"],
        version=VERSION,
    log:
        f"{RESULTS}/logs/evaluate_captures.log",
    benchmark:
        f"{RESULTS}/benchmarks/evaluate_captures.tsv"
    resources:
        mem_mb=lambda wildcards, attempt: 3000 * attempt,
        runtime=lambda wildcards, attempt: 30 * attempt,
    script:
        "../scripts/evaluate_captures.py"
