# Real frames (config key real_frames): folders of labelled real depth frames, segmented as recognize segments a
# frame and scored per category, with each folder's worst frames drawn; off unless folders are named.


rule segment_real_frames:
    input:
        lambda wildcards: frame_files(REAL_FRAMES[wildcards.folder]),
    output:
        scores=f"{RESULTS}/real_frames/{{folder}}.csv",
        worst=f"{RESULTS}/real_frames/{{folder}}.worst.png",
    params:
        folder=lambda wildcards: str(REAL_FRAMES[wildcards.folder]),
        settings=config["real_frames"],
        version=VERSION,
    wildcard_constraints:
        folder="|".join(map(re.escape, REAL_FRAMES)) or "no-real-frames",
    log:
        f"{RESULTS}/logs/segment_real_frames/{{folder}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/segment_real_frames/{{folder}}.tsv"
    threads: 1
    resources:
        mem_mb=lambda wildcards, attempt: 2000 * attempt,
        runtime=lambda wildcards, attempt: 20 * attempt,
    script:
        "../scripts/segment_real_frames.py"


rule real_frames_report:
    input:
        scores=expand(f"{RESULTS}/real_frames/{{folder}}.csv", folder=REAL_FRAMES),
        worst=expand(f"{RESULTS}/real_frames/{{folder}}.worst.png", folder=REAL_FRAMES),
    output:
        summary=report(f"{RESULTS}/real_frames/summary.csv", caption="../report/real_frames_table.rst",
                       category="Real frames"),
        page=report(f"{RESULTS}/figures/real_frames.html", caption="../report/real_frames.rst",
                    category="Real frames"),
    params:
        folders=list(REAL_FRAMES),
        settings=config["real_frames"],
    log:
        f"{RESULTS}/logs/real_frames_report.log",
    benchmark:
        f"{RESULTS}/benchmarks/real_frames_report.tsv"
    resources:
        mem_mb=lambda wildcards, attempt: 1000 * attempt,
        runtime=lambda wildcards, attempt: 10 * attempt,
    script:
        "../scripts/real_frames_report.py"
