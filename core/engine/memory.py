"""Memory bounds of a run: estimate before allocating, refuse with the figure.

A run holds its arrays in memory for its whole length, so its size grows with the number of steps:
a 1e9 m run would try to allocate terabytes and end in a ``MemoryError`` half-way through the set-up.
:func:`check_run_memory` estimates the peak from the run's shape before anything large is allocated and
refuses, in one line with the figure, a run over :func:`memory_limit`.

The estimate (bytes, per element of the run: run-in and the two margins included) is

* ``STEP_BYTES`` = 200 for every model: the loop's history (force, rail displacement, interpolation
  indices and weights), the per-step outputs, the result's copies and the set-up's temporaries;
* ``2 x 8`` bytes per roughness line held (the lines along the track and their interpolation temporary;
  25 lines for ``3d``, 1 otherwise);
* a law that keeps a window per step (the bedding of ``2d``, ``ContactLaw.memory_columns``): ``2 x 8`` bytes
  per window column (the window of each step and its temporary);
* a pressure-map model (``3d``) keeping its maps: ``4`` bytes (float32) per window element per step;
  without them the run keeps only the last map.

Costs that do not grow with the run (the Green's functions, the 3D window's influence matrix) are left out.
``tests/unit/test_limits.py`` holds the estimate between 1 and 2 times the peak traced with ``tracemalloc``
(the measured figures: the documentation's benchmarks page, "Memory of a run").
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


def run_memory_bytes(
    *, n_elements: float, n_steps: float, n_lines: int, window_columns: int, pressure_elements: int
) -> float:
    """Estimated peak memory of a run that grows with its length, bytes (see the module docstring).

    Parameters
    ----------
    n_elements : float
        Elements the run holds: run-in, steps and margins (a float, so that an absurd length gives a
        huge or infinite estimate instead of an overflow).
    n_steps : float
        Steps whose results are kept.
    n_lines : int
        Roughness lines held (a lateral window's lines, else 1).
    window_columns : int
        Columns of the bedding window held for each step (the ``2d`` model), else 0.
    pressure_elements : int
        Elements of each pressure map kept in the result (0 when none are kept).
    """
    per_element = STEP_BYTES + LINE_BYTES * n_lines + WINDOW_COLUMN_BYTES * window_columns
    maps = PRESSURE_BYTES * pressure_elements * n_steps if pressure_elements else 0.0  # no 0 * inf = nan
    return float(per_element * n_elements + maps)


def check_run_memory(entry, params, length, run_in_length, keep_pressure: bool) -> float:
    """Estimate a run's memory before anything is allocated; WheelrailError with the figure over the limit.

    Parameters
    ----------
    entry : wheelrail.core.models.ModelEntry
        The contact model (its ``name`` and ``traits``).
    params : ModelParameters
        The run's parameters (element size).
    length, run_in_length : float
        Run and run-in lengths, m. A length that is no positive number is left to the run's own checks.
    keep_pressure : bool
        Every pressure map of a model that has them is kept in the result.

    Returns
    -------
    float
        The estimate, bytes (upper bound: the window counted at its full 25 lines).
    """
    from wheelrail.core.engine.laws.base import law_class
    from wheelrail.core.engine.track_lines import WINDOW_HALF_WIDTH, run_margin

    if isinstance(length, bool) or not isinstance(length, int | float) or not length > 0:
        return 0.0
    dx = params.run.element_size
    width = 2 * int(round(WINDOW_HALF_WIDTH / dx)) + 1
    traits = entry.traits
    n_lines = width if traits.lateral_window else 1
    n_steps = length / dx
    maps = n_lines * width if traits.pressure_map and keep_pressure else 0
    needed = run_memory_bytes(
        n_elements=(length + 2 * run_margin(dx) + run_in_length) / dx,
        n_steps=n_steps,
        n_lines=n_lines,
        window_columns=law_class(traits).memory_columns(width),
        pressure_elements=maps,
    )
    limit = memory_limit()
    if not needed <= limit:
        kept = (
            f", of which {_gib(PRESSURE_BYTES * maps * n_steps)} are the pressure maps kept for the result"
            if maps
            else ""
        )
        run_in = run_in_length > length  # the run-in's elements outnumber the run's: it is what to shorten
        about = "about " if math.isfinite(needed) else ""  # past 1e290 EiB the estimate is a bound
        raise WheelrailError(
            f"a {entry.name} run of {_count(n_steps)} steps"
            + (f" after a run-in of {run_in_length:.4g} m" if run_in else "")
            + f" needs {about}{_gib(needed)} of memory{kept}, over the {_gib(limit)} limit ({MEMORY_LIMIT_ENV} sets "
            f"it); shorten the {'run-in' if run_in else 'run'}"
        )
    return needed


def _count(n: float) -> str:
    return f"{n:.4g}" if math.isfinite(n) else "over 1e308"


def _gib(n_bytes: float) -> str:
    if not math.isfinite(n_bytes):
        return "more than 1e290 EiB"
    if n_bytes >= 1024**6:
        return f"{n_bytes / 1024**6:.3g} EiB"
    if n_bytes >= 1024**3:
        return f"{n_bytes / 1024**3:.3g} GiB"
    return f"{n_bytes / 1024**2:.3g} MiB"
