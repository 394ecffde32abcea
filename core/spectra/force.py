"""The contact force's band spectrum: levels in dB re 1 N on the paper's bands (Figs 10-17), the start-up left out.

:func:`force_spectrum` computes the levels of a run's contact force, :func:`spectrum_record` the
:class:`~wheelrail.core.spectra.record.SpectrumRecord` (which bands the record resolves) that every front end
prints, and :func:`shortest_spectrum_run` the shortest run whose spectrum reaches the lowest band.
"""

from __future__ import annotations

import math

import numpy as np

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.inputs.checks import integer, real
from wheelrail.core.spectra.bands import FORCE_BAND_RANGE, band_centre_range, band_labels, third_octave_bands
from wheelrail.core.spectra.narrowband import third_octave_spectrum
from wheelrail.core.spectra.record import SpectrumRecord, resolved_bands

FORCE_REFERENCE = 1.0  # N: contact-force levels are in dB re 1 N
FORCE_SKIP = 0.02  # s, start of a run left out of force spectra (see force_spectrum)
FORCE_MIN_STEPS = 16  # steps a force spectrum needs after FORCE_SKIP


def shortest_spectrum_run(speed: float, element_size: float, skip: float = FORCE_SKIP) -> float:
    """The shortest run that has a force spectrum: ``skip`` left out and ``FORCE_MIN_STEPS`` steps after it.

    Parameters
    ----------
    speed : float
        Train speed, m/s.
    element_size : float
        Step length along the rail, m.
    skip : float
        Start of the run left out, s (whole steps, as :func:`force_spectrum` counts them).

    Returns
    -------
    float
        Run length, m.

    Raises
    ------
    WheelrailError
        A speed, element size or skip that is not a finite number of its sign, or a skip of more steps than a
        float counts exactly.

    Examples
    --------
    >>> from wheelrail.core.spectra.force import shortest_spectrum_run
    >>> round(shortest_spectrum_run(100 / 3.6, 1e-3), 3)    # m at 100 km/h, 1 mm steps: 556 skipped + 16
    0.572
    """
    speed = real("shortest_spectrum_run: speed", speed, "m/s")
    element_size = real("shortest_spectrum_run: element_size", element_size, "m")
    skip = real("shortest_spectrum_run: skip", skip, "s", sign="nonnegative")
    steps = skip * speed / element_size
    if steps > 1e15:  # more steps than a float counts exactly, and than any run has
        raise WheelrailError(f"shortest_spectrum_run: a skip of {steps:.3g} steps (speed x skip / element_size)")
    return (math.ceil(steps - 1e-9) + FORCE_MIN_STEPS) * element_size


def check_spectrum_length(length: float, speed: float, element_size: float) -> None:
    """A run of ``length`` m at ``speed`` m/s has a force spectrum; else one WheelrailError blaming the length
    (key ``length``) with the shortest that has one (:func:`shortest_spectrum_run`)."""
    if isinstance(length, bool) or not isinstance(length, int | float):
        raise WheelrailError(f"check_spectrum_length: length must be a number in m, got {type(length).__name__}")
    if not (math.isfinite(length) and length > 0):
        raise WheelrailError("not a positive length", Blame("length", value=length, unit="m"))
    shortest = shortest_spectrum_run(speed, element_size)
    if length < shortest - 1e-9 * element_size:
        raise WheelrailError(
            f"too short for a force spectrum at {speed * 3.6:.4g} km/h, which leaves out the first "
            f"{FORCE_SKIP * 1e3:g} ms (start-up) and needs {FORCE_MIN_STEPS} steps after them",
            Blame("length", value=length, unit="m", minimum=shortest),
        )


def _force_record(result_or_force, time_step, skip) -> tuple[np.ndarray, float, float]:
    """The force (N), time step (s) and skip (s) of :func:`force_spectrum`, checked (one WheelrailError each)."""
    if hasattr(result_or_force, "force") and hasattr(result_or_force, "time_step"):
        own_step = float(result_or_force.time_step)
        if time_step is not None and not math.isclose(float(time_step), own_step, rel_tol=1e-9):
            raise WheelrailError(f"force_spectrum: time_step {time_step!r} s differs from the run's {own_step!r} s")
        force, time_step = result_or_force.force, own_step
    else:
        force = result_or_force
        if time_step is None:
            raise WheelrailError("force_spectrum: time_step (s) is required when a force array is given")
    try:
        time_step = float(time_step)
        skip = float(skip)
        force = np.asarray(force, dtype=float)
    except (TypeError, ValueError):
        raise WheelrailError("force_spectrum: force must be numbers in N, time_step and skip numbers in s") from None
    if not (math.isfinite(time_step) and time_step > 0):
        raise WheelrailError(f"force_spectrum: time_step must be a positive number of seconds, got {time_step!r}")
    if not (math.isfinite(skip) and skip >= 0):
        raise WheelrailError(f"force_spectrum: skip must be zero or a positive number of seconds, got {skip!r}")
    if force.ndim != 1:
        raise WheelrailError(f"force_spectrum: force must be one value per step, got shape {force.shape}")
    if not np.all(np.isfinite(force)):
        raise WheelrailError("force_spectrum: force contains NaN or infinity")
    return force, time_step, skip


def force_spectrum(
    result_or_force,
    time_step: float | None = None,
    *,
    skip: float = FORCE_SKIP,
    band_range: tuple[float, float] = FORCE_BAND_RANGE,
) -> tuple[np.ndarray, np.ndarray]:
    """Third-octave band levels of the dynamic contact force, dB re 1 N (paper Figs 10-17).

    Steps: (1) the first ``skip`` seconds are dropped (start-up); (2) the mean of the rest is removed, so
    only the dynamic part around the (pre)load is analysed; (3) one Hann-windowed FFT of the whole
    remaining record with the power-conserving window correction (:func:`narrowband_spectrum`, as for the
    roughness spectra of section 3.1); (4) the PSD is integrated into exact base-10 third-octave bands
    (:func:`band_power`) and expressed as ``10 log10(F_band² / (1 N)²)``. A tone of amplitude F̂ in a band
    therefore reads ``20 log10(F̂ / sqrt(2))`` dB. A band is resolved when it is at least as wide as the
    frequency resolution 1 / T of the record analysed (T: the duration left after ``skip``) and lies below the
    Nyquist frequency; every other band is NaN. The resolved bands are contiguous (third-octave bands widen with
    their centre): a short record loses its lowest bands. :func:`spectrum_record` says what was left out, what
    was analysed and which bands that resolves, as every front end prints it.

    Why skip the start: at step 0 the roughness starts acting on a system in its steady state on the gap of
    step 0 (the loop's start and run-in), and the response to that onset is a transient, not a property of the
    roughness. It decays within a few periods of the lowest, well-damped wheel-on-track resonances
    (~60-110 Hz); the default 20 ms is one period of the lowest band (50 Hz) and about 0.56 m at 100 km/h,
    7 % of the paper's 8 m run.

    Parameters
    ----------
    result_or_force : RunResult or array_like
        A run result (its ``force`` in N and ``time_step`` in s are used) or the contact force F_n(t), N,
        sampled every ``time_step`` s.
    time_step : float, optional
        Sampling interval dt, s. Required with an array; with a RunResult it must be omitted or equal to
        the result's.
    skip : float
        Duration excluded at the start of the record, s (default ``FORCE_SKIP`` = 0.02 s). 0 keeps all.
    band_range : (float, float)
        Lowest and highest band centre, Hz (default 50 Hz .. 8 kHz).

    Returns
    -------
    centres : numpy.ndarray
        Exact base-10 band centres, Hz.
    levels : numpy.ndarray
        Band levels of the dynamic contact force, dB re 1 N (NaN where a band is not resolved).

    Raises
    ------
    WheelrailError
        For a force that is not one finite number per step, a missing or inconsistent time step, or a record
        with fewer than ``FORCE_MIN_STEPS`` steps after ``skip``.

    See Also
    --------
    contact_filter : the difference of two models' levels.
    shortest_spectrum_run : the shortest run that has a spectrum.
    spectrum_record : the skip, the analysed duration and the resolved bands of the same call.

    Examples
    --------
    A tone of 100 N amplitude at 1 kHz on the 65 kN preload reads 20 log10(100 / sqrt(2)) = 37.0 dB in its band:

    >>> import numpy as np
    >>> from wheelrail.core.spectra.force import force_spectrum
    >>> time = np.arange(4096) * 1e-4                                   # s
    >>> force = 65e3 + 100.0 * np.sin(2 * np.pi * 1000.0 * time)        # N
    >>> centres, levels = force_spectrum(force, 1e-4)
    >>> loudest = int(np.nanargmax(levels))
    >>> round(float(centres[loudest])), round(float(levels[loudest]), 1)
    (1000, 37.0)
    """
    force, time_step, skip = _force_record(result_or_force, time_step, skip)
    first = _skipped_steps(force.size, time_step, skip)
    kept = force.size - first
    if kept < FORCE_MIN_STEPS:
        record = f"the record of {force.size} steps ({force.size * time_step:.4g} s)"
        if force.size < FORCE_MIN_STEPS:
            raise WheelrailError(
                f"force_spectrum: {record} is shorter than the {FORCE_MIN_STEPS} steps a "
                "spectrum needs; use a longer run"
            )
        raise WheelrailError(
            f"{record} leaves {max(kept, 0)} steps after the skip, and a spectrum needs {FORCE_MIN_STEPS}",
            Blame("skip", value=skip, unit="s", maximum=(force.size - FORCE_MIN_STEPS) * time_step),
            advice="or use a longer run",
        )
    dynamic = force[first:] - force[first:].mean()
    return third_octave_spectrum(dynamic, 1.0 / time_step, band_range, FORCE_REFERENCE)


def _skipped_steps(n_steps: int, time_step: float, skip: float) -> int:
    """Whole steps in the first ``skip`` seconds (at most ``n_steps``; no overflow for any finite skip)."""
    steps = skip / time_step
    return n_steps if steps >= n_steps else min(int(math.ceil(steps - 1e-9)), n_steps)


def spectrum_record(
    result_or_force,
    time_step: float | None = None,
    *,
    skip: float = FORCE_SKIP,
    band_range: tuple[float, float] = FORCE_BAND_RANGE,
) -> SpectrumRecord:
    """What :func:`force_spectrum` analyses with the same arguments: the start left out, the duration T of the
    record analysed, its frequency resolution 1 / T and the bands resolved (at least 1 / T wide, below the
    Nyquist frequency; contiguous).

    Parameters
    ----------
    result_or_force, time_step, skip, band_range
        As for :func:`force_spectrum`.

    Returns
    -------
    SpectrumRecord
        ``skip`` (s, whole steps), ``duration`` (s), ``resolution`` (Hz), ``resolved`` per band,
        ``to_dict()`` for JSON and ``words()`` for a line of text.

    Raises
    ------
    WheelrailError
        As :func:`force_spectrum`, for a force that is not one finite number per step or a bad time step or skip.

    Examples
    --------
    >>> import numpy as np
    >>> from wheelrail.core.spectra.force import spectrum_record
    >>> record = spectrum_record(np.full(1000, 65e3), 1e-3 / (100 / 3.6))   # 1 m at 100 km/h, 1 mm steps
    >>> round(record.skip * 1e3, 2), round(record.duration * 1e3, 2), record.band_labels[record.lowest_resolved()]
    (20.02, 15.98, '315')
    """
    force, time_step, skip = _force_record(result_or_force, time_step, skip)
    return record_of_steps(force.size, time_step, skip=skip, band_range=band_range)


def record_of_steps(
    n_steps: int,
    time_step: float,
    *,
    skip: float = FORCE_SKIP,
    band_range: tuple[float, float] = FORCE_BAND_RANGE,
) -> SpectrumRecord:
    """:func:`spectrum_record` from the record's size alone: ``n_steps`` samples every ``time_step`` s."""
    n_steps = min(integer("record_of_steps: n_steps", n_steps, 0), 2**40)
    time_step = real("record_of_steps: time_step", time_step, "s")
    skip = real("record_of_steps: skip", skip, "s", sign="nonnegative")
    centres, lower, upper = third_octave_bands(*band_centre_range(band_range))
    first = _skipped_steps(n_steps, time_step, skip)
    kept = n_steps - first
    resolved = (
        resolved_bands(lower, upper, 1.0 / (kept * time_step), 0.5 / time_step)
        if kept >= 2
        else np.zeros(centres.shape, dtype=bool)
    )
    return SpectrumRecord(
        n_steps=n_steps,
        time_step=time_step,
        skipped_steps=first,
        band_centres=centres,
        band_labels=band_labels(centres),
        resolved=resolved,
    )


def resolved_force_bands(
    n_steps: int,
    time_step: float,
    *,
    skip: float = FORCE_SKIP,
    band_range: tuple[float, float] = FORCE_BAND_RANGE,
) -> tuple[np.ndarray, np.ndarray]:
    """Band centres (Hz) and which bands :func:`force_spectrum` resolves (bool) for a record of ``n_steps``
    samples every ``time_step`` s (:func:`record_of_steps`); the other bands are NaN. Checks stored spectra."""
    record = record_of_steps(n_steps, time_step, skip=skip, band_range=band_range)
    return record.band_centres, record.resolved
