# Describe: the objects' time scales (Alg. 5.1, for FT-PVHK; one table for the run), the fitted kinds (SI-HKS's codebook, from
# every object's library views), descriptor tables one job per object,
# then one table for the run.


rule time_scale:
    input:
        f"{RESULTS}/views/{{object}}.parquet",
    output:
        f"{RESULTS}/time_scales/{{object}}.csv",
    params:
        descriptors=config["descriptors"],
        version=VERSION,
    log:
        f"{RESULTS}/logs/time_scale/{{object}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/time_scale/{{object}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 2000 * attempt,
        runtime=lambda wildcards, attempt: 10 * attempt,
    script:
        "../scripts/time_scale.py"


rule collect_time_scales:
    input:
        expand(f"{RESULTS}/time_scales/{{object}}.csv", object=OBJECTS),
    output:
        f"{RESULTS}/time_scales.csv",
    log:
        f"{RESULTS}/logs/collect_time_scales.log",
    benchmark:
        f"{RESULTS}/benchmarks/collect_time_scales.tsv"
    resources:
        mem_mb=lambda wildcards, attempt: 1000 * attempt,
        runtime=10,
    script:
        "../scripts/collect_time_scales.py"


rule fit_descriptor:
    input:
        expand(f"{RESULTS}/views/{{object}}.parquet", object=OBJECTS),
    output:
        f"{RESULTS}/fitted/{{descriptor}}.npz",
    params:
        descriptor=lambda wildcards: FITTED[wildcards.descriptor].options,
        kind=lambda wildcards: FITTED[wildcards.descriptor].kind,
        steps_limit=config["learned_steps_limit"],
        version=VERSION,
    wildcard_constraints:
        descriptor="|".join(map(re.escape, FITTED)) or "no-fitted-kind",
    log:
        f"{RESULTS}/logs/fit/{{descriptor}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/fit/{{descriptor}}.tsv"
    threads: 1  # XLA trains the pointnet on one core here: two fits run side by side
    resources:
        mem_mb=lambda wildcards, attempt: 4000 * attempt,
        runtime=lambda wildcards, attempt: 60 * attempt,
    script:
        "../scripts/fit.py"


rule describe:
    input:
        views=f"{RESULTS}/views/{{object}}.parquet",
        # kinds learned on every object's library views (SI-HKS)
        fitted=[f"{RESULTS}/fitted/{name}.npz" for name in FITTED],
        # a test view is described at every object's time scale (Alg. 5.2)
        time_scales=TIME_SCALES,
    output:
        f"{RESULTS}/descriptors/{{object}}.parquet",
    params:
        descriptors=config["descriptors"],
        fitted={s.name: f"{RESULTS}/fitted/{name}.npz" for name, s in FITTED.items()},
        version=VERSION,
    log:
        f"{RESULTS}/logs/describe/{{object}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/describe/{{object}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 2000 * attempt,
        runtime=lambda wildcards, attempt: 60 * attempt,
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
