"""Logging and signal set-up for the command line and the workflow's jobs (no heatdata module logs by print)."""

from __future__ import annotations

import logging
import multiprocessing
import re
import signal
import sys
import threading
from collections.abc import Iterable

from tqdm import tqdm

from heatdata.errors import Terminated

log = logging.getLogger("heatdata")


_CONTROL = re.compile(r"[\x00-\x1f\x7f-\x9f]")


def printable(value: object) -> str:
    """``str(value)`` with its control characters escaped (``\\n``, ``\\x1b``): a name read from a file (an
    object's, a frame's) cannot clear the terminal, colour it or forge a line.

    Parameters
    ----------
    value : object
        What is printed.

    Returns
    -------
    str
    """
    return _CONTROL.sub(lambda match: match.group().encode("unicode_escape").decode(), str(value))


class _Printable(logging.Filter):
    """Each log record's message made :func:`printable` (its traceback, when there is one, is left as it is)."""

    def filter(self, record: logging.LogRecord) -> bool:
        record.msg, record.args = printable(record.getMessage()), None
        return True


def setup_logging(verbose: bool = False, path: str | None = None) -> None:
    """Log heatdata's progress to stderr, or to ``path`` (a Snakemake job's log file).

    With a ``path``, an uncaught error is written to that log too, so a failed job's
    log names the file or view that failed. SIGTERM unwinds as Ctrl-C does
    (:func:`terminate_as_interrupt`), so a killed job leaves no temporary file.
    """
    terminate_as_interrupt()
    logging.basicConfig(
        level=logging.DEBUG if verbose else logging.INFO,
        filename=path,
        force=path is not None,
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
        datefmt="%H:%M:%S",
    )
    for handler in logging.root.handlers:
        if not any(isinstance(f, _Printable) for f in handler.filters):
            handler.addFilter(_Printable())
    if path is not None:

        def log_and_raise(kind, value, traceback):
            log.critical("%s: %s", kind.__name__, value, exc_info=(kind, value, traceback))
            sys.__excepthook__(kind, value, traceback)

        sys.excepthook = log_and_raise
    logging.getLogger("trimesh").setLevel(logging.WARNING)
    logging.getLogger("faiss.loader").setLevel(logging.WARNING)  # which of its CPU builds it tried
    if not verbose:  # per-view repairs are summarized per object and recorded in the tables
        logging.getLogger("heatdata.views.view").setLevel(logging.WARNING)


def _raise_terminated(signum, frame):
    raise Terminated()


def terminate_as_interrupt() -> None:
    """Make SIGTERM (a batch system's kill, ``timeout``) raise :class:`~heatdata.errors.Terminated`, a
    ``KeyboardInterrupt``, in the main thread.

    The default SIGTERM ends the process at once, leaving the temporary file of a write under way; raised, it
    passes through :func:`heatdata.io.files.atomic`, which removes it. Outside the main thread (where Python takes no
    signal handler) and in a worker of a multiprocessing pool (which its pool ends with SIGTERM, and which would
    then hang) nothing changes.
    """
    if threading.current_thread() is threading.main_thread() and multiprocessing.parent_process() is None:
        signal.signal(signal.SIGTERM, _raise_terminated)


def progress(items: Iterable, *, total: int | None = None, desc: str, unit: str) -> Iterable:
    """``items`` with a progress bar (count, rate, ETA) on stderr; silent when stderr is not a terminal.

    The command line runs under ``tqdm.contrib.logging.logging_redirect_tqdm``, so log lines
    print above the bar instead of through it.
    """
    return tqdm(items, total=total, desc=desc, unit=unit, file=sys.stderr, disable=None, dynamic_ncols=True)
