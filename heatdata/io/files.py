"""Writing outputs safely: checked before the work starts, never over an input, and atomically.

Every file heatdata writes goes through :func:`atomic`: it is written under a temporary name in
its own folder and renamed onto its real name only when complete, so an interrupted or failed
write never leaves a half file under the real name (a rename within one folder is atomic on
POSIX). Commands call :func:`check_output` (or :func:`check_folder`) first, so that an output
that cannot be written, or would replace one of the command's inputs, is refused in one line
before minutes of work.

A command that writes several outputs writes them with :func:`atomic_group`: each under its temporary name, then
all renamed together while the output folders are locked, so two runs writing the same outputs leave one run's
set, never a mix. SIGTERM unwinds like Ctrl-C in heatdata's commands and jobs
(:func:`heatdata.log.terminate_as_interrupt`), so the temporary files of an interrupted write are removed.
Readers of folders skip what :func:`is_partial` names: hidden files and the temporary files of a write under way.
"""

from __future__ import annotations

import fcntl
import os
import secrets
import tempfile
from collections.abc import Iterable, Iterator, Sequence
from contextlib import ExitStack, contextmanager, suppress
from pathlib import Path

from heatdata.errors import HeatdataError, OutputError
from heatdata.typing import StrPath


def require_file(path: StrPath, what: str, error: type[HeatdataError] = HeatdataError) -> Path:
    """``path`` if it is a regular file, else ``error`` saying it is missing or not a file.

    A folder, a device (``/dev/zero`` would be read forever) or a pipe is refused as well as a missing path.

    Parameters
    ----------
    path : str or Path
        An input.
    what : str
        What it should be, for the message (``"model file"``).
    error : type
        The :class:`HeatdataError` the caller raises.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    HeatdataError
        Of type ``error``: ``"<path>: no such <what>"``, or ``"<path>: is a folder, not a <what>"``.
    """
    path = Path(path)
    if path.is_file():
        return path
    if path.is_dir():
        raise error(f"{path}: is a folder, not a {what}")
    if path.exists():
        raise error(f"{path}: is not a regular file (a device or a pipe), not a {what}")
    raise error(f"{path}: no such {what}")


def _reason(error: OSError) -> str:
    return error.strerror or str(error)


def _same_file(a: Path, b: Path) -> bool:
    """Whether two paths name one file (through links, ``..`` or a hard link)."""
    if a.resolve() == b.resolve():
        return True
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist yet
        return False


def _writable_folder(folder: Path, output: Path, *, create: bool = False) -> None:
    """Prove a file can be created in ``folder``, or in its nearest existing ancestor when it does not exist yet (a
    read-only disk, ``/proc``, ...); create it only when ``create``, after the proof."""
    existing = folder
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        raise OutputError(f"{output}: cannot be written: {existing} is a file, not a folder")
    try:
        handle, probe = tempfile.mkstemp(dir=existing, prefix=".heatdata-probe-")
        os.close(handle)
        os.unlink(probe)
        if create:
            folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise OutputError(f"{output}: cannot be written in {folder} ({_reason(error)})") from None


def check_output(
    path: StrPath,
    *,
    inputs: Iterable[StrPath | None] = (),
    suffixes: tuple[str, ...] | None = None,
    what: str = "the output",
) -> Path:
    """Refuse an output file before the work that makes it: one that cannot be written or would replace an input.

    Nothing is created: a refused command leaves no trace, and the writer (:func:`atomic`) creates the folder.

    Parameters
    ----------
    path : str or Path
        The file to be written.
    inputs : iterable of str or Path or None
        The command's input files (``None`` entries are skipped).
    suffixes : tuple of str, optional
        The suffixes the writer understands, lower case with the dot (``(".npz", ".ply")``).
    what : str
        What the file is, for the message (``"the view"``).

    Returns
    -------
    Path
        ``path``, checked.

    Raises
    ------
    OutputError
        The suffix is not one of ``suffixes``, the path is a folder, it names one of the ``inputs``, or its
        folder cannot be created or written to.
    """
    path = Path(path)
    if suffixes is not None and path.suffix.lower() not in suffixes:
        raise OutputError(f"{path}: {what} is written to a file ending in {' or '.join(suffixes)}")
    if path.is_dir():
        raise OutputError(f"{path}: is a folder; {what} is a file: give a file name")
    for given in inputs:
        if given is not None and _same_file(path, Path(given)):
            raise OutputError(f"{path}: is also an input of this command; write {what} to another file")
    _writable_folder(path.parent, path)
    return path


def check_folder(path: StrPath, *, inputs: Iterable[StrPath | None] = ()) -> Path:
    """Refuse an output folder before the work: a file, a folder that cannot be created or written, or an input.

    Parameters
    ----------
    path : str or Path
        The folder to write into (created if missing).
    inputs : iterable of str or Path or None
        The command's input files and folders.

    Returns
    -------
    Path
        ``path``, created and checked.

    Raises
    ------
    OutputError
        ``path`` is a file or an input, or it cannot be created or written to.
    """
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise OutputError(f"{path}: the output folder is a file")
    for given in inputs:
        if given is not None and _same_file(path, Path(given)):
            raise OutputError(f"{path}: is also an input of this command; write into another folder")
    _writable_folder(path, path, create=True)
    return path


def is_partial(path: StrPath) -> bool:
    """Whether a folder's reader should skip ``path``: a hidden file, or the temporary file of a write under way
    (:func:`atomic`'s ``.<stem>.<hex>.part<suffix>``).

    Parameters
    ----------
    path : str or Path
        A file found in a folder.

    Returns
    -------
    bool
    """
    name = Path(path).name
    return name.startswith(".") or ".part." in name or name.endswith(".part")


def _temporary(path: Path) -> Path:
    return path.with_name(f".{path.stem}.{secrets.token_hex(4)}.part{path.suffix}")


@contextmanager
def atomic(path: StrPath) -> Iterator[Path]:
    """A temporary file next to ``path`` to write; renamed onto ``path`` when the block ends without an error.

    The temporary name keeps ``path``'s suffix (writers that choose a format by suffix work unchanged) and
    starts with a dot. On an error it is removed and ``path`` is left as it was. The folder is created. It is
    :func:`atomic_group` of one file.

    Parameters
    ----------
    path : str or Path
        The file to write.

    Yields
    ------
    Path
        Where to write it.

    Raises
    ------
    OutputError
        The folder cannot be created, or the file cannot be written or renamed (the system's reason is given).
    """
    with atomic_group([path]) as (temporary,):
        yield temporary


def _remove(path: Path) -> None:
    with suppress(OSError):  # it may never have been created
        path.unlink()


@contextmanager
def _locked(folder: Path) -> Iterator[None]:
    """An exclusive lock on ``folder`` (``flock`` on the folder itself: no lock file is left behind)."""
    handle = os.open(folder, os.O_RDONLY)
    try:
        fcntl.flock(handle, fcntl.LOCK_EX)
        yield
    finally:
        os.close(handle)  # closing releases the lock


@contextmanager
def atomic_group(paths: Sequence[StrPath]) -> Iterator[list[Path]]:
    """Temporary files for several outputs, renamed onto them together when the block ends without an error.

    The renames happen while every output folder is locked, so two commands writing the same outputs leave
    the whole set of one of them, never one's first file beside the other's second. On an error (or Ctrl-C,
    or SIGTERM with :func:`heatdata.log.terminate_as_interrupt`) every temporary file is removed and no output is
    touched.

    Parameters
    ----------
    paths : sequence of str or Path
        The files to write (distinct).

    Yields
    ------
    list of Path
        Where to write each, in the order of ``paths``.

    Raises
    ------
    OutputError
        A folder cannot be created or locked, or a file cannot be written or renamed.
    """
    outputs = [Path(p) for p in paths]
    temporaries = [_temporary(p) for p in outputs]
    try:
        for path in outputs:
            if path.is_dir():
                raise OutputError(f"{path}: is a folder; give a file name")
            path.parent.mkdir(parents=True, exist_ok=True)
        yield temporaries
        with ExitStack() as stack:
            for folder in sorted({p.parent.resolve() for p in outputs}):  # one order: no two commands deadlock
                stack.enter_context(_locked(folder))
            for temporary, path in zip(temporaries, outputs):
                os.replace(temporary, path)
    except OSError as error:
        for temporary in temporaries:
            _remove(temporary)
        raise OutputError(f"{', '.join(map(str, outputs))}: cannot be written ({_reason(error)})") from None
    except BaseException:
        for temporary in temporaries:
            _remove(temporary)
        raise
