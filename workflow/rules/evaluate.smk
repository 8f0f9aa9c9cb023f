# Libraries and evaluation: nearest-neighbour predictions, one job per descriptor (every library size: its test rows
# are read once), precision tables and the report's figures.


rule classify:
    input:
        f"{RESULTS}/descriptors.parquet",
    output:
        temp(f"{RESULTS}/evaluation/parts/{{descriptor}}.parquet"),
    params:
        descriptor=lambda wildcards: SPEC_FILES[wildcards.descriptor].name,
        sizes=config["library_sizes"],
        time_rule=config["time_scale_rule"],
        version=VERSION,
    wildcard_constraints:
        descriptor="|".join(map(re.escape, SPEC_FILES)),
    log:
        f"{RESULTS}/logs/classify/{{descriptor}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/classify/{{descriptor}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 4000 * attempt,
        runtime=lambda wildcards, attempt: 20 * attempt,
    script:
        "../scripts/classify.py"


rule evaluate:
    input:
        expand(f"{RESULTS}/evaluation/parts/{{descriptor}}.parquet", descriptor=SPEC_FILES),
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
        views=expand(f"{RESULTS}/views/{{object}}.parquet", object=OBJECTS),  # misclassified views and neighbours
        models=[model_input(obj) for obj in OBJECTS[:8]],  # the objects drawn in views.png
        scenes=[f"{RESULTS}/scenes/summary.csv"] if SCENES["scenes"] else [],  # the summary leads with them
    output:
        summary_html=report(f"{RESULTS}/figures/summary.html", caption="../report/summary.rst", category="Run"),
        precision=report(f"{RESULTS}/figures/precision.png", caption="../report/precision.rst",
                         category="Precision"),
        precision_table=report(f"{RESULTS}/figures/precision.html", caption="../report/precision_html.rst",
                               category="Precision"),
        confusion=report(directory(f"{RESULTS}/figures/confusion"), patterns=[CONFUSION_PATTERN],
                         caption="../report/confusion.rst", category="Confusion matrices",
                         subcategory="{descriptor}", labels=confusion_labels(config["library_sizes"])),
        view_angles=report(f"{RESULTS}/figures/view_angles.png", caption="../report/view_angles.rst",
                           category="Confusion matrices", subcategory="view angles"),
        misclassified=report(f"{RESULTS}/figures/misclassified.png", caption="../report/misclassified.rst",
                             category="Confusion matrices", subcategory="misclassified views"),
        isomap=report(f"{RESULTS}/figures/isomap.png", caption="../report/isomap.rst", category="Descriptors"),
        curves=report(f"{RESULTS}/figures/curves.png", caption="../report/curves.rst", category="Descriptors"),
        views=report(f"{RESULTS}/figures/views.png", caption="../report/views.rst", category="Descriptors"),
        global_derivative=report(f"{RESULTS}/figures/global_derivative.png",
                                 caption="../report/global_derivative.rst", category="Descriptors"),
        summary=f"{RESULTS}/summary.md",
    params:
        primary=config["primary_descriptor"],
        config=config,
        libraries=LIBRARIES,
        scene_frame=f"{RESULTS}/scenes/frames/{next(iter(SCENES['scenes']))}.png" if SCENES["scenes"] else None,
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


rule front_page:
    input:
        precision=f"{RESULTS}/evaluation/precision.csv",
        overlays=[f"{RESULTS}/scenes/overlays/{scene}.png" for scene in list(SCENES["scenes"])[:3]],
    output:
        report(f"{RESULTS}/figures/front.html", caption="../report/front.rst", category="Run"),
    params:
        primary=config["primary_descriptor"],
        order=[s.name for s in SPECS],
    log:
        f"{RESULTS}/logs/front_page.log",
    benchmark:
        f"{RESULTS}/benchmarks/front_page.tsv"
    resources:
        mem_mb=500,
        runtime=5,
    script:
        "../scripts/front_page.py"


rule ablation:
    input:
        config["ablation"] or [],
    output:
        report(f"{RESULTS}/figures/ablation.html", caption="../report/ablation.rst", category="Ablation"),
    params:
        version=VERSION,
    log:
        f"{RESULTS}/logs/ablation.log",
    benchmark:
        f"{RESULTS}/benchmarks/ablation.tsv"
    threads: 1
    resources:
        mem_mb=500,
        runtime=5,
    script:
        "../scripts/ablation.py"


rule surface:
    input:
        model=lambda wildcards: model_input(wildcards.object),
    output:
        f"{RESULTS}/surfaces/{{object}}.json",
    params:
        row=catalog_row,
        version=VERSION,
    log:
        f"{RESULTS}/logs/surface/{{object}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/surface/{{object}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 2000 * attempt,
        runtime=lambda wildcards, attempt: 5 * attempt,
    script:
        "../scripts/surface.py"


# A descriptor's library files, one per library size (the run's and the scenes'), each with its search index beside it
# (name.faiss; heatdata.recognition.index), which heatdata recognize reads; the index is not an output of its own, as a
# time-scaled kind has none (a library without one builds it). One job a descriptor: building a library takes a
# fraction of the second its imports take.
rule library:
    input:
        descriptors=f"{RESULTS}/descriptors.parquet",
        surfaces=expand(f"{RESULTS}/surfaces/{{object}}.json", object=OBJECTS),
        time_scales=TIME_SCALES,
        fitted=lambda wildcards: [f"{RESULTS}/fitted/{wildcards.descriptor}.npz"] if wildcards.descriptor in FITTED else [],
    output:
        expand(f"{RESULTS}/libraries/{{descriptor}}-{{size}}.parquet", size=LIBRARY_SIZES, allow_missing=True),
    params:
        descriptor=lambda wildcards: SPEC_FILES[wildcards.descriptor].name,
        library_sizes=LIBRARY_SIZES,
        descriptors=config["descriptors"],
        render=config["views"],
        sizes=catalog_sizes(CATALOG),
        objects=OBJECTS,
        time_rule=config["time_scale_rule"],
        version=VERSION,
    wildcard_constraints:
        descriptor="|".join(map(re.escape, SPEC_FILES)),
    log:
        f"{RESULTS}/logs/library/{{descriptor}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/library/{{descriptor}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 2000 * attempt,
        runtime=lambda wildcards, attempt: 10 * attempt,
    script:
        "../scripts/library.py"
