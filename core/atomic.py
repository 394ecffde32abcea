"""Atomic file writes: a temporary file in the target folder, renamed over the target when complete.

An interrupted write never leaves a half-written file under the final name that a later run would trust
(SPEC.md §7: caches, study results, exported data). The published file gets ordinary permissions
(0666 less the umask), not the private 0600 that ``tempfile.mkstemp`` creates.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from pathlib import Path


def temporary_beside(path: str | os.PathLike, suffix: str = ".tmp") -> Path:
    """Create an empty temporary file in the folder of ``path`` (hidden, named after it) and return it."""
    path = Path(path)
    fd, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix, dir=path.parent)
    os.close(fd)
    return Path(temporary)


def publish(temporary: str | os.PathLike, path: str | os.PathLike) -> Path:
    """Give ``temporary`` ordinary permissions and rename it over ``path`` (atomic on one filesystem)."""
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(temporary, 0o666 & ~umask)
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
