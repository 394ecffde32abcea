"""Disk cache for expensive, deterministic results (track Green's functions).

Location: ``$WHEELRAIL_CACHE_DIR`` if set, else the user's cache directory (platformdirs). Entries are
``.npz`` files named by a SHA-256 key of everything that affects their content (a format version and
every parameter), hold that key inside, and are written atomically (temporary file + rename), so an
interrupted write never leaves a file a later run would trust. An entry that cannot be read, whose
stored key differs or whose arrays are missing is treated as absent and rebuilt (SPEC.md §7).
"""

from __future__ import annotations

import hashlib
import json
import os
import warnings
import zipfile
from pathlib import Path

import numpy as np

from wheelrail.core.atomic import atomic_write

FORMAT_VERSION = 1


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
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as error:
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
    atomic_write(path, lambda handle: np.savez(handle, cache_key=np.array(key), **arrays))
    return path
