"""Logging set-up for the command line and the workflow's jobs (no heatdata module logs by print)."""

from __future__ import annotations

import logging
import sys
from collections.abc import Iterable

from tqdm import tqdm

log = logging.getLogger("heatdata")


def setup_logging(verbose: bool = False, path: str | None = None) -> None:
    """Log heatdata's progress to stderr, or to ``path`` (a Snakemake job's log file).

    With a ``path``, an uncaught error is written to that log too, so a failed job's
    log names the file or view that failed.
    """
    logging.basicConfig(
        level=logging.DEBUG if verbose else logging.INFO,
        filename=path,
        force=path is not None,
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
        datefmt="%H:%M:%S",
    )
    if path is not None:

        def log_and_raise(kind, value, traceback):
            log.critical("%s: %s", kind.__name__, value, exc_info=(kind, value, traceback))
            sys.__excepthook__(kind, value, traceback)

        sys.excepthook = log_and_raise
    logging.getLogger("trimesh").setLevel(logging.WARNING)
    if not verbose:  # per-view repairs are summarized per object and recorded in the tables
        logging.getLogger("heatdata.views.view").setLevel(logging.WARNING)


def progress(items: Iterable, *, total: int | None = None, desc: str, unit: str) -> Iterable:
    """``items`` with a progress bar (count, rate, ETA) on stderr; silent when stderr is not a terminal.

    The command line runs under ``tqdm.contrib.logging.logging_redirect_tqdm``, so log lines
    print above the bar instead of through it.
    """
    return tqdm(items, total=total, desc=desc, unit=unit, file=sys.stderr, disable=None, dynamic_ncols=True)
