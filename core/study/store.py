"""The study's run files: one ``run-<key>.npz`` per finished run, written atomically, checked when read.

A run file that cannot be read (truncated, a damaged ZIP header byte: ``zipfile`` then raises
``RuntimeError`` "encrypted" or ``NotImplementedError`` "compression method"), belongs to another spec, or
holds arrays of the wrong shape, a NaN where the spectrum has an estimate, or impossible force statistics
is not used: a warning names it and the run is computed again (its file then replaced atomically).

Each run file carries ``digest``, the SHA-256 of its arrays (name, dtype, shape and bytes, in a fixed
order), written with them: a file edited afterwards (a level raised by 50 dB, say, which every check of
shape and range would pass) or written without one no longer matches, and is computed again. The digest
guards against edits and damage, not against someone who recomputes it on purpose.
"""

from __future__ import annotations

import hashlib
import math
import warnings
from pathlib import Path

import numpy as np

from wheelrail.core.files.atomic import atomic_write
from wheelrail.core.study.specs import SUMMARY_SCALARS, RunSpec, RunSummary

_ARRAYS = ("run_key", "band_centres_hz", "levels_db", *SUMMARY_SCALARS)


def cache_path(cache: Path, key: str) -> Path:
    """The run file of run key ``key`` in the folder ``cache``."""
    return cache / f"run-{key[:32]}.npz"


def arrays_digest(arrays: dict) -> str:
    """SHA-256 (hex) of the run file's arrays :data:`_ARRAYS`: each one's name, dtype, shape and bytes."""
    digest = hashlib.sha256()
    for name in _ARRAYS:
        array = np.ascontiguousarray(arrays[name])
        digest.update(f"{name}|{array.dtype.str}|{array.shape}|".encode())
        digest.update(array.tobytes())
    return digest.hexdigest()


def save_cached(cache: Path, summary: RunSummary) -> None:
    """Write ``summary`` and the digest of its arrays to its run file atomically (a reader never sees half a
    file)."""
    arrays = summary.to_arrays()
    atomic_write(
        cache_path(cache, summary.key), lambda handle: np.savez(handle, digest=arrays_digest(arrays), **arrays)
    )


def load_cached(cache: Path, spec: RunSpec) -> RunSummary | None:
    """The stored summary of ``spec``, or None when there is none or it is not usable (with a warning)."""
    path = cache_path(cache, spec.key)
    if not path.exists():
        return None
    try:
        summary = _read(path)
    except Exception as error:  # noqa: BLE001 - any unreadable file is recomputed, whatever zipfile raised
        _ignore(path, f"{type(error).__name__}: {error}")
        return None
    if summary.key != spec.key:
        _ignore(path, "it belongs to another run")
        return None
    problem = summary_problem(summary, spec)
    if problem:
        _ignore(path, problem)
        return None
    return summary


def _read(path: Path) -> RunSummary:
    with np.load(path, allow_pickle=False) as data:
        missing = [name for name in (*_ARRAYS, "digest") if name not in data.files]
        if missing:
            raise KeyError(f"missing arrays {', '.join(missing)}")
        arrays = {name: data[name] for name in _ARRAYS}
        digest = data["digest"]
    if digest.shape != () or str(digest) != arrays_digest(arrays):
        raise ValueError("its content does not match the digest written with it (edited or damaged)")
    for name in ("run_key", *SUMMARY_SCALARS):
        if arrays[name].shape != ():
            raise ValueError(f"{name} has shape {arrays[name].shape}, expected a scalar")
    return RunSummary.from_arrays(arrays)


def summary_problem(summary: RunSummary, spec: RunSpec) -> str:
    """What is wrong with a stored summary of ``spec`` ("" when nothing): shapes, NaN, impossible values.

    The levels must be NaN exactly in the bands the run's record cannot resolve
    (:func:`wheelrail.core.spectra.force.resolved_force_bands` of its steps and time step) and a number elsewhere.
    """
    from wheelrail.core.spectra.force import resolved_force_bands

    scalars = {name: getattr(summary, name) for name in SUMMARY_SCALARS}
    if not all(isinstance(v, int | float) and math.isfinite(v) for v in scalars.values()):
        return "a force statistic is not a finite number"
    n_steps = scalars["n_steps"]
    if n_steps != int(n_steps) or n_steps < 1 or not 0 <= scalars["loss_of_contact_steps"] <= n_steps:
        return "impossible step counts"
    if not (summary.force_min <= summary.force_mean <= summary.force_max and summary.force_std >= 0):
        return "impossible force statistics"
    centres, resolved = resolved_force_bands(int(n_steps), spec.params.run.time_step)
    if summary.band_centres.shape != centres.shape or summary.levels.shape != centres.shape:
        return f"spectrum of shape {summary.levels.shape}, expected {centres.shape}"
    if not np.allclose(summary.band_centres, centres, rtol=1e-12, atol=0.0):
        return "band centres differ from the force spectrum's"
    if np.any(np.isnan(summary.levels[resolved])) or np.any(summary.levels[resolved] == np.inf):
        return "NaN or infinite level in a resolved band"
    if not np.all(np.isnan(summary.levels[~resolved])):
        return "a level in a band the run cannot resolve"
    return ""


def _ignore(path: Path, reason: str) -> None:
    warnings.warn(f"ignoring unusable study run file {path} ({reason}); computing the run again", stacklevel=3)
