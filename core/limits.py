"""Memory bounds of a run: estimate before allocating, refuse with the figure (SPEC.md §7).

A run holds its arrays in memory for its whole length, so its size grows with the number of steps:
a 1e9 m run would try to allocate terabytes and end in a ``MemoryError`` half-way through the set-up.
:func:`check_run_memory` estimates the peak from the run's shape before anything large is allocated and
refuses, in one line with the figure, a run over :func:`memory_limit`.

The estimate (bytes, per element of the run: run-in and the two margins included) is

* ``STEP_BYTES`` = 200 for every model: the loop's history (force, rail displacement, interpolation
  indices and weights), the per-step outputs, the result's copies and the set-up's temporaries;
* ``2 x 8`` bytes per roughness line held (the lines along the track and their interpolation temporary;
  25 lines for ``3d``, 1 otherwise);
* ``2d``: ``2 x 8`` bytes per window column (the bedding window of each step and its temporary);
* ``3d`` keeping its pressure maps: ``4`` bytes (float32) per window element per step; without them the
  run keeps only the last map.

``tests/unit/test_limits.py`` checks it against the peak traced with ``tracemalloc``: measured growth of
the peak per element 192 B (``hertz``), 512 B (``2d``) and 2804 B (``3d`` keeping its maps) against the
estimated 216, 616 and 3100 B; the test asks for an estimate between 1 and 2 times the measured growth. Fixed costs (the
Green's functions, about 35 MB of stationary responses, and their weights, under 1 MB at any accepted
speed) are left out: they do not grow with the run.
"""

from __future__ import annotations

import math
import os

from wheelrail.core.errors import WheelrailError

MEMORY_LIMIT_BYTES = 2 * 1024**3
"""Default largest estimated run size, bytes (2 GiB: two study workers fit on a small machine)."""

MEMORY_LIMIT_ENV = "WHEELRAIL_MEMORY_LIMIT_GB"
"""Environment variable that replaces ``MEMORY_LIMIT_BYTES`` (in GiB) on machines with more memory."""

STEP_BYTES = 200
"""Bytes per element of every run (see the module docstring)."""

LINE_BYTES = 2 * 8
"""Bytes per element and roughness line held."""

WINDOW_COLUMN_BYTES = 2 * 8
"""``2d``: bytes per element and bedding-window column."""

PRESSURE_BYTES = 4
"""``3d`` with its maps kept: bytes per element, step and window element (float32)."""


def memory_limit() -> int:
    """Largest estimated run size, bytes: ``$WHEELRAIL_MEMORY_LIMIT_GB`` GiB if set, else MEMORY_LIMIT_BYTES."""
    text = os.environ.get(MEMORY_LIMIT_ENV)
    if not text:
        return MEMORY_LIMIT_BYTES
    try:
        gib = float(text)
    except ValueError:
        gib = float("nan")
    if not 0 < gib < 1e6:
        raise WheelrailError(f"{MEMORY_LIMIT_ENV}={text!r}: give a memory size in GiB, e.g. 8")
    return int(gib * 1024**3)


def run_memory_bytes(model: str, *, n_elements: float, n_steps: float, n_lines: int, window_columns: int,
                     keep_pressure: bool) -> float:
    """Estimated peak memory of a run that grows with its length, bytes (see the module docstring).

    Parameters
    ----------
    model : str
        Contact model name.
    n_elements : float
        Elements the run holds: run-in, steps and margins (a float, so that an absurd length gives a
        huge or infinite estimate instead of an overflow).
    n_steps : float
        Steps whose results are kept.
    n_lines : int
        Roughness lines held (3d: the window's lines).
    window_columns : int
        Elements of the contact window along the rail.
    keep_pressure : bool
        3d: every pressure map is kept in the result.
    """
    per_element = STEP_BYTES + LINE_BYTES * n_lines
    if model == "2d":
        per_element += WINDOW_COLUMN_BYTES * window_columns
    total = per_element * n_elements
    if model == "3d" and keep_pressure:
        total += PRESSURE_BYTES * n_lines * window_columns * n_steps
    return float(total)


def check_run_memory(model: str, *, n_elements: float, n_steps: float, n_lines: int, window_columns: int,
                     keep_pressure: bool) -> float:
    """:func:`run_memory_bytes`, or a WheelrailError with the figure when it exceeds :func:`memory_limit`."""
    needed = run_memory_bytes(model, n_elements=n_elements, n_steps=n_steps, n_lines=n_lines,
                              window_columns=window_columns, keep_pressure=keep_pressure)
    limit = memory_limit()
    if needed > limit:
        maps = ""
        if model == "3d" and keep_pressure:
            maps_bytes = PRESSURE_BYTES * n_lines * window_columns * n_steps
            maps = f", of which {_gib(maps_bytes)} are the pressure maps kept for the result"
        raise WheelrailError(
            f"a {model} run of {_count(n_steps)} steps needs about {_gib(needed)} of memory{maps}, over the "
            f"{_gib(limit)} limit ({MEMORY_LIMIT_ENV} sets it); shorten the run"
        )
    return needed


def _count(n: float) -> str:
    return f"{n:.4g}" if math.isfinite(n) else "over 1e308"


def _gib(n_bytes: float) -> str:
    if not math.isfinite(n_bytes):
        return "over 1e290 EiB"
    if n_bytes >= 1024**6:
        return f"{n_bytes / 1024**6:.3g} EiB"
    if n_bytes >= 1024**3:
        return f"{n_bytes / 1024**3:.3g} GiB"
    return f"{n_bytes / 1024**2:.3g} MiB"
