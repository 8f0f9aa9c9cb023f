# People (thesis 3.5, config key people): one MakeHuman body's poses in the descriptor's Isomap (Fig. 3.11) and two
# people of one shape in different clothes told apart by colour (Fig. 3.12); Reallusion's people if configured.


rule people:
    input:
        reallusion=[config["people"]["reallusion"]] if config["people"]["reallusion"] else [],
    output:
        table=f"{RESULTS}/people/frames.csv",
        reallusion=f"{RESULTS}/people/reallusion.csv",
        poses_table=f"{RESULTS}/people/poses.csv",
        predictions=f"{RESULTS}/people/twins.csv",
        poses=report(f"{RESULTS}/figures/people_poses.png", caption="../report/people_poses.rst",
                     category="People (3.5)"),
        twins=report(f"{RESULTS}/figures/people_twins.png", caption="../report/people_twins.rst",
                     category="People (3.5)"),
        page=report(f"{RESULTS}/figures/people.html", caption="../report/people_table.rst", category="People (3.5)"),
    params:
        settings=config["people"],
        version=VERSION,
    log:
        f"{RESULTS}/logs/people.log",
    benchmark:
        f"{RESULTS}/benchmarks/people.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 3000 * attempt,
        runtime=lambda wildcards, attempt: 60 * attempt,
    script:
        "../scripts/people.py"
