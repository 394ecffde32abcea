"""Checks on a run read back from a file (a ``.npz`` of ``RunResult.save_npz`` or a ``.rrd`` recording).

A file is refused in one line naming it and what is wrong when its content does not match the SHA-256 digest
written with it (:func:`content_digest`: a flipped byte, an edited array) or when what it holds is not a run
the package could have made (:func:`check_run`): no steps, a contact force that is negative or not finite
(contact is compressive, F >= 0; loss of contact is F = 0), times that are not the time step apart, positions
that are not the element apart, a count of loss-of-contact steps that is not the file's own, pressure maps of
another shape than their window. A force that does not fluctuate has no spectrum or sound:
:func:`check_fluctuating` says so.
"""

from __future__ import annotations

import hashlib
import math
from pathlib import Path

import numpy as np

from wheelrail.core.errors import WheelrailError

__all__ = ["check_fluctuating", "check_run", "content_digest"]

_TIME_TOLERANCE = 1e-6  # relative to the time step, plus 1.5 ns: a recording stores whole nanoseconds


def content_digest(metadata: str, arrays: dict) -> str:
    """SHA-256 (hex) of a run file's content: its metadata text, then each array's name, dtype, shape and bytes
    in the order of their names (non-finite values counted as one NaN, as a recording reads them back).

    Parameters
    ----------
    metadata : str
        The file's metadata (the run's header as JSON text), without the digest.
    arrays : dict of str to numpy.ndarray
        The arrays as stored.

    Returns
    -------
    str
        64 hexadecimal digits.
    """
    from wheelrail.core.files.cache import array_digest

    canonical = {
        name: np.where(np.isfinite(array), array, np.nan).astype(array.dtype) if array.dtype.kind == "f" else array
        for name, array in ((name, np.asarray(value)) for name, value in arrays.items())
    }
    return array_digest(canonical, hashlib.sha256(metadata.encode("utf-8")))


def check_run(result, source: str | Path) -> None:
    """One WheelrailError naming ``source`` unless ``result`` (a RunResult read from it) holds a possible run.

    Parameters
    ----------
    result : RunResult
        The run as read.
    source : str or pathlib.Path
        The file it was read from (named in the message).

    Raises
    ------
    WheelrailError
        No steps; a negative, NaN or infinite contact force; times not ``time_step`` apart from 0; positions not
        ``element_size`` apart; non-finite displacements or roughness; a loss-of-contact count outside 0..steps;
        pressure maps that are negative, not finite or not of their window's shape.
    """
    problem = _problem(result)
    if problem:
        raise WheelrailError(f"{source}: {problem}; not a run wheelrail wrote (damaged or edited)")


def _problem(result) -> str:
    n = result.n_steps
    if n == 0:
        return "the run holds no steps"
    force = np.asarray(result.force, dtype=float)
    if not np.all(np.isfinite(force)):
        return "the contact force holds NaN or infinite values"
    if np.any(force < 0):
        return (
            f"the contact force is negative at {int(np.sum(force < 0))} steps (min {force.min():.6g} N), and contact "
            "is compressive (F >= 0; loss of contact is F = 0)"
        )
    dt, dx = result.time_step, result.element_size
    expected = np.arange(n) * dt
    if not np.all(np.abs(np.asarray(result.time) - expected) <= _TIME_TOLERANCE * dt * np.arange(1, n + 1) + 1.5e-9):
        return f"the times are not {dt:.6g} s (the header's time step) apart from 0"
    x = np.asarray(result.x, dtype=float)
    if not np.all(np.isfinite(x)) or (n > 1 and not np.allclose(np.diff(x), dx, rtol=1e-6, atol=0.0)):
        return f"the positions are not {dx:.6g} m (the header's element size) apart"
    for name in ("xi_wheel", "xi_rail", "roughness", "equivalent_roughness"):
        if not np.all(np.isfinite(getattr(result, name))):
            return f"{name} holds NaN or infinite values"
    for name in ("contact_length", "contact_area"):  # NaN where a model has none (2D: no area)
        values = np.asarray(getattr(result, name), dtype=float)
        if np.any(np.isinf(values)) or np.any(values < 0):
            return f"{name} holds negative or infinite values"
    loss = result.loss_of_contact_steps
    if loss != int(np.sum(force == 0)):
        return f"its {loss} loss-of-contact steps are not the {int(np.sum(force == 0))} steps of F = 0 it holds"
    return _pressure_problem(result)


def _pressure_problem(result) -> str:
    if result.pressure is None:
        return ""
    pressure = np.asarray(result.pressure)
    if result.window_x is None or result.window_y is None:
        return "pressure maps without their window"
    shape = (result.n_steps, np.size(result.window_y), np.size(result.window_x))
    if pressure.shape != shape:
        return f"pressure maps of shape {pressure.shape}, expected {shape} (steps x window)"
    if not np.all(np.isfinite(pressure)) or np.any(pressure < 0):
        return "the pressure maps hold negative, NaN or infinite values"
    return ""


def check_fluctuating(force, skipped_steps: int, source: str) -> None:
    """One WheelrailError unless the force after the first ``skipped_steps`` varies: a constant force has no
    dynamic part, so no spectrum level (-inf dB) and no sound.

    Parameters
    ----------
    force : array_like
        Contact force per step, N.
    skipped_steps : int
        Steps left out at the start (the start-up skip).
    source : str
        What the force is (named in the message: a file, a run).

    Raises
    ------
    WheelrailError
        If the kept force is constant (its standard deviation is 0, or below 1e-12 of its mean).
    """
    kept = np.asarray(force, dtype=float)[skipped_steps:]
    if kept.size and float(np.std(kept)) <= 1e-12 * max(abs(float(np.mean(kept))), math.ulp(1.0)):
        raise WheelrailError(
            f"{source}: the contact force is constant ({float(np.mean(kept)):.6g} N) after the start-up: there is "
            "no fluctuating force, so no force spectrum and no rolling noise"
        )
