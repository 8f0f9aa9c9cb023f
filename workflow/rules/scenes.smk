# Scenes: the run's objects on a table with a wall behind, seen through the sensor profile; every scene recognized
# with the run's libraries, scored against its truth, and drawn (config key scenes). The test views rendered again
# off the optical axis measure that where an object stands in the frame does not change its answer.


rule scene:
    input:
        lambda wildcards: [model_input(obj) for obj in SCENES["scenes"][wildcards.scene]],
    output:
        depth=f"{RESULTS}/scenes/frames/{{scene}}.png",
        rgb=f"{RESULTS}/scenes/frames/{{scene}}.rgb.png",
        intrinsics=f"{RESULTS}/scenes/frames/{{scene}}.json",
        labels=f"{RESULTS}/scenes/frames/{{scene}}.labels.png",
        truth=f"{RESULTS}/scenes/frames/{{scene}}.truth.json",
    params:
        rows=lambda wildcards: [catalog_row_of(obj) for obj in SCENES["scenes"][wildcards.scene]],
        index=lambda wildcards: int(wildcards.scene.split("-")[1]),
        settings=config["scenes"],
        version=VERSION,
    wildcard_constraints:
        scene=r"scene-\d{3}",
    log:
        f"{RESULTS}/logs/scene/{{scene}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/scene/{{scene}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 2000 * attempt,
        runtime=lambda wildcards, attempt: 10 * attempt,
    script:
        "../scripts/scene.py"


rule recognize_scenes:
    input:
        frames=expand(f"{RESULTS}/scenes/frames/{{scene}}{{part}}", scene=SCENES["scenes"],
                      part=[".png", ".rgb.png", ".json", ".labels.png", ".truth.json"]),
        library=f"{RESULTS}/libraries/{{descriptor}}-{SCENES['size']}.parquet",
    output:
        f"{RESULTS}/scenes/detections/{{descriptor}}.parquet",
    params:
        size=SCENES["size"],
        settings=config["scenes"],
        version=VERSION,
    wildcard_constraints:
        descriptor="|".join(map(re.escape, SPEC_FILES)),
    log:
        f"{RESULTS}/logs/recognize_scenes/{{descriptor}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/recognize_scenes/{{descriptor}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 3000 * attempt,
        runtime=lambda wildcards, attempt: 30 * attempt,
    script:
        "../scripts/recognize_scenes.py"


rule offaxis_views:
    input:
        model=lambda wildcards: model_input(wildcards.object),
    output:
        f"{RESULTS}/scenes/offaxis/views/{{object}}.parquet",
    params:
        row=catalog_row,
        views=config["views"],
        views_per_object=config["scenes"]["offaxis"],
        version=VERSION,
    log:
        f"{RESULTS}/logs/offaxis_views/{{object}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/offaxis_views/{{object}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 2000 * attempt,
        runtime=lambda wildcards, attempt: 10 * attempt,
    script:
        "../scripts/offaxis_views.py"


rule describe_offaxis:
    input:
        views=f"{RESULTS}/scenes/offaxis/views/{{object}}.parquet",
        fitted=[f"{RESULTS}/fitted/{name}.npz" for name in FITTED],
        time_scales=TIME_SCALES,
    output:
        f"{RESULTS}/scenes/offaxis/descriptors/{{object}}.parquet",
    params:
        descriptors=config["descriptors"],
        fitted={s.name: f"{RESULTS}/fitted/{name}.npz" for name, s in FITTED.items()},
        version=VERSION,
    log:
        f"{RESULTS}/logs/describe_offaxis/{{object}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/describe_offaxis/{{object}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 2000 * attempt,
        runtime=lambda wildcards, attempt: 60 * attempt,
    script:
        "../scripts/describe.py"


rule evaluate_scenes:
    input:
        detections=[f"{RESULTS}/scenes/detections/{file_name(name)}.parquet" for name in SCENES["descriptors"]],
        frames=expand(f"{RESULTS}/scenes/frames/{{scene}}{{part}}", scene=SCENES["scenes"],
                      part=[".png", ".rgb.png"]),
        library=f"{RESULTS}/descriptors.parquet" if config["scenes"]["offaxis"] else [],
        offaxis=expand(f"{RESULTS}/scenes/offaxis/descriptors/{{object}}.parquet", object=OBJECTS)
        if config["scenes"]["offaxis"] else [],
        predictions=f"{RESULTS}/evaluation/predictions.parquet" if config["scenes"]["offaxis"] else [],
        surfaces=expand(f"{RESULTS}/surfaces/{{object}}.json", object=OBJECTS),
    output:
        summary=report(f"{RESULTS}/scenes/summary.csv", caption="../report/scenes_table.rst", category="Scenes"),
        offaxis=f"{RESULTS}/scenes/offaxis.csv",
        overlays=[f"{RESULTS}/scenes/overlays/{scene}.png" for scene in SCENES["scenes"]],
        page=report(f"{RESULTS}/figures/scenes.html", caption="../report/scenes.rst", category="Scenes"),
    params:
        objects=OBJECTS,
        primary=SCENES["primary"],
        size=SCENES["size"],
        settings=config["scenes"],
        time_rule=config["time_scale_rule"],
        version=VERSION,
    log:
        f"{RESULTS}/logs/evaluate_scenes.log",
    benchmark:
        f"{RESULTS}/benchmarks/evaluate_scenes.tsv"
    resources:
        mem_mb=lambda wildcards, attempt: 3000 * attempt,
        runtime=lambda wildcards, attempt: 20 * attempt,
    script:
        "../scripts/evaluate_scenes.py"
