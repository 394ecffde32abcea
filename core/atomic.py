"""Atomic file writes: a temporary file in the target folder, renamed over the target when complete.

An interrupted write never leaves a half-written file under the final name that a later run would trust
(caches, study results, exported data). The published file gets ordinary permissions (0666 less the
umask): the temporary file is created with mode 0666 and the kernel applies the umask, as for any new file.
The umask is never read or changed (``os.umask`` sets it for the whole process: racy when threads write).
"""

from __future__ import annotations

import os
import secrets
from collections.abc import Callable
from pathlib import Path


def temporary_beside(path: str | os.PathLike, suffix: str = ".tmp") -> Path:
    """Create an empty temporary file in the folder of ``path`` (hidden, named after it) and return it."""
    path = Path(path)
    for _ in range(100):
        temporary = path.parent / f".{path.name}.{secrets.token_hex(4)}{suffix}"
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
    try:
        with open(temporary, mode, **open_args) as handle:
            write(handle)
        return publish(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)
