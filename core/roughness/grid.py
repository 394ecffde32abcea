"""Roughness on the model grid: longitudinal and lateral interpolation, and lines along the track.

Every function here estimates the size of its result first and refuses, with the figure, a grid of more
than :data:`~wheelrail.core.roughness.model.MAX_VALUES` heights (e.g. a set sampled every 1 km
interpolated to 1 mm) before allocating it.
"""

from __future__ import annotations

import math

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.roughness.model import RoughnessSet, check_value_count

ANTI_ALIAS_ATTENUATION_DB = 80.0  # the rail's FIR: stopband attenuation and passband ripple (1e-4)
ANTI_ALIAS_PASSBAND = 0.8  # the rail's FIR passes up to this fraction of the grid's Nyquist wavenumber


def anti_alias(roughness: RoughnessSet, dx: float) -> np.ndarray:
    """The heights of ``roughness`` low-passed for a grid of spacing ``dx`` (m, coarser than the set's): nothing
    left at or above the grid's Nyquist wavenumber 1 / (2 dx), so that nothing folds back onto longer wavelengths.

    Without it the roughness at wavelengths below 2 dx would fold onto longer ones on the grid (aliasing), where
    no contact filter removes it (docs/physics.md, "Roughness on a coarser grid": 0.2 dB at 315-1000 Hz on a
    bundled 0.5 mm wheel set at 1 mm, up to 1.5 dB at 500 Hz at 2 mm; ``validation/roughness_aliasing.py``).
    Returns the heights on the set's own samples, (lines, samples), m.

    A wheel's lines (one circumference, periodic) keep their Fourier series below the Nyquist wavenumber: the
    ideal low-pass, exact for a periodic line. A rail's lines are convolved with a zero-phase FIR low-pass
    (``scipy.signal.firwin``, Kaiser window, ``scipy.signal.kaiserord``: ``ANTI_ALIAS_ATTENUATION_DB`` of
    attenuation from the Nyquist wavenumber, gain 1 within the same ripple up to ``ANTI_ALIAS_PASSBAND`` of it),
    each line extended at either end by its point reflection (a straight line continues as it is).
    """
    if roughness.periodic:
        spectrum = np.fft.rfft(roughness.heights, axis=1)
        spectrum[:, np.arange(spectrum.shape[1]) >= roughness.length / (2 * dx) - 1e-9] = 0.0
        return np.fft.irfft(spectrum, n=roughness.n_samples, axis=1)
    from scipy.signal import firwin, kaiserord, oaconvolve

    ratio = dx / roughness.dx  # the grid's Nyquist wavenumber is 1 / ratio of the set's
    width = (1.0 - ANTI_ALIAS_PASSBAND) / ratio
    taps, beta = kaiserord(ANTI_ALIAS_ATTENUATION_DB, width)
    half = taps // 2
    kernel = firwin(2 * half + 1, 1.0 / ratio - width / 2, window=("kaiser", beta))
    padded = np.pad(roughness.heights, ((0, 0), (half, half)), mode="reflect", reflect_type="odd")
    return oaconvolve(padded, kernel[np.newaxis, :], mode="valid", axes=1)  # overlap-add FFT: long kernels too


def resample_longitudinal(roughness: RoughnessSet, dx: float) -> RoughnessSet:
    """Linear interpolation of every line to spacing ``dx`` (m), e.g. 0.5 mm -> 1 mm (paper section 3), the lines
    low-passed first where ``dx`` is the coarser (:func:`anti_alias`).

    Rail: samples at ``0, dx, ...`` up to the last original position. Wheel: the circumference is kept
    exactly; ``dx`` is adjusted to ``length / round(length / dx)`` and interpolation wraps around.
    """
    dx = float(dx)
    if not (math.isfinite(dx) and dx > 0):
        raise WheelrailError(f"resample: longitudinal spacing must be positive (m), got {dx!r}")
    x_old = roughness.x
    if roughness.periodic:
        what = f"{roughness.length:g} m of roughness at dx {dx:g} m"
        check_value_count(roughness.n_lines * (roughness.length / dx), what)
        n = max(2, round(roughness.length / dx))
        dx = roughness.length / n
    else:
        check_value_count(roughness.n_lines * (x_old[-1] / dx + 1), f"{x_old[-1]:g} m of roughness at dx {dx:g} m")
        n = int(math.floor(x_old[-1] / dx + 1e-9)) + 1
        if n < 2:
            raise WheelrailError(f"resample: spacing {dx:g} m leaves fewer than 2 samples in {x_old[-1]:g} m")
    coarser = dx > roughness.dx * (1 + 1e-9)
    heights = anti_alias(roughness, dx) if coarser else roughness.heights
    x_new = np.arange(n) * dx
    period = {"period": roughness.length} if roughness.periodic else {}
    z = np.stack([np.interp(x_new, x_old, line, **period) for line in heights])
    note = f"{'low-passed and ' if coarser else ''}interpolated to dx {dx * 1e3:g} mm"
    return roughness.with_heights(z, dx=dx, note=note)


def resample_lateral(roughness: RoughnessSet, dy: float) -> RoughnessSet:
    """Linear interpolation across the lines to lateral spacing ``dy`` (m), e.g. 2 mm -> 1 mm for 3D.

    New lines are at integer multiples of ``dy`` (so y = 0 stays a line) within the original lateral
    extent.
    """
    dy = float(dy)
    if not (math.isfinite(dy) and dy > 0):
        raise WheelrailError(f"resample: lateral spacing must be positive (m), got {dy!r}")
    if roughness.n_lines < 2:
        raise WheelrailError("resample: lateral interpolation needs at least 2 lines")
    y = roughness.y
    what = f"{y[-1] - y[0]:g} m of roughness width at lines {dy:g} m apart"
    check_value_count(((y[-1] - y[0]) / dy + 1) * roughness.n_samples, what)
    tol = 1e-9 * max(1.0, abs(y).max() / dy)
    first = math.ceil(y[0] / dy - tol)
    last = math.floor(y[-1] / dy + tol)
    y_new = np.arange(first, last + 1) * dy
    if y_new.size < 1:
        raise WheelrailError(f"resample: lateral spacing {dy:g} m leaves no line in [{y[0]:g}, {y[-1]:g}] m")
    z_new = _across(roughness.heights, y, y_new)
    return roughness.with_heights(z_new, y=y_new, note=f"interpolated to {dy * 1e3:g} mm lines")


LATERAL_TOLERANCE = 1e-9  # m: a lateral position this close to a line, or to the edge of a set, is on it


def _across(z: np.ndarray, y: np.ndarray, y_new: np.ndarray) -> np.ndarray:
    """Heights ``z`` (rows at ``y``) linearly interpolated across to ``y_new`` (within ``y``), one row each
    (vectorised through index/weight arrays; a position on a line takes that line as it is)."""
    if y.size == 1:
        return np.repeat(z, y_new.size, axis=0)
    idx = np.clip(np.searchsorted(y, y_new, side="right") - 1, 0, y.size - 2)
    w = np.clip((y_new - y[idx]) / (y[idx + 1] - y[idx]), 0.0, 1.0)
    return (1 - w)[:, None] * z[idx] + w[:, None] * z[idx + 1]


def covers(roughness: RoughnessSet, y_low: float, y_high: float) -> bool:
    """True if the set has data across the lateral range ``y_low`` .. ``y_high`` (m), its edges included."""
    return float(roughness.y[0]) - LATERAL_TOLERANCE <= y_low and y_high <= float(roughness.y[-1]) + LATERAL_TOLERANCE


def lateral_extent_mm(roughness: RoughnessSet) -> str:
    """The set's lateral data range in words, mm (``-4 .. 4 mm``, or ``one line at 0 mm``)."""
    low, high = float(roughness.y[0]) * 1e3, float(roughness.y[-1]) * 1e3
    return f"one line at {low:g} mm" if roughness.n_lines == 1 else f"{low:g} .. {high:g} mm"


def at_lateral_positions(roughness: RoughnessSet, y) -> RoughnessSet:
    """The set at the lateral positions ``y`` (m, strictly increasing): each line linearly interpolated across
    between the set's two neighbouring lines (a position on a line takes that line as it is), e.g. a wheel set
    2 mm apart at a rail set's lines 1 mm apart, so that surfaces are paired where they touch.

    Raises WheelrailError for a position outside the set's lateral data (it is never extrapolated).
    """
    y_new = np.asarray(y, dtype=float).reshape(-1)
    if y_new.size < 1 or not np.all(np.isfinite(y_new)):
        raise WheelrailError(f"lateral positions must be finite (m), got {y_new.tolist()}")
    if not covers(roughness, float(y_new.min()), float(y_new.max())):
        raise WheelrailError(
            f"lateral positions {y_new.min() * 1e3:g} .. {y_new.max() * 1e3:g} mm lie outside the set's data "
            f"({lateral_extent_mm(roughness)}); a set is interpolated across its lines, never extrapolated"
        )
    check_value_count(y_new.size * roughness.n_samples, f"{y_new.size} lines of {roughness.n_samples} samples")
    y_new = np.clip(y_new, roughness.y[0], roughness.y[-1])
    z_new = _across(roughness.heights, roughness.y, y_new)
    note = f"interpolated across to {y_new.size} lateral position{'s' if y_new.size > 1 else ''}"
    return roughness.with_heights(z_new, y=y_new, note=note)


def to_model_grid(roughness: RoughnessSet, dx: float, dy: float | None = None) -> RoughnessSet:
    """Interpolate to the model grid: longitudinal ``dx`` and, for the 3D model, lateral ``dy`` (m)."""
    out = resample_longitudinal(roughness, dx) if not math.isclose(dx, roughness.dx, rel_tol=1e-12) else roughness
    if dy is not None and not (
        roughness.n_lines > 1 and np.allclose(np.diff(out.y), dy, rtol=1e-9) and np.any(np.isclose(out.y, 0))
    ):
        out = resample_lateral(out, dy)
    return out


def lines_along_track(roughness: RoughnessSet, lines, length: float, dx: float | None = None) -> np.ndarray:
    """Heights of several lines covering a run of ``length`` m at spacing ``dx`` m, shape (lines, samples).

    Sample ``i`` is at ``x = i dx`` for ``i = 0 .. round(length / dx)``. Wheel data is repeated around the
    circumference as often as needed (periodic linear interpolation); rail data must be long enough.
    """
    dx = roughness.dx if dx is None else float(dx)
    if not (math.isfinite(dx) and dx > 0):
        raise WheelrailError(f"spacing dx must be positive (m), got {dx!r}")
    if not (math.isfinite(length) and length >= 0):
        raise WheelrailError(f"run length must be zero or positive (m), got {length!r}")
    rows = [roughness.row_of_line(line) for line in lines]
    check_value_count(len(rows) * (length / dx + 1), f"roughness along a run of {length:g} m at dx {dx:g} m")
    n = int(round(length / dx)) + 1
    x = np.arange(n) * dx
    if roughness.periodic:
        return np.stack([np.interp(x, roughness.x, roughness.heights[r], period=roughness.length) for r in rows])
    available = roughness.x[-1]
    if x[-1] > available * (1 + 1e-12):
        raise WheelrailError(
            f"run length {length:g} m exceeds the rail roughness data ({available:g} m); "
            "shorten the run or use longer data"
        )
    return np.stack([np.interp(x, roughness.x, roughness.heights[r]) for r in rows])


def line_along_track(roughness: RoughnessSet, line: int, length: float, dx: float | None = None) -> np.ndarray:
    """Heights of one line over a run of ``length`` m at spacing ``dx`` m (see :func:`lines_along_track`)."""
    return lines_along_track(roughness, [line], length, dx)[0]
