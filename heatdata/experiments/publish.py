"""Published results: the steps of the ``docs_*`` targets, and the manifest that says what made each file.

Every table in ``docs/results`` and figure in ``docs/images`` is written by a Snakemake target of
``workflow/rules/docs.smk`` (issue 32). A target runs its steps (an analysis script on a run's tables, a table
cut from a run's precision, a figure copied from a run), then :func:`record` writes one row per file into
``docs/results/MANIFEST.csv``: the file, the target, the config files, the commit, the wall time and the machine.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path
from typing import NamedTuple

import pandas as pd

from heatdata.errors import HeatdataError
from heatdata.io.files import atomic

E = "config/experiments"


def csv(name: str) -> str:
    """A published table's path."""
    return f"docs/results/{name}.csv"


def png(name: str) -> str:
    """A published figure's path."""
    return f"docs/images/{name}.png"


def script(name: str, *arguments: str) -> dict:
    """A step that runs ``scripts/<name>.py`` with ``arguments``."""
    return {"script": [f"scripts/{name}.py", *arguments]}


VALUE_SCALES = [
    "--descriptor",
    "pvhk/polar/center/64",
    "ft-pvhk/polar/center/64",
    "pvst/polar/interior/64/T0.75",
    "--transform",
    "x1",
    "x0.3",
    "x0.1",
    "x0.01",
    "log10",
    "log10x0.3",
    "log10x0.1",
]
#: the multi-view ablations' run and settings on the chairs (``multiview_chairs.yaml``'s library and path)
CHAIRS_ABLATION = (
    *("multiview_ablation", "--results", "results/multiview_chairs", "--library-views", "13", "7"),
    *("--sigma", "0.2", "--tau", "0.5", "--starts", "10", "--max-degrees", "360"),
)
RESOLUTIONS = {"320x240, 2.5 m": "results/chairs_12", "640x480, 1.5 m": "results/chairs_12_640"}
PEOPLE_RUNS = {
    "seed 0": "results/people",
    "seed 1": "results/people_seed1",
    "seed 2": "results/people_seed2",
    "seed 0, 640x480": "results/people_640",
}
RUMP = "results/rump_proxy"  # the proxy's intermediate tables (scripts/rump_proxy.py reads no run)

MANIFEST = "docs/results/MANIFEST.csv"
#: the folders the targets write (their changes do not make a checkout's commit ``+changes``)
PUBLISHED = ("docs/results", "docs/images")
#: ``wall_seconds``: the docs job's own time (the runs it reads have their own ``benchmark:`` files); empty for a file
#: made before its target existed
MANIFEST_COLUMNS = ["file", "target", "config", "commit", "wall_seconds", "machine"]


def machine() -> str:
    """This machine in a few words: cores, memory and processor (the manifest's ``machine``)."""
    memory = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    return f"{os.cpu_count()} cores, {memory:.0f} GB, {platform.machine()}, Python {platform.python_version()}"


def commit(root: str | Path = ".", exclude: Sequence[str] = ()) -> str:
    """The checkout's commit, with ``+changes`` when files git tracks differ from it (outside ``exclude``, the
    folders a target writes); ``unknown`` outside git."""
    pathspec = ["--", ".", *(f":(exclude){folder}" for folder in exclude)] if exclude else []
    try:
        head = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True, text=True, check=False
        )
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no", *pathspec],
            cwd=root,
            capture_output=True,
            check=False,
        )
    except OSError:
        return "unknown"
    if head.returncode != 0:
        return "unknown"
    return head.stdout.strip() + ("+changes" if dirty.stdout.strip() else "")


def read_manifest(path: str | Path) -> pd.DataFrame:
    """The manifest, one row per published file (an empty one if there is none yet)."""
    if not Path(path).exists():
        return pd.DataFrame(columns=MANIFEST_COLUMNS)
    manifest = pd.read_csv(path, dtype=str, keep_default_na=False)
    if list(manifest.columns) != MANIFEST_COLUMNS:
        raise HeatdataError(f"{path}: a manifest has the columns {', '.join(MANIFEST_COLUMNS)}")
    return manifest


def record(
    manifest: str | Path,
    files: Sequence[str],
    target: str,
    configs: Sequence[str],
    seconds: float,
    source: str | None = None,
) -> None:
    """Replace the manifest rows of ``files`` by this run's (under a lock: targets may finish together).

    ``source``: the commit the files were made at (default: the checkout's now, published folders aside).
    """
    path = Path(manifest)
    rows = pd.DataFrame(
        {
            "file": list(files),
            "target": target,
            "config": " ".join(configs) or "none",
            "commit": source or commit(exclude=PUBLISHED),
            "wall_seconds": f"{seconds:.0f}",
            "machine": machine(),
        }
    )
    key = hashlib.sha1(str(path.resolve()).encode()).hexdigest()[:16]
    with open(Path(tempfile.gettempdir()) / f"heatdata-manifest-{key}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        table = read_manifest(path)
        table = pd.concat([table[~table["file"].isin(rows["file"])], rows], ignore_index=True)
        with atomic(path) as temporary:
            table.sort_values("file").to_csv(temporary, index=False)


def precision_rows(precision_csv: str | Path) -> pd.DataFrame:
    """Object precision over every test view (``level == object``, ``group == all``) of a run's precision table."""
    table = pd.read_csv(precision_csv)
    rows = table[(table["level"] == "object") & (table["group"] == "all")]
    return rows[["descriptor", "library_size", "precision"]].reset_index(drop=True)


def compact_rows(precision_csv: str | Path, descriptor: str) -> pd.DataFrame:
    """A compact-library run's object precision: ``library`` is the method (initial or compact alpha=a)."""
    rows = precision_rows(precision_csv).rename(columns={"descriptor": "library"})
    return rows.assign(descriptor=descriptor)[["descriptor", "library", "library_size", "precision"]]


def labelled(parts: dict[str, pd.DataFrame], column: str) -> pd.DataFrame:
    """Tables of several runs, one above the other, each labelled in a first ``column``."""
    return pd.concat([part.assign(**{column: label}) for label, part in parts.items()], ignore_index=True)[
        [column, *next(iter(parts.values())).columns]
    ]


def write_csv(table: pd.DataFrame, path: str | Path) -> None:
    with atomic(path) as temporary:
        table.to_csv(temporary, index=False)


def copy(source: str | Path, destination: str | Path) -> None:
    """A run's file published as it is (written whole, then renamed)."""
    with atomic(destination) as temporary:
        shutil.copyfile(source, temporary)


def run_script(argv: Sequence[str], log) -> None:
    """One analysis script of ``scripts/`` with this interpreter; its output goes to the job's log."""
    log.write(f"$ {' '.join(map(str, argv))}\n")
    log.flush()
    done = subprocess.run([sys.executable, *map(str, argv)], stdout=log, stderr=subprocess.STDOUT, check=False)
    if done.returncode != 0:
        raise HeatdataError(f"{argv[0]} failed (exit {done.returncode}); its output is in the job's log")


def publish(
    steps: Sequence[dict], outputs: Sequence[str], target: str, configs: Sequence[str], log_path: str, manifest: str
) -> None:
    """Run a ``docs_*`` target's steps in order, check that each output was written, and record them.

    A step is ``{"script": [argv]}``, ``{"copy": [source, destination]}``, ``{"precision": [run csv, out]}``,
    ``{"compact": [run csv, descriptor, out]}``, ``{"concat": [[csv, ...], out]}`` (one table below the other) or
    ``{"labelled": [column, {label: csv}, out]}`` (each labelled in a first column).
    """
    start = time.perf_counter()
    source = commit(exclude=PUBLISHED)  # before the steps write anything
    with open(log_path, "a") as log:
        for step in steps:
            (kind, arguments), *_ = step.items()
            if kind == "script":
                run_script(arguments, log)
            elif kind == "copy":
                copy(*arguments)
            elif kind == "precision":
                write_csv(precision_rows(arguments[0]), arguments[1])
            elif kind == "compact":
                write_csv(compact_rows(arguments[0], arguments[1]), arguments[2])
            elif kind == "concat":
                sources, out = arguments
                write_csv(pd.concat([pd.read_csv(source) for source in sources], ignore_index=True), out)
            elif kind == "labelled":
                column, parts, out = arguments
                write_csv(labelled({label: pd.read_csv(csv) for label, csv in parts.items()}, column), out)
            else:
                raise HeatdataError(f"{target}: unknown step {kind!r}")
    missing = [path for path in outputs if not Path(path).is_file()]
    if missing:
        raise HeatdataError(f"{target}: its steps did not write {', '.join(missing)}")
    record(manifest, outputs, target, configs, time.perf_counter() - start, source)


class Target(NamedTuple):
    """A ``docs_*`` target: the results folder of the run it publishes (None: it reads no run), its config files,
    its inputs, the files it writes into docs/ and the steps of :func:`publish` that write them."""

    results: str | None
    configs: list[str]
    inputs: list[str]
    outputs: list[str]
    steps: list[dict]


def targets(objects: Sequence[str], results: str) -> dict[str, Target]:
    """Every ``docs_*`` target of ``workflow/rules/docs.smk``; ``objects`` and ``results`` are the current run's (the
    rendered views of a run are inputs only when it is the current one)."""

    def views_of(run: str) -> list[str]:
        return [f"{run}/views/{obj}.parquet" for obj in objects] if run == results else []

    table: dict[str, tuple[str | None, list[str], list[str], list[str], list[dict]]] = {
        "docs_main": (
            "results",
            ["config/config.yaml"],
            ["results/figures/views.png", "results/descriptors.parquet", *views_of("results")],
            [png("views"), csv("household_ft_time_scales"), csv("household_value_scales"), csv("household_steps")],
            [
                {"copy": ["results/figures/views.png", png("views")]},
                script(
                    "ft_time_scales",
                    "results/descriptors.parquet",
                    "ft-pvhk/polar/center/64",
                    "--out",
                    csv("household_ft_time_scales"),
                ),
                script(
                    "value_scales", "results/descriptors.parquet", *VALUE_SCALES, "--out", csv("household_value_scales")
                ),
                script("complex_ablation", "results", "--out", csv("household_steps")),
            ],
        ),
        "docs_demo": (
            None,
            [],
            [],
            [png("confusion_objects")],
            [
                {"script": ["-m", "heatdata.cli", "demo", "--out", "results/demo"]},
                {"copy": ["results/demo/confusion_objects_pvhk_polar_center_64.png", png("confusion_objects")]},
            ],
        ),
        "docs_chairs": (
            "results/chairs",
            [f"{E}/chairs.yaml"],
            [
                "results/chairs/figures/precision.png",
                "results/chairs/figures/global_derivative.png",
                "results/chairs/descriptors.parquet",
            ],
            [
                png("chairs_precision"),
                png("chairs_global_derivative"),
                csv("chairs_protocols"),
                csv("chairs_ft_time_scales"),
                csv("chairs_value_scales"),
                csv("chairs_combined"),
            ],
            [
                {"copy": ["results/chairs/figures/precision.png", png("chairs_precision")]},
                {"copy": ["results/chairs/figures/global_derivative.png", png("chairs_global_derivative")]},
                script("protocols", "results/chairs/descriptors.parquet", "--out", csv("chairs_protocols")),
                script(
                    "ft_time_scales",
                    "results/chairs/descriptors.parquet",
                    "ft-pvhk/polar/center/64",
                    "--out",
                    csv("chairs_ft_time_scales"),
                ),
                script(
                    "value_scales",
                    "results/chairs/descriptors.parquet",
                    *VALUE_SCALES,
                    "--leave-one-out",  # its leave-one-out rows (library size 0); the household table has none
                    "--out",
                    csv("chairs_value_scales"),
                ),
                script(
                    "combine_kinds",
                    "results/chairs/descriptors.parquet",
                    "--descriptor",
                    "esf",
                    "pvst/polar/interior/64/T0.75/log-time",
                    "--out",
                    csv("chairs_combined"),
                ),
            ],
        ),
        "docs_chairs_12": (
            "results/chairs_12",
            [f"{E}/chairs.yaml", f"{E}/chairs_12.yaml"],
            [
                "results/chairs_12/evaluation/precision.csv",
                "results/chairs_12/descriptors.parquet",
                *views_of("results/chairs_12"),
            ],
            [
                csv("chairs_12_precision"),
                csv("chairs_12_steps"),
                csv("chairs_12_combined"),
                csv("chairs_12_colour_share"),
            ],
            [
                {"precision": ["results/chairs_12/evaluation/precision.csv", csv("chairs_12_precision")]},
                script("complex_ablation", "results/chairs_12", "--out", csv("chairs_12_steps")),
                script(
                    "combine_kinds",
                    "results/chairs_12/descriptors.parquet",
                    "--descriptor",
                    "esf",
                    "pvst/polar/interior/64/T0.75/log-time",
                    "--out",
                    csv("chairs_12_combined"),
                ),
                script("color_share", "results/chairs_12/descriptors.parquet", "--out", csv("chairs_12_colour_share")),
            ],
        ),
        "docs_chairs_12_640": (
            "results/chairs_12_640",
            [f"{E}/chairs.yaml", f"{E}/chairs_12.yaml", f"{E}/chairs_640.yaml"],
            [f"{run}/descriptors.parquet" for run in RESOLUTIONS.values()],
            [csv("chairs_12_resolution"), csv("chairs_12_ft_time_scales")],
            [
                *(
                    script(
                        "protocols",
                        f"{run}/descriptors.parquet",
                        "--out",
                        f"results/chairs_12_640/published/protocols_{k}.csv",
                    )
                    for k, run in enumerate(RESOLUTIONS.values())
                ),
                *(
                    script(
                        "ft_time_scales",
                        f"{run}/descriptors.parquet",
                        "ft-pvhk/polar/center/64",
                        "--out",
                        f"results/chairs_12_640/published/ft_time_scales_{k}.csv",
                    )
                    for k, run in enumerate(RESOLUTIONS.values())
                ),
                {
                    "labelled": [
                        "views",
                        {
                            label: f"results/chairs_12_640/published/protocols_{k}.csv"
                            for k, label in enumerate(RESOLUTIONS)
                        },
                        csv("chairs_12_resolution"),
                    ]
                },
                {
                    "labelled": [
                        "views",
                        {
                            label: f"results/chairs_12_640/published/ft_time_scales_{k}.csv"
                            for k, label in enumerate(RESOLUTIONS)
                        },
                        csv("chairs_12_ft_time_scales"),
                    ]
                },
            ],
        ),
        "docs_chairs_12_sampling": (
            "results/chairs_12_sampling",
            [f"{E}/chairs.yaml", f"{E}/chairs_12.yaml", f"{E}/chairs_12_sampling.yaml"],
            ["results/chairs_12_sampling/evaluation/precision.csv"],
            [csv("chairs_12_sampling")],
            [{"precision": ["results/chairs_12_sampling/evaluation/precision.csv", csv("chairs_12_sampling")]}],
        ),
        "docs_compact_chairs": (
            "results/compact_chairs",
            [f"{E}/compact_chairs.yaml"],
            ["results/compact_chairs/figures/compact_precision.png"],
            [png("compact_chairs_precision")],
            [{"copy": ["results/compact_chairs/figures/compact_precision.png", png("compact_chairs_precision")]}],
        ),
        "docs_compact_chairs_pvst": (
            "results/compact_chairs_pvst",
            [f"{E}/compact_chairs.yaml", f"{E}/compact_chairs_pvst.yaml"],
            [
                "results/compact_chairs_pvst/compact/precision.csv",
                "results/compact_chairs_pvst/figures/compact_precision.png",
            ],
            [csv("compact_chairs_pvst"), png("compact_chairs_pvst_precision")],
            [
                {
                    "compact": [
                        "results/compact_chairs_pvst/compact/precision.csv",
                        "pvst/polar/interior/64/T0.75",
                        csv("compact_chairs_pvst"),
                    ]
                },
                {
                    "copy": [
                        "results/compact_chairs_pvst/figures/compact_precision.png",
                        png("compact_chairs_pvst_precision"),
                    ]
                },
            ],
        ),
        "docs_compact_chairs_pvst_thesis": (
            "results/compact_chairs_pvst_thesis",
            [f"{E}/compact_chairs.yaml", f"{E}/compact_chairs_pvst.yaml", f"{E}/compact_chairs_pvst_thesis.yaml"],
            ["results/compact_chairs_pvst_thesis/compact/precision.csv"],
            [csv("compact_chairs_pvst_thesis")],
            [
                {
                    "compact": [
                        "results/compact_chairs_pvst_thesis/compact/precision.csv",
                        "pvst/polar/interior/64/T0.75 (c: mhd, rho: l2)",
                        csv("compact_chairs_pvst_thesis"),
                    ]
                }
            ],
        ),
        "docs_compact_chairs_small": (
            "results/compact_chairs_pvst_small",
            [
                f"{E}/compact_chairs.yaml",
                f"{E}/compact_chairs_pvst.yaml",
                f"{E}/compact_chairs_small.yaml",
                f"{E}/compact_chairs_pvst_small.yaml",
            ],
            [
                "results/compact_chairs_small/compact/precision.csv",
                "results/compact_chairs_pvst_small/compact/precision.csv",
            ],
            [csv("compact_chairs_pvst_small")],
            [
                {
                    "compact": [
                        "results/compact_chairs_small/compact/precision.csv",
                        "pvhk/polar/center/64",
                        "results/compact_chairs_pvst_small/published/pvhk.csv",
                    ]
                },
                {
                    "compact": [
                        "results/compact_chairs_pvst_small/compact/precision.csv",
                        "pvst/polar/interior/64/T0.75",
                        "results/compact_chairs_pvst_small/published/pvst.csv",
                    ]
                },
                {
                    "labelled": [
                        "run",
                        {
                            "compact_chairs_small": "results/compact_chairs_pvst_small/published/pvhk.csv",
                            "compact_chairs_pvst_small": "results/compact_chairs_pvst_small/published/pvst.csv",
                        },
                        csv("compact_chairs_pvst_small"),
                    ]
                },
            ],
        ),
        "docs_compact_cups": (
            "results/compact_cups",
            [f"{E}/compact_cups.yaml"],
            ["results/compact_cups/figures/compact_precision.png"],
            [png("compact_cups_precision")],
            [{"copy": ["results/compact_cups/figures/compact_precision.png", png("compact_cups_precision")]}],
        ),
        "docs_baselines": (
            "results/baselines",
            [f"{E}/baselines.yaml"],
            [
                "results/baselines/evaluation/precision.csv",
                "results/baselines/comparison/holes.csv",
                "results/baselines/figures/holes.png",
                "results/baselines/figures/isomap_descriptors.png",
            ],
            [csv("baselines_precision"), csv("baselines_holes"), png("holes"), png("isomap_descriptors")],
            [
                {"copy": ["results/baselines/evaluation/precision.csv", csv("baselines_precision")]},
                {"copy": ["results/baselines/comparison/holes.csv", csv("baselines_holes")]},
                {"copy": ["results/baselines/figures/holes.png", png("holes")]},
                {"copy": ["results/baselines/figures/isomap_descriptors.png", png("isomap_descriptors")]},
            ],
        ),
        "docs_baselines_28": (
            "results/baselines_28",
            [f"{E}/baselines.yaml", f"{E}/baselines_28.yaml"],
            ["results/baselines_28/evaluation/precision.csv"],
            [csv("baselines_28_precision")],
            [{"precision": ["results/baselines_28/evaluation/precision.csv", csv("baselines_28_precision")]}],
        ),
        "docs_multiview": (
            "results/multiview",
            [f"{E}/multiview.yaml"],
            [
                "results/multiview/multiview/summary.csv",
                "results/multiview/figures/multiview.png",
                "results/multiview/descriptors.parquet",
            ],
            [csv("multiview_cups_speakers"), png("multiview"), csv("multiview_ablation")],
            [
                {"copy": ["results/multiview/multiview/summary.csv", csv("multiview_cups_speakers")]},
                {"copy": ["results/multiview/figures/multiview.png", png("multiview")]},
                script("multiview_ablation", "--results", "results/multiview", "--out", csv("multiview_ablation")),
            ],
        ),
        "docs_multiview_chairs": (
            "results/multiview_chairs",
            [f"{E}/multiview_chairs.yaml"],
            [
                "results/multiview_chairs/multiview/summary.csv",
                "results/multiview_chairs/figures/multiview.png",
                "results/multiview_chairs/descriptors.parquet",
            ],
            [
                csv("multiview_chairs"),
                png("multiview_chairs"),
                csv("multiview_chairs_newcomers"),
                csv("multiview_chairs_alpha"),
            ],
            [
                {"copy": ["results/multiview_chairs/multiview/summary.csv", csv("multiview_chairs")]},
                {"copy": ["results/multiview_chairs/figures/multiview.png", png("multiview_chairs")]},
                script(
                    *CHAIRS_ABLATION,
                    *("--particles", "16", "40", "160", "--newcomer", "mean", "least", "--repopulate", "cell", "view"),
                    *("--policies", "fixed", "--repetitions", "3", "--out", csv("multiview_chairs_newcomers")),
                ),
                script(
                    *CHAIRS_ABLATION,
                    *("--particles", "16", "80", "--alpha", "learned", "3", "1", "--repetitions", "2"),
                    *("--out", csv("multiview_chairs_alpha")),
                ),
            ],
        ),
        "docs_people": (
            "results/people",
            [f"{E}/people.yaml"],
            [f"{run}/people/{table}.csv" for run in PEOPLE_RUNS.values() for table in ("poses", "twins")]
            + ["results/people/figures/people_poses.png", "results/people/figures/people_twins.png"],
            [csv("people_poses"), csv("people_twins"), png("people_poses"), png("people_twins")],
            [
                {
                    "labelled": [
                        "run",
                        {label: f"{run}/people/poses.csv" for label, run in PEOPLE_RUNS.items()},
                        csv("people_poses"),
                    ]
                },
                {
                    "labelled": [
                        "run",
                        {label: f"{run}/people/twins.csv" for label, run in PEOPLE_RUNS.items()},
                        csv("people_twins"),
                    ]
                },
                {"copy": ["results/people/figures/people_poses.png", png("people_poses")]},
                {"copy": ["results/people/figures/people_twins.png", png("people_twins")]},
            ],
        ),
        "docs_twins": (
            "results/twins",
            [f"{E}/twins.yaml"],
            ["results/twins/evaluation/predictions.parquet", "results/twins/catalog.csv"],
            [csv("twins_precision"), png("colour_twins")],
            [script("color_twins", "results/twins", "--out", csv("twins_precision"), "--figure", png("colour_twins"))],
        ),
        "docs_jasnom_cuts": (
            None,
            [],
            [],
            [csv("jasnom_cuts"), csv("jasnom_holes")],
            [script("jasnom_cuts", "--out", csv("jasnom_cuts"), "--holes-out", csv("jasnom_holes"))],
        ),
        "docs_jasnom_scans": (
            None,
            [],
            [],
            [csv("jasnom_scans"), csv("jasnom_scans_precision"), csv("jasnom_scans_tried"), png("jasnom")],
            [
                script(
                    "jasnom_scans",
                    "--out",
                    csv("jasnom_scans"),
                    "--precision-out",
                    csv("jasnom_scans_precision"),
                    "--tried-out",
                    csv("jasnom_scans_tried"),
                    "--figure",
                    png("jasnom"),
                )
            ],
        ),
        "docs_rump": (
            None,
            [],
            [],
            [csv("rump_proxy"), csv("rump_proxy_ablation"), png("rump_proxy")],
            [
                script(
                    "rump_proxy",
                    "--out",
                    csv("rump_proxy"),
                    "--ablation-out",
                    f"{RUMP}/ablation.csv",
                    "--figure",
                    png("rump_proxy"),
                ),
                script(
                    "rump_proxy",
                    "--image-scale",
                    "0.5",
                    "--out",
                    f"{RUMP}/bodies_320.csv",
                    "--ablation-out",
                    f"{RUMP}/ablation_320.csv",
                ),
                script(
                    "rump_proxy",
                    "--muscle",
                    "0.5,0.5",
                    "--ablation",
                    "1.5",
                    "--out",
                    f"{RUMP}/bodies_muscle.csv",
                    "--ablation-out",
                    f"{RUMP}/ablation_muscle.csv",
                ),
                {
                    "concat": [
                        [f"{RUMP}/ablation.csv", f"{RUMP}/ablation_320.csv", f"{RUMP}/ablation_muscle.csv"],
                        csv("rump_proxy_ablation"),
                    ]
                },
            ],
        ),
        "docs_complex_steps": (  # draws the two published step tables (docs_chairs_12's and docs_main's)
            None,
            [],
            [],
            [png("complex_steps")],
            [
                script(
                    "complex_ablation",
                    "--plot",
                    csv("chairs_12_steps"),
                    csv("household_steps"),
                    "--figure",
                    png("complex_steps"),
                )
            ],
        ),
    }
    return {name: Target(*entry) for name, entry in table.items()}
