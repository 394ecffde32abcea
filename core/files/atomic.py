"""Atomic file writes: a temporary file in the target folder, renamed over the target when complete.

An interrupted write never leaves a half-written file under the final name that a later run would trust
(caches, study results, exported data). The published file gets ordinary permissions (0666 less the
umask): the temporary file is created with mode 0666 and the kernel applies the umask, as for any new file.
The umask is never read or changed (``os.umask`` sets it for the whole process: racy when threads write).

A command that writes several files (``filters --csv F --plot G``) writes them in an :func:`all_or_none` block:
each is renamed into place only once every one is complete, so a full disk or a failed figure leaves none of
them, not a table without its figure. A file that cannot be written is one :class:`WheelrailError` naming it
and the reason ("no space left on device writing r.npz"); its temporary file is removed.

A temporary file is named ``.wheelrail-NAME.XXXXXXXX.HOST-PID.tmp`` (:func:`temporary_beside`): hidden, ours by
its prefix, and its writer's. A writer killed outright (``kill -9``, a power cut) cannot remove its own; the
next write into that folder removes those of this host whose process no longer runs
(:func:`remove_stale_temporaries`), never a file named otherwise, written on another host, or of a process
still running.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import re
import secrets
import socket
from collections.abc import Callable, Iterator
from pathlib import Path

from wheelrail.core.errors import WheelrailError

TEMPORARY_PREFIX = ".wheelrail-"
_TEMPORARY_NAME = re.compile(r"^\.wheelrail-.+\.[0-9a-f]{8}\.(?P<host>[A-Za-z0-9_-]+)-(?P<pid>\d+)\.tmp$")
_SWEPT: set[str] = set()  # the folders whose stale temporaries this process has removed

# the (temporary, final path) pairs of the innermost all_or_none block, or None outside one
_STAGED: contextvars.ContextVar[list[tuple[Path, Path]] | None] = contextvars.ContextVar(
    "wheelrail_atomic_staged", default=None
)


def writer() -> str:
    """HOST-PID of this process, as its temporary files' names carry it."""
    host = re.sub(r"[^A-Za-z0-9_-]", "_", socket.gethostname()) or "host"
    return f"{host}-{os.getpid()}"


def temporary_beside(path: str | os.PathLike) -> Path:
    """Create an empty temporary file in the folder of ``path``, named ``.wheelrail-NAME.XXXXXXXX.HOST-PID.tmp``
    after it and this process (module docstring), and return it."""
    path = Path(path)
    for _ in range(100):
        temporary = path.parent / f"{TEMPORARY_PREFIX}{path.name}.{secrets.token_hex(4)}.{writer()}.tmp"
        try:
            fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)  # the kernel applies the umask
        except FileExistsError:
            continue
        os.close(fd)
        return temporary
    raise FileExistsError(f"no free temporary name beside {path}")


def same_file(a: str | os.PathLike, b: str | os.PathLike) -> bool:
    """Whether paths ``a`` and ``b`` name the same file, however spelled (relative, ``..``, symbolic or hard
    links): the same device and inode when both exist, else the same resolved path."""
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist (yet): compare where they would be
        return Path(a).resolve() == Path(b).resolve()


def refuse_inputs(outputs, inputs) -> None:
    """One WheelrailError if any of ``outputs`` is one of ``inputs`` (:func:`same_file`): writing it would
    destroy the input. Inputs that are not existing files (a bundled set's name, a roughness object) are
    skipped."""
    sources = [Path(item) for item in inputs if isinstance(item, str | os.PathLike) and Path(item).is_file()]
    for output in outputs:
        for source in sources:
            if same_file(output, source):
                raise WheelrailError(
                    f"{output} is the input file {source}: writing it would destroy the input; choose another "
                    "output name or folder"
                )


def running(pid: int) -> bool:
    """Whether a process ``pid`` runs on this host (one we may not signal runs): is a temporary's writer alive."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # e.g. PermissionError: it exists, owned by someone else
        return True
    return True


def stale_temporary(path: Path) -> bool:
    """Whether ``path`` is a temporary file of ours (:func:`temporary_beside`) whose writer, a process of this
    host, no longer runs."""
    match = _TEMPORARY_NAME.match(path.name)
    if match is None or match["host"] != writer().rsplit("-", 1)[0]:
        return False
    pid = int(match["pid"])
    return pid != os.getpid() and not running(pid)


def remove_stale_temporaries(folder: str | os.PathLike) -> list[Path]:
    """Remove the temporary files in ``folder`` left by writers of this host that were killed
    (:func:`stale_temporary`); returns them. Any other file is left alone."""
    removed = []
    try:
        found = list(Path(folder).glob(f"{TEMPORARY_PREFIX}*.tmp"))
    except OSError:
        return removed
    for path in found:
        try:
            if stale_temporary(path) and path.is_file() and not path.is_symlink():
                path.unlink()
                removed.append(path)
        except OSError:  # removed meanwhile, or a read-only folder: nothing to do
            continue
    return removed


def _sweep_once(folder: Path) -> None:
    """:func:`remove_stale_temporaries` in ``folder`` the first time this process writes there."""
    key = os.path.abspath(folder)
    if key not in _SWEPT:
        _SWEPT.add(key)
        remove_stale_temporaries(folder)


def write_failed(error: OSError, path: str | os.PathLike) -> WheelrailError:
    """The one-line error of a file that could not be written: "no space left on device writing r.npz"."""
    reason = (error.strerror or str(error) or type(error).__name__).lower()
    return WheelrailError(f"{reason} writing {path}")


def publish(temporary: str | os.PathLike, path: str | os.PathLike) -> Path:
    """Rename ``temporary`` (made by :func:`temporary_beside`) over ``path`` (atomic on one filesystem)."""
    os.replace(temporary, path)
    return Path(path)


def atomic_write(path: str | os.PathLike, write: Callable, mode: str = "wb", **open_args) -> Path:
    """Write ``path`` atomically: ``write(handle)`` fills a temporary file opened with ``mode``.

    Parameters
    ----------
    path : str or path
        Final file name; its folder must exist.
    write : callable
        Called with the open file object of the temporary file.
    mode : str
        ``open`` mode of the temporary file ("wb" or "w").
    **open_args
        Extra ``open`` arguments (e.g. ``newline=""``, ``encoding="utf-8"``).

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    WheelrailError
        If the file cannot be written (a full disk, a read-only folder): one line naming ``path`` and the
        reason (:func:`write_failed`); the temporary file is removed.
    """
    _sweep_once(Path(path).parent)
    try:
        temporary = temporary_beside(path)
    except OSError as error:
        raise write_failed(error, path) from error
    try:
        with open(temporary, mode, **open_args) as handle:
            write(handle)
    except OSError as error:
        temporary.unlink(missing_ok=True)
        raise write_failed(error, path) from error
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
    return stage(temporary, path)


def stage(temporary: str | os.PathLike, path: str | os.PathLike) -> Path:
    """Publish a completed ``temporary`` file as ``path``: at once, or, inside an :func:`all_or_none` block,
    when the block ends without an error (the block removes it otherwise)."""
    staged = _STAGED.get()
    if staged is not None:
        staged.append((Path(temporary), Path(path)))
        return Path(path)
    try:
        return publish(temporary, path)
    except OSError as error:
        raise write_failed(error, path) from error
    finally:
        Path(temporary).unlink(missing_ok=True)


@contextlib.contextmanager
def all_or_none() -> Iterator[None]:
    """Files written with :func:`atomic_write` (or given to :func:`stage`) in this block appear together when
    it ends without an error; on an error none of them does (their temporary files are removed, earlier files
    under their names are left as they were). Renaming the completed files needs no space, so a full disk
    fails while writing, before anything is renamed."""
    staged: list[tuple[Path, Path]] = []
    token = _STAGED.set(staged)
    try:
        yield
    except BaseException:
        for temporary, _ in staged:
            temporary.unlink(missing_ok=True)
        raise
    finally:
        _STAGED.reset(token)
    published: list[Path] = []
    current = None
    try:
        for temporary, current in staged:
            published.append(publish(temporary, current))
    except BaseException as error:  # a rename refused (rare): remove what this block wrote, leave no partial set
        for temporary, _ in staged:
            temporary.unlink(missing_ok=True)
        for path in published:
            path.unlink(missing_ok=True)
        if isinstance(error, OSError):
            raise write_failed(error, current) from error
        raise
