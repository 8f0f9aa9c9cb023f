"""Published results: the steps of the ``docs_*`` targets, and the manifest that says what made each file.

The targets themselves (which run each reads, which steps) are :mod:`heatdata.experiments.docs_targets`.

Every table in ``docs/results`` and figure in ``docs/images`` is written by a Snakemake target of
``workflow/rules/docs.smk``. A target runs its steps (an analysis script on a run's tables, a table
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

import pandas as pd

from heatdata.errors import HeatdataError
from heatdata.io.files import atomic

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


def print_precision(table: pd.DataFrame, index: list[str], out: str | Path | None = None, *, sort: bool = True) -> None:
    """The ending of an analysis script: ``table``'s precision printed by ``index`` (rows) and library size
    (columns) as percentages, and the table written whole to ``out`` when given.

    Parameters
    ----------
    table : DataFrame
        Columns ``index``, ``library_size`` and ``precision`` (a share), one row each.
    index : list of str
    out : path, optional
        The CSV to write.
    sort : bool
        Sort the rows (False: in the order the table has them).
    """
    pivot = table.pivot_table(index=index, columns="library_size", values="precision", sort=sort)
    print(pivot.map(lambda p: f"{p:.1%}").to_string())
    if out:
        write_csv(table, out)


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
