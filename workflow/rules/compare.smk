# The descriptor comparison of thesis 3.6 (config key comparison): Isomaps of every descriptor on four
# objects (Fig. 3.13) and boxes with holes cut in their faces against the same boxes solid (Fig. 3.14-3.15).
# Precision against library size for every descriptor is the ordinary evaluation's.


rule compare_descriptors:
    input:
        descriptors=f"{RESULTS}/descriptors.parquet",
        fitted=[f"{RESULTS}/fitted/{name}.npz" for name in FITTED],
    output:
        isomaps=report(f"{RESULTS}/figures/isomap_descriptors.png", caption="../report/isomap_descriptors.rst",
                       category="Descriptor comparison"),
        holes=report(f"{RESULTS}/comparison/holes.csv", caption="../report/holes_table.rst",
                     category="Descriptor comparison"),
        holes_figure=report(f"{RESULTS}/figures/holes.png", caption="../report/holes.rst",
                            category="Descriptor comparison"),
    params:
        comparison=config["comparison"],
        descriptors=config["descriptors"],
        fitted={s.name: f"{RESULTS}/fitted/{name}.npz" for name, s in FITTED.items()},
        version=VERSION,
    log:
        f"{RESULTS}/logs/compare_descriptors.log",
    benchmark:
        f"{RESULTS}/benchmarks/compare_descriptors.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 4000 * attempt,
        runtime=lambda wildcards, attempt: 60 * attempt,
    script:
        "../scripts/compare.py"
