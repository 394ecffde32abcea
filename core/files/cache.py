"""Disk cache for expensive, deterministic results (track Green's functions).

Location: ``$WHEELRAIL_CACHE_DIR`` if set, else the user's cache directory (platformdirs); a setting that
names a file is refused in one line. Entries are ``KIND-KEY.npz`` files (KEY: the first 24 hex digits of a
SHA-256 key of everything that affects their content: a format version and every parameter). Each holds its
key, a JSON description (``cache_meta``: what it was computed for, when, how long it took) and a SHA-256
digest of all its arrays (``cache_digest``), and is written atomically (temporary file + rename), so an
interrupted write never leaves a file a later run would trust.

What is trusted: an entry whose stored key matches the file name's and whose arrays hash to the stored
digest. One that cannot be read (any failure: a damaged ZIP flag, method or version byte gives RuntimeError
or NotImplementedError, not only OSError), whose key differs, whose digest is missing or differs (an edit,
a flipped bit) or whose arrays are missing is treated as absent, with a warning, and rebuilt. The digest
detects damage and accidental edits; it is no signature (whoever can write the folder can write a
consistent entry), and arrays are never unpickled.

A cache that cannot be written (a read-only or full folder) never aborts a run: the result is kept in
memory and one warning per folder names ``WHEELRAIL_CACHE_DIR``.

A large entry (a track's Green's functions) can be written in the background (:func:`save_entry_behind`): its
temporary file is made at once (a folder that cannot be written is known, and warned about, before the call
returns), its digest and its arrays are written by a thread of its own, and the caller goes on with the result in
memory. The thread is no daemon, so the interpreter waits for it before the process exits. In this process,
whatever reads the folder waits for the writes under way there first (:func:`load_entry` for its own entry,
:func:`entries`, :func:`clear`); :func:`wait_for_writes` waits for them all, :meth:`PendingEntry.wait` for one.

Bounded: after each write the least recently used entries (by modification time, which every load
refreshes) are removed until the folder's entries take at most ``WHEELRAIL_CACHE_MAX_GB`` (default
``DEFAULT_MAX_GB``); the entry just written is never removed. ``wheelrail cache`` lists and clears them.

Only files the cache wrote are ever removed, known by more than their name: an entry is a file named
``KIND-KEY.npz`` that is a NumPy archive holding the key its name begins (``cache_key``) and a digest
(``cache_digest``), checked before it is listed, evicted or cleared (:func:`written_by_the_cache`); a file
named like one but holding anything else (a user's copy, notes) is no entry and is left alone. Temporaries named
``.wheelrail-NAME.XXXXXXXX.HOST-PID.tmp`` (a write killed half-way, kill -9 during a Green's-function
build, leaves one of up to 210 MB). A temporary is removed when the process of this host that wrote it no
longer runs, or when it is older than ``STALE_TEMPORARY_S`` (other hosts sharing the folder, reused
process ids). Any other file in the folder is left alone.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import threading
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.files.atomic import publish, running, temporary_beside, writer

# in every key: bump when what an entry holds changes without its parameters (2: the track's mesh; 3: the track's
# model mirror-symmetric about its central bay)
FORMAT_VERSION = 3
STALE_TEMPORARY_S = 3600.0  # s: a temporary file of ours this old is a leftover whoever wrote it
DEFAULT_MAX_GB = 4.0  # GB (1e9 bytes): about 19 track entries of 208 MB
_ENTRY_NAME = re.compile(r"^(?P<kind>[a-z0-9]+(?:-[a-z0-9]+)*)-(?P<key>[0-9a-f]{24})\.npz$")
# ours: TEMPORARY_PREFIX + entry name + token + writer (the prefix optional: a name without it is ours too)
_TEMPORARY_NAME = re.compile(
    r"^\.(?:wheelrail-)?[a-z0-9]+(?:-[a-z0-9]+)*-[0-9a-f]{24}\.npz\.[0-9a-f]{8}\.(?P<host>[A-Za-z0-9_-]+)-(?P<pid>\d+)\.tmp$"
)
_INTERNAL = ("cache_digest", "cache_meta")
_DESCRIPTIONS: dict[str, tuple[str, dict]] = {}  # key -> (kind, description) of the keys made in this process
_WARNED_UNWRITABLE: set[str] = set()
_WARNING = threading.Lock()  # held while a folder is checked, noted and warned about: two writers warn once
_PENDING: list[PendingEntry] = []  # this process's writes under way (save_entry_behind)
_PENDING_LOCK = threading.Lock()


def cache_dir() -> Path:
    """The cache folder (created if missing and possible: one that cannot be created, e.g. under a read-only
    folder, is returned as it is and reads as empty, and writing it warns); a WheelrailError naming the setting
    if it names a file or a path through one."""
    env = os.environ.get("WHEELRAIL_CACHE_DIR")
    if env:
        path = Path(env).expanduser()
    else:
        from platformdirs import user_cache_dir

        path = Path(user_cache_dir("wheelrail"))
    where = f"WHEELRAIL_CACHE_DIR={env}" if env else f"the cache folder {path}"
    if path.exists() and not path.is_dir():
        raise WheelrailError(f"{where} is a file, not a folder; set WHEELRAIL_CACHE_DIR to a folder")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError):  # a file on the way (e.g. WHEELRAIL_CACHE_DIR=file/sub)
        raise WheelrailError(
            f"{where} cannot be a folder: part of its path is a file; set WHEELRAIL_CACHE_DIR to a folder"
        ) from None
    except OSError:  # e.g. permission denied: nothing cached; save_entry says so once
        pass
    return path


def max_bytes() -> int:
    """The size limit of the cache's entries, bytes (``WHEELRAIL_CACHE_MAX_GB``, default ``DEFAULT_MAX_GB``)."""
    text = os.environ.get("WHEELRAIL_CACHE_MAX_GB", "").strip()
    if not text:
        return int(DEFAULT_MAX_GB * 1e9)
    try:
        value = float(text) if "_" not in text else math.nan  # float() would read "1_0" as 10
    except ValueError:
        value = math.nan
    if not (0.0 < value < 1e9):
        raise WheelrailError(
            f"WHEELRAIL_CACHE_MAX_GB={text}: the cache's size limit must be a number of GB above 0 "
            f"(default {DEFAULT_MAX_GB:g})"
        )
    return int(value * 1e9)


def cache_key(kind: str, description: dict) -> str:
    """Stable SHA-256 key of a JSON-able description (sorted keys, floats via repr)."""
    text = json.dumps({"kind": kind, "version": FORMAT_VERSION, **description}, sort_keys=True, default=repr)
    key = hashlib.sha256(text.encode()).hexdigest()
    # remembered so that save_entry can describe the entry (``wheelrail cache`` lists it); small dicts, the
    # newest few hundred kept (a long-lived explorer sees a new key per wheel and time step)
    _DESCRIPTIONS.pop(key, None)
    _DESCRIPTIONS[key] = (kind, json.loads(json.dumps(description, default=repr)))
    while len(_DESCRIPTIONS) > 256:
        del _DESCRIPTIONS[next(iter(_DESCRIPTIONS))]
    return key


def entry_path(kind: str, key: str) -> Path:
    """The file of the entry of ``kind`` and ``key``, once this process's write of it under way, if any, has ended
    (:func:`save_entry_behind`): it names the complete entry or none."""
    path = cache_dir() / f"{kind}-{key[:24]}.npz"
    _wait_for(lambda pending: pending.path == path)
    return path


def array_digest(arrays: dict[str, np.ndarray], digest=None) -> str:
    """SHA-256 (hex) of every array's name, dtype, shape and bytes (sorted by name), fed into ``digest`` (a
    ``hashlib.sha256`` object that already holds what precedes the arrays, e.g. a run file's metadata) or a new
    one: a cache entry's digest, and a run file's (``run_file.content_digest``)."""
    digest = hashlib.sha256() if digest is None else digest
    for name in sorted(arrays):
        array = np.ascontiguousarray(arrays[name])
        digest.update(f"{name}|{array.dtype.str}|{array.shape}|".encode())
        digest.update(memoryview(array).cast("B") if array.size else b"")
    return digest.hexdigest()


def load_entry(kind: str, key: str, required: tuple[str, ...]) -> dict[str, np.ndarray] | None:
    """Arrays of a valid cache entry, or None if it is absent, corrupt, tampered with or stale.

    A valid entry's modification time is set to now (the cache's least-recently-used order)."""
    max_bytes()  # a bad WHEELRAIL_CACHE_MAX_GB is refused at the first lookup, before anything is computed
    path = entry_path(kind, key)  # this process's write of it, if under way, ended
    remove_stale_temporaries(path.parent)
    if not path.exists():
        return None
    try:
        arrays = _read(path, key, required)
    except FileNotFoundError:  # removed meanwhile (another process cleared or evicted it)
        return None
    except Exception as error:  # noqa: BLE001 - any unreadable entry is rebuilt, whatever the reader raised
        warnings.warn(f"ignoring unusable cache entry {path}: {error}; rebuilding", stacklevel=2)
        try:
            path.unlink()
        except OSError:
            pass
        return None
    try:
        os.utime(path)  # last used: now
    except OSError:  # a read-only folder: the order is only less exact
        pass
    return arrays


def _read(path: Path, key: str, required: tuple[str, ...]) -> dict[str, np.ndarray]:
    with np.load(path, allow_pickle=False) as data:
        if str(data["cache_key"]) != key:
            raise ValueError("stale entry (key differs)")
        missing = [name for name in required if name not in data.files]
        if missing:
            raise ValueError(f"missing arrays {missing}")
        arrays = {name: data[name] for name in data.files}
    stored = str(arrays.pop("cache_digest", ""))
    if not stored:
        raise ValueError("no digest (written by an earlier wheelrail)")
    if array_digest(arrays) != stored:
        raise ValueError("its arrays do not match its digest (damaged or edited)")
    arrays.pop("cache_meta", None)
    return arrays


def save_entry(kind: str, key: str, arrays: dict[str, np.ndarray], *, info: dict | None = None) -> Path | None:
    """Write a cache entry atomically and keep the cache within its limit; returns its path.

    ``info``: extra JSON-able facts for its description (e.g. ``compute_s``). If the folder cannot be
    written (read-only, full, ...), warns once per folder and returns None: the caller keeps its result.
    """
    folder = cache_dir()
    path = folder / f"{kind}-{key[:24]}.npz"
    temporary = _claim(folder, path)
    return None if temporary is None else _write(key, arrays, _meta(kind, key, info), temporary, path)


class PendingEntry:
    """A cache entry being written by a thread of its own (:func:`save_entry_behind`).

    Attributes
    ----------
    path : Path
        Where the entry appears, complete, when the write ends (if it can be written).
    """

    def __init__(self, path: Path, thread: threading.Thread | None = None) -> None:
        self.path = path
        self._thread = thread
        self._written: Path | None = None

    def done(self) -> bool:
        """Whether the write has ended (written or not)."""
        return self._thread is None or not self._thread.is_alive()

    def wait(self) -> Path | None:
        """Wait for the write to end; the entry's path, or None if it could not be written (warned about)."""
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join()
        return self._written


def save_entry_behind(kind: str, key: str, arrays: dict[str, np.ndarray], *, info: dict | None = None) -> PendingEntry:
    """:func:`save_entry` with the digest and the write in a thread of its own: returns at once.

    The temporary file is made, the description taken and the size limit read before it returns (a folder that
    cannot be written is warned about now, and the returned entry is done, its path None). The thread is no
    daemon: the process ends only once the entry is written. ``arrays`` must not change until it is.

    Returns
    -------
    PendingEntry
        The write: :meth:`PendingEntry.wait` gives the entry's path once it is on disk.
    """
    max_bytes()  # a bad WHEELRAIL_CACHE_MAX_GB is refused here, in the caller's thread
    folder = cache_dir()
    path = folder / f"{kind}-{key[:24]}.npz"
    pending = PendingEntry(path)
    temporary = _claim(folder, path)
    if temporary is None:
        return pending
    meta = _meta(kind, key, info)

    def write() -> None:
        try:
            pending._written = _write(key, arrays, meta, temporary, path)
        except Exception as error:  # noqa: BLE001 - a thread's error would print a traceback: one line instead
            temporary.unlink(missing_ok=True)
            warnings.warn(f"could not write the cache entry {path}: {error}", stacklevel=1)
        finally:
            with _PENDING_LOCK:
                _PENDING.remove(pending)

    # not a daemon: the interpreter joins it before the process exits
    pending._thread = threading.Thread(target=write, name=f"wheelrail-cache-write {path.name}", daemon=False)
    with _PENDING_LOCK:  # listed and started together: a reader never joins a thread not yet started
        _PENDING.append(pending)
        try:
            pending._thread.start()
        except RuntimeError:  # no new thread to be had: written below, in the caller's
            pending._thread = None
    if pending._thread is None:
        write()
    return pending


def wait_for_writes(folder: Path | None = None) -> None:
    """Wait for this process's cache writes under way (:func:`save_entry_behind`), into ``folder`` only if given
    (a write does not wait for itself)."""
    folder = None if folder is None else Path(folder)
    _wait_for(lambda pending: folder is None or pending.path.parent == folder)


def _wait_for(which) -> None:
    """Wait for the writes under way for which ``which(pending)`` is true."""
    with _PENDING_LOCK:
        found = [pending for pending in _PENDING if which(pending)]
    for pending in found:
        pending.wait()


def _claim(folder: Path, path: Path) -> Path | None:
    """A new temporary file beside ``path`` for its entry, or None (warned about) if the folder cannot be
    written."""
    try:
        remove_stale_temporaries(folder)
        return temporary_beside(path)  # .wheelrail-NAME.XXXXXXXX.HOST-PID.tmp
    except OSError as error:
        _unwritable(folder, error)
        return None


def _write(key: str, arrays: dict[str, np.ndarray], meta: str, temporary: Path, path: Path) -> Path | None:
    """The entry's digest and arrays written into ``temporary``, published as ``path``, the cache evicted down to
    its limit; ``path``, or None (warned about) if it could not be written."""
    try:
        try:
            with open(temporary, "wb") as handle:
                stored = {**arrays, "cache_key": np.array(key), "cache_meta": np.array(meta)}
                np.savez(handle, cache_digest=np.array(array_digest(stored)), **stored)
            publish(temporary, path)
        finally:
            temporary.unlink(missing_ok=True)
    except OSError as error:
        _unwritable(path.parent, error)
        return None
    try:
        evict(keep=path)
    except OSError:  # the folder cannot be listed or changed now: the next write evicts
        pass
    return path


def _unwritable(folder: Path, error: OSError) -> None:
    """The one warning per folder that the cache cannot be written there."""
    with _WARNING:
        if str(folder) in _WARNED_UNWRITABLE:
            return
        _WARNED_UNWRITABLE.add(str(folder))
        warnings.warn(
            f"could not write the cache in {folder} ({error.strerror or error}): results are kept in memory "
            "for this run only; set WHEELRAIL_CACHE_DIR to a writable folder",
            stacklevel=4,
        )


def _meta(kind: str, key: str, info: dict | None) -> str:
    from wheelrail import __version__

    described = _DESCRIPTIONS.get(key)
    return json.dumps(
        {
            "kind": kind,
            "key": key,
            "written": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            "wheelrail": __version__,
            "description": described[1] if described and described[0] == kind else None,
            **(info or {}),
        },
        default=repr,
    )


@dataclass(frozen=True)
class Entry:
    """One file of the cache: ``kind`` and ``key`` (its 24 hex digits) from its name, ``size`` in bytes,
    ``last_used`` (modification time, s since the epoch) and its stored description (None if unreadable)."""

    path: Path
    kind: str
    key: str
    size: int
    last_used: float
    meta: dict | None


def written_by_the_cache(path: Path, key: str) -> bool:
    """Whether ``path`` is an entry the cache wrote: a NumPy archive holding a digest and a stored key that
    begins with ``key`` (the 24 hex digits of its name). Reads the archive's directory and its key, a few kB."""
    try:
        with np.load(path, allow_pickle=False) as data:
            if not isinstance(data, np.lib.npyio.NpzFile) or not {"cache_key", "cache_digest"} <= set(data.files):
                return False
            return str(data["cache_key"]).startswith(key)
    except Exception:  # noqa: BLE001 - whatever else it is, it is not an entry we can vouch for
        return False


def entries(folder: Path | None = None, *, describe: bool = False) -> list[Entry]:
    """The cache's entries (files named as this module names them and holding their key:
    :func:`written_by_the_cache`), least recently used first.

    ``describe``: read each entry's stored description (a few kB from its ZIP; None for an old entry). This
    process's writes under way into the folder are waited for (:func:`wait_for_writes`)."""
    folder = cache_dir() if folder is None else Path(folder)
    wait_for_writes(folder)
    return _listed(folder, describe)


def _listed(folder: Path, describe: bool) -> list[Entry]:
    """:func:`entries` without waiting for the writes under way (what a write's own eviction lists)."""
    found = []
    for path in folder.iterdir() if folder.is_dir() else ():
        match = _ENTRY_NAME.match(path.name)
        if match is None or not written_by_the_cache(path, match["key"]):
            continue
        try:
            stat = path.stat()
        except OSError:  # removed meanwhile
            continue
        meta = stored_meta(path) if describe else None
        found.append(Entry(path, match["kind"], match["key"], stat.st_size, stat.st_mtime, meta))
    return sorted(found, key=lambda entry: (entry.last_used, entry.path.name))


def stored_meta(path: Path) -> dict | None:
    """The description stored in the entry at ``path`` (None if it has none or cannot be read)."""
    try:
        with np.load(path, allow_pickle=False) as data:
            return json.loads(str(data["cache_meta"])) if "cache_meta" in data.files else None
    except Exception:  # noqa: BLE001 - a damaged entry is listed without its description
        return None


def evict(limit: int | None = None, *, keep: Path | None = None) -> list[Path]:
    """Remove least recently used entries until they take at most ``limit`` bytes (default ``max_bytes()``),
    never ``keep``; returns the removed files. Writes under way are not waited for (a write evicts when it ends)."""
    limit = max_bytes() if limit is None else limit
    found = _listed(keep.parent if keep is not None else cache_dir(), False)
    total = sum(entry.size for entry in found)
    removed = []
    for entry in found:
        if total <= limit:
            break
        if keep is not None and entry.path == keep:
            continue
        try:
            entry.path.unlink()
        except FileNotFoundError:
            pass
        except OSError:
            continue
        total -= entry.size
        removed.append(entry.path)
    return removed


def clear(kind: str | None = None) -> list[Path]:
    """Remove the cache's entries (of ``kind`` only, if given) and the temporaries of finished writes (this
    process's writes under way are waited for, then removed)."""
    wait_for_writes(cache_dir())
    removed = remove_stale_temporaries(cache_dir())
    for entry in entries():
        if kind is None or entry.kind == kind:
            try:
                entry.path.unlink()
                removed.append(entry.path)
            except OSError:  # removed meanwhile, or a read-only folder (the entry stays listed)
                continue
    return removed


def remove_stale_temporaries(folder: Path, now: float | None = None) -> list[Path]:
    """Delete the leftover temporary files of interrupted cache writes in ``folder``; returns those deleted.

    Only the cache's own temporaries (named ``.wheelrail-NAME.XXXXXXXX.HOST-PID.tmp``) are considered; one is
    stale when the process of this host that wrote it no longer runs, or when it is older than
    ``STALE_TEMPORARY_S``.
    """
    now = time.time() if now is None else now
    host = writer().rsplit("-", 1)[0]
    removed = []
    for temporary in Path(folder).glob(".*.tmp"):
        match = _TEMPORARY_NAME.match(temporary.name)
        if match is None:
            continue  # not ours: never touched
        try:
            dead = match["host"] == host and not running(int(match["pid"]))
            if dead or now - temporary.stat().st_mtime > STALE_TEMPORARY_S:
                temporary.unlink()
                removed.append(temporary)
        except OSError:  # removed meanwhile by another process
            continue
    return removed
