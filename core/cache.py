"""Disk cache for expensive, deterministic results (track Green's functions).

Location: ``$WHEELRAIL_CACHE_DIR`` if set, else the user's cache directory (platformdirs). Entries are
``.npz`` files named by a SHA-256 key of everything that affects their content (a format version and
every parameter), hold that key inside, and are written atomically (temporary file + rename), so an
interrupted write never leaves a file a later run would trust. An entry that cannot be read (any
failure: a damaged ZIP flag, method or version byte gives RuntimeError or NotImplementedError, not only
OSError), whose stored key differs or whose arrays are missing is treated as absent, with a warning,
and rebuilt.

A write killed half-way (kill -9 during a Green's-function build) leaves its temporary file, up to
35 MB, hidden beside the entries. Temporaries are named after the process that writes them
(``.NAME.XXXX.HOST-PID.tmp``); every lookup removes those of a process of this host that no longer
runs, and any older than ``STALE_TEMPORARY_S`` (a write takes seconds; this also covers other hosts
sharing the folder and reused process ids).
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import socket
import time
import warnings
from pathlib import Path

import numpy as np

from wheelrail.core.atomic import publish, temporary_beside

FORMAT_VERSION = 1
STALE_TEMPORARY_S = 3600.0  # s: a temporary file this old is a leftover whoever wrote it


def cache_dir() -> Path:
    """The cache folder (created if missing)."""
    env = os.environ.get("WHEELRAIL_CACHE_DIR")
    if env:
        path = Path(env).expanduser()
    else:
        from platformdirs import user_cache_dir

        path = Path(user_cache_dir("wheelrail"))
    path.mkdir(parents=True, exist_ok=True)
    return path


def cache_key(kind: str, description: dict) -> str:
    """Stable SHA-256 key of a JSON-able description (sorted keys, floats via repr)."""
    text = json.dumps({"kind": kind, "version": FORMAT_VERSION, **description}, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()


def entry_path(kind: str, key: str) -> Path:
    return cache_dir() / f"{kind}-{key[:24]}.npz"


def load_entry(kind: str, key: str, required: tuple[str, ...]) -> dict[str, np.ndarray] | None:
    """Arrays of a valid cache entry, or None if it is absent, corrupt or stale."""
    path = entry_path(kind, key)
    remove_stale_temporaries(path.parent)
    if not path.exists():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            if str(data["cache_key"]) != key:
                raise ValueError("stale entry (key differs)")
            missing = [name for name in required if name not in data.files]
            if missing:
                raise ValueError(f"missing arrays {missing}")
            arrays = {name: data[name] for name in data.files}
    except Exception as error:  # noqa: BLE001 - any unreadable entry is rebuilt, whatever the reader raised
        warnings.warn(f"ignoring unusable cache entry {path}: {error}; rebuilding", stacklevel=2)
        try:
            path.unlink()
        except OSError:
            pass
        return None
    return arrays


def save_entry(kind: str, key: str, arrays: dict[str, np.ndarray]) -> Path:
    """Write a cache entry atomically; returns its path."""
    path = entry_path(kind, key)
    remove_stale_temporaries(path.parent)
    temporary = temporary_beside(path, suffix=f".{_writer()}.tmp")
    try:
        with open(temporary, "wb") as handle:
            np.savez(handle, cache_key=np.array(key), **arrays)
        return publish(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)


def _writer() -> str:
    """HOST-PID of this process, as written into its temporary files' names."""
    host = re.sub(r"[^A-Za-z0-9_-]", "_", socket.gethostname()) or "host"
    return f"{host}-{os.getpid()}"


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # e.g. PermissionError: it exists, owned by someone else
        return True
    return True


def remove_stale_temporaries(folder: Path, now: float | None = None) -> list[Path]:
    """Delete the leftover temporary files of interrupted writes in ``folder``; returns those deleted.

    A temporary is stale when the process of this host that wrote it no longer runs, or when it is older
    than ``STALE_TEMPORARY_S``.
    """
    now = time.time() if now is None else now
    host = _writer().rsplit("-", 1)[0]
    removed = []
    for temporary in Path(folder).glob(".*.tmp"):
        match = re.search(r"\.([A-Za-z0-9_-]+)-(\d+)\.tmp$", temporary.name)
        try:
            dead = match is not None and match.group(1) == host and not _alive(int(match.group(2)))
            if dead or now - temporary.stat().st_mtime > STALE_TEMPORARY_S:
                temporary.unlink()
                removed.append(temporary)
        except OSError:  # removed meanwhile by another process
            continue
    return removed
