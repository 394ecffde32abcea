"""Atomic file writes: a temporary file in the target folder, renamed over the target when complete.

An interrupted write never leaves a half-written file under the final name that a later run would trust
(caches, study results, exported data). The published file gets ordinary permissions (0666 less the
umask): the temporary file is created with mode 0666 and the kernel applies the umask, as for any new file.
The umask is never read or changed (``os.umask`` sets it for the whole process: racy when threads write).

A command that writes several files (``filters --csv F --plot G``) writes them in an :func:`all_or_none` block:
each is renamed into place only once every one is complete, so a full disk or a failed figure leaves none of
them, not a table without its figure.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import secrets
from collections.abc import Callable, Iterator
from pathlib import Path

# the (temporary, final path) pairs of the innermost all_or_none block, or None outside one
_STAGED: contextvars.ContextVar[list[tuple[Path, Path]] | None] = contextvars.ContextVar(
    "wheelrail_atomic_staged", default=None
)


def temporary_beside(path: str | os.PathLike, suffix: str = ".tmp", *, prefix: str = ".") -> Path:
    """Create an empty temporary file in the folder of ``path`` (hidden, named ``PREFIX NAME.XXXXXXXX SUFFIX``
    after it) and return it."""
    path = Path(path)
    for _ in range(100):
        temporary = path.parent / f"{prefix}{path.name}.{secrets.token_hex(4)}{suffix}"
        try:
            fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)  # the kernel applies the umask
        except FileExistsError:
            continue
        os.close(fd)
        return temporary
    raise FileExistsError(f"no free temporary name beside {path}")


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
    """
    temporary = temporary_beside(path)
    staged = _STAGED.get()
    try:
        with open(temporary, mode, **open_args) as handle:
            write(handle)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
    if staged is not None:  # published when the enclosing all_or_none block ends
        staged.append((temporary, Path(path)))
        return Path(path)
    try:
        return publish(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)


@contextlib.contextmanager
def all_or_none() -> Iterator[None]:
    """Files written with :func:`atomic_write` in this block appear together when it ends without an error;
    on an error none of them does (their temporary files are removed, earlier files under their names are
    left as they were). Renaming the completed files needs no space, so a full disk fails while writing,
    before anything is renamed."""
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
    try:
        for temporary, path in staged:
            published.append(publish(temporary, path))
    except BaseException:  # a rename refused (rare): remove what this block wrote, leave no partial set
        for temporary, _ in staged:
            temporary.unlink(missing_ok=True)
        for path in published:
            path.unlink(missing_ok=True)
        raise
