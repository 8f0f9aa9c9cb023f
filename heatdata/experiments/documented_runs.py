"""Every workflow run the documentation tells a user to make, so that CI runs each one.

A documented run is the list of config files of one ``snakemake --configfile ...`` command in the README,
``config/README.md`` or a page under ``docs/`` (an optional file in brackets, ``[config/experiments/x.yaml]``, makes
two runs: without it and with it), of a ``docs_*`` target (``workflow/docs_targets.yaml``), or the default run
(``config/config.yaml``). :func:`run_small` makes one of them with ``config/small.yaml`` layered last: a dry run of
the run as documented, then the run itself on three of its objects and a few views, then its report page.
``scripts/documented_runs.py`` runs them all (CI does, after the tests).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import NamedTuple

from heatdata.experiments import docs_targets

ROOT = Path(__file__).resolve().parents[2]
#: where the docs' commands are read from, relative to the repository
DOCUMENTS = ("README.md", "config/README.md", "docs")
DEFAULT_CONFIG = "config/config.yaml"
SMALL_CONFIG = "config/small.yaml"
#: ``--configfile`` (or ``--configfiles``) and the config files after it, an optional one in brackets
_COMMAND = re.compile(r"--configfiles?((?:\s+\[?config/[a-z0-9_/.-]+\.yaml\]?)+)")
_FILE = re.compile(r"(\[?)(config/[a-z0-9_/.-]+\.yaml)\]?")
#: a target after the config files: snakemake reads it as one more config file
_TARGET_AFTER = re.compile(r"--configfiles?(?:[ \t]+\[?config/[\w/.-]+\.yaml\]?)++[ \t]+([A-Za-z_][\w/.-]*)")


class Run(NamedTuple):
    """A documented run: its name (its config files' stems), its config files in order, where it is documented."""

    name: str
    configs: tuple[str, ...]
    where: str


def _name(configs: Sequence[str]) -> str:
    return "+".join(Path(c).stem for c in configs)


def command_configs(text: str) -> list[tuple[str, ...]]:
    """The config-file lists of every ``--configfile`` command in ``text``, an optional file both left out and in.

    Parameters
    ----------
    text : str
        A page of the docs.

    Returns
    -------
    list of tuple of str
        One tuple of config paths per run, in the order the command gives them.
    """
    runs = []
    for command in _COMMAND.finditer(text):
        required: list[str] = []
        optional: list[str] = []
        for bracket, path in _FILE.findall(command.group(1)):
            (optional if bracket else required).append(path)
        runs.append(tuple(required))
        if optional:
            runs.append(tuple(required + optional))
    return runs


def targets_after_configs(text: str) -> list[str]:
    """The commands of ``text`` that name a target after ``--configfile``'s files: snakemake takes the target for
    one more config file (its option reads every word after it), so a target must come first."""
    return [match.group(0) for match in _TARGET_AFTER.finditer(text)]


def _pages(root: Path) -> list[Path]:
    pages = []
    for entry in DOCUMENTS:
        path = root / entry
        pages += sorted(path.rglob("*.md")) if path.is_dir() else [path]
    return pages


def documented_runs(root: Path = ROOT) -> list[Run]:
    """Every documented run, once each, in the order the docs first give them (the default run first); a command
    with :data:`SMALL_CONFIG` is the small run of the others, which CI makes anyway.

    Parameters
    ----------
    root : Path
        The repository.

    Returns
    -------
    list of Run
    """
    found: dict[tuple[str, ...], str] = {(DEFAULT_CONFIG,): "README.md"}
    for page in _pages(root):
        for configs in command_configs(page.read_text(encoding="utf-8")):
            configs = tuple(c for c in configs if c != SMALL_CONFIG)  # a small run of the rest: that run's own
            if configs:
                found.setdefault(configs, page.relative_to(root).as_posix())
    for name, target in docs_targets.targets([], "results").items():
        if target.configs:
            found.setdefault(tuple(target.configs), f"workflow/docs_targets.yaml ({name})")
    return [Run(_name(configs), configs, where) for configs, where in found.items()]


class Outcome(NamedTuple):
    """How one documented run went: each stage's seconds (None: not reached; a failed stage's are its own), the jobs
    of its small run, and the first failure's last lines."""

    run: Run
    dry_seconds: float | None
    run_seconds: float | None
    report_seconds: float | None
    jobs: int | None
    error: str

    @property
    def ok(self) -> bool:
        return not self.error


def _snakemake(arguments: list[str], root: Path, timeout: float) -> tuple[float, subprocess.CompletedProcess]:
    snakemake = Path(sys.executable).parent / "snakemake"
    start = time.perf_counter()
    try:
        done = subprocess.run(
            [str(snakemake), "--cores", "2", *arguments], cwd=root, capture_output=True, text=True, timeout=timeout,
            env=dict(os.environ, PYTHONPATH=str(root)), check=False,
        )  # fmt: skip
    except subprocess.TimeoutExpired as exc:
        done = subprocess.CompletedProcess(exc.cmd, 124, "", f"timed out after {timeout:.0f} s")
    return time.perf_counter() - start, done


def _tail(done: subprocess.CompletedProcess, lines: int = 15) -> str:
    return "\n".join((done.stdout + done.stderr).strip().splitlines()[-lines:])


def run_small(run: Run, out: Path, root: Path = ROOT, timeout: float = 1800) -> Outcome:
    """Dry-run ``run`` as documented, then run it small (:data:`SMALL_CONFIG` last) into ``out``, then its report.

    Parameters
    ----------
    run : Run
        A documented run.
    out : Path
        Its small run's results folder (``results`` of the config is set to it).
    root : Path
        The repository, where snakemake runs.
    timeout : float
        Seconds each stage may take.

    Returns
    -------
    Outcome
    """
    configs = ["--configfile", *run.configs]
    dry_seconds, dry = _snakemake(["--dry-run", "--quiet", *configs], root, timeout)
    if dry.returncode:
        return Outcome(run, None, None, None, None, f"dry run: {_tail(dry)}")
    small = [*configs, SMALL_CONFIG, "--config", f"results={out}"]
    run_seconds, done = _snakemake(small, root, timeout)
    jobs = re.search(r"(\d+) of \1 steps \(100%\) done", done.stdout + done.stderr)
    if done.returncode:
        return Outcome(run, dry_seconds, run_seconds, None, None, f"small run: {_tail(done)}")
    report_seconds, report = _snakemake([*small, "--report", str(out / "report.html")], root, timeout)
    error = f"report: {_tail(report)}" if report.returncode else ""
    jobs_done = int(jobs.group(1)) if jobs else 0
    if not error and not (out / "summary.md").is_file():
        error = f"report: the run left no {out / 'summary.md'}"
    return Outcome(run, dry_seconds, run_seconds, report_seconds, jobs_done, error)
