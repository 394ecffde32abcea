"""Equivalent roughness for the Hertzian spring (paper section 2.3.3): the two prefilters.

``winkler_equivalent_roughness`` (Ford & Thompson, the paper's ``hertz-winkler``)
    At every wheel position x the Winkler bedding of :mod:`wheelrail.core.contact.winkler` (eqs. 3-6)
    is pressed onto the local roughness with the static preload P. Its approach delta(x) solves
    F_bedding(delta, r) = P. A Hertz spring (eqs. 12, 14) carries P at the compression
    delta_H(P) = (P / C_H)^(2/3), so the equivalent roughness that makes the Hertz spring see what the
    bedding sees (same approach for the same load) is

        r_eq(x) = delta_0(P) - delta(x),

    where delta_0(P) is the approach of the same (discrete) bedding on a *smooth* surface. For a continuous
    bedding delta_0(P) = delta_H(P) (eq. 6 makes the bedding reproduce Hertz); on the 1 mm grid they differ
    by the discretisation (0.21 um of 77.07 um at 65 kN and dx = 1 mm), and using delta_0 keeps a constant or very long
    roughness exactly unchanged. Signs (eqs. 3 and 14): r = r_W - r_R is positive when it pushes the
    surfaces together; a bump under the wheel lets the bedding carry P at a smaller delta, so r_eq > 0, as
    r itself. Constant roughness c gives delta = delta_0 - c and r_eq = c.

``average_roughness`` (the paper's ``hertz-average``)
    The mean of the roughness over the nominal contact length 2a centred on the wheel: the integral of the
    linear interpolant of the samples over [x - a, x + a] divided by 2a. Its transfer function is
    sin(pi 2a / lambda) / (pi 2a / lambda) (times the small effect of linear interpolation): zero at the
    wavelengths lambda = 2a / n, the dips of eq. (19).

Both work on one roughness line (1D array, spacing dx) and return an array of the same length. Near the
ends the line is extended by its end values (``boundary="nearest"``) or periodically (``"wrap"``, for a
wheel's circumference).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from wheelrail.core.contact.winkler import (
    bedding_approach,
    calibrated_bedding,
    checked_contact,
    checked_roughness,
    wheel_profile,
)
from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.inputs.checks import positive as _positive
from wheelrail.core.parameters import ContactParameters

__all__ = ["average_roughness", "averaging_weights", "winkler_equivalent_roughness"]

_BOUNDARIES = ("nearest", "wrap")


@njit(cache=True)
def _winkler_equivalent(padded, profile, k_dx, load, reference):
    """r_eq for every position of a line padded by half a window on both sides (see module docstring).

    The bedding force is convex and piecewise linear in delta, so Newton's method from the previous
    position's delta ends exactly in a few steps; the sort-based exact solution is the fallback.
    Returns (r_eq, number of positions where an end spring of the window is compressed).
    """
    window = profile.shape[0]
    n = padded.shape[0] - window + 1
    out = np.empty(n)
    values = np.empty(window)
    target = load / k_dx
    at_edge = 0
    delta = reference
    for i in range(n):
        for j in range(window):
            values[j] = padded[i + j] - profile[j]
        solved = False
        for _ in range(30):
            total = 0.0
            count = 0
            for j in range(window):
                c = delta + values[j]
                if c > 0.0:
                    total += c
                    count += 1
            if count == 0:
                delta = target - values.max()
                continue
            step = (total - target) / count
            delta -= step
            if abs(step) <= 1e-13 * (abs(delta) + 1e-12):
                solved = True
                break
        if not solved:
            delta, count = bedding_approach(values, k_dx, load)
        if delta + values[0] > 0.0 or delta + values[window - 1] > 0.0:
            at_edge += 1
        out[i] = reference - delta
    return out, at_edge


def _pad(line: np.ndarray, half: int, boundary: str) -> np.ndarray:
    mode = "edge" if boundary == "nearest" else "wrap"
    return np.pad(line, half, mode=mode)


def _check_boundary(where: str, boundary: str) -> str:
    if boundary not in _BOUNDARIES:
        raise WheelrailError(f"{where}: boundary must be one of {_BOUNDARIES}, got {boundary!r}")
    return boundary


def winkler_equivalent_roughness(
    roughness,
    element_size: float,
    contact: ContactParameters | None = None,
    *,
    half_window: float | None = None,
    boundary: str = "nearest",
) -> np.ndarray:
    """Ford & Thompson equivalent roughness r_eq for the Hertzian spring (eqs. 3-6, 12-14).

    Parameters
    ----------
    roughness : array_like, shape (n,)
        Combined roughness line r = r_W - r_R, m, every ``element_size`` (positive pushes together, eq. 3).
    element_size : float
        Sample spacing dx, m (one spring per sample).
    contact : ContactParameters, optional
        The preload P and the bedding of ``contact.winkler.calibrated_bedding`` (eqs. 5-6 for the paper's
        circle: k = E*, R_m = R / 2); default ``ContactParameters()``.
    half_window : float, optional
        a' of eq. (4), m: the bedding spans [-a', a'] around the wheel. Default 3 a (a = (3 P R / (4 k))^(1/3),
        the Hertz radius at the preload), which holds roughness up to ~8 a^2 / R (0.6 mm at the defaults)
        without reaching the end.
    boundary : {"nearest", "wrap"}
        How the line is extended beyond its ends.

    Returns
    -------
    ndarray, shape (n,)
        r_eq in m, to use in eq. (14).

    Raises
    ------
    WheelrailError
        On bad input, or if the bedding's contact reaches the end of its window somewhere (roughness too
        large for ``half_window``).

    See Also
    --------
    average_roughness : the other pre-filter of section 2.3.3.
    wheelrail.core.contact.winkler.winkler_contact : the bedding itself.

    References
    ----------
    Ford & Thompson, J. Sound Vib. 291 (2006) 1065-1082; Pieringer et al., Wear 271 (2011), section 2.3.3.

    Examples
    --------
    >>> import numpy as np
    >>> from wheelrail.core.contact import winkler_equivalent_roughness
    >>> x = np.arange(2000) * 1e-3
    >>> r_eq = winkler_equivalent_roughness(10e-6 * np.sin(2 * np.pi * x / 5e-3), 1e-3, boundary="wrap")
    >>> bool(np.abs(r_eq).max() < 2e-6)   # a 10 um, 5 mm corrugation under the 11 mm contact: filtered out
    True
    """
    where = "winkler_equivalent_roughness"
    line = checked_roughness(where, roughness)
    element_size = _positive(where, "element_size", element_size, "m")
    contact = checked_contact(where, contact)
    preload = contact.preload
    k, radius = calibrated_bedding(contact)
    boundary = _check_boundary(where, boundary)
    a = (3.0 * preload * radius / (4.0 * k)) ** (1.0 / 3.0)
    half_window = 3.0 * a if half_window is None else _positive(where, "half_window", half_window, "m")
    half = max(2, int(math.ceil(half_window / element_size)))
    profile = wheel_profile(2 * half + 1, element_size, radius)
    k_dx = k * element_size
    reference, _ = bedding_approach(-profile, k_dx, preload)
    r_eq, at_edge = _winkler_equivalent(_pad(line, half, boundary), profile, k_dx, preload, reference)
    if at_edge:
        raise WheelrailError(
            f"the bedding contact reaches the end of its window at {at_edge} positions: the "
            "roughness is too large for it",
            Blame("half_window", half * element_size, unit="m", argument=f"{where}: half_window"),
            advice="give a larger one",
        )
    return r_eq


def _hat_cumulative(t: np.ndarray) -> np.ndarray:
    """Integral of the unit hat function (linear interpolation weight) from -inf to t."""
    return np.where(
        t <= -1.0, 0.0, np.where(t <= 0.0, 0.5 * (t + 1.0) ** 2, np.where(t <= 1.0, 1.0 - 0.5 * (1.0 - t) ** 2, 1.0))
    )


def averaging_weights(contact_length: float, element_size: float) -> np.ndarray:
    """Weights w_j (sum 1) of the mean of the linearly interpolated line over a length L, centred.

    Parameters
    ----------
    contact_length : float
        L = 2a, m.
    element_size : float
        dx, m.

    Returns
    -------
    ndarray, shape (2 h + 1,)
        Weights of the samples at offsets -h..h, with h = ceil(L / (2 dx)) + 1.
    """
    half_length = 0.5 * contact_length / element_size
    h = int(math.ceil(half_length)) + 1
    offsets = np.arange(-h, h + 1, dtype=float)
    weights = _hat_cumulative(half_length - offsets) - _hat_cumulative(-half_length - offsets)
    return weights / weights.sum()


def average_roughness(
    roughness,
    element_size: float,
    contact: ContactParameters | None = None,
    *,
    contact_length: float | None = None,
    boundary: str = "nearest",
) -> np.ndarray:
    """Equivalent roughness by averaging over the nominal contact length 2a (paper section 2.3.3).

    Parameters
    ----------
    roughness : array_like, shape (n,)
        Combined roughness line r, m, spacing ``element_size``.
    element_size : float
        dx, m.
    contact : ContactParameters, optional
        Used only for the default ``contact_length``; default ``ContactParameters()``.
    contact_length : float, optional
        Averaging length 2a, m. Default: twice Hertz's semi-axis along the rail at the preload (10.96 mm at
        the paper's values, a = (3 P R / (4 E*))^(1/3)).
    boundary : {"nearest", "wrap"}
        How the line is extended beyond its ends.

    Returns
    -------
    ndarray, shape (n,)
        r_eq in m.

    Raises
    ------
    WheelrailError
        On bad input (a non-finite line, a length that is not positive, an unknown ``boundary``).

    See Also
    --------
    averaging_weights : the weights of the mean.
    winkler_equivalent_roughness : the other pre-filter of section 2.3.3.

    References
    ----------
    A. Pieringer, W. Kropp, D. J. Thompson, Wear 271 (2011) 328-338, section 2.3.3.

    Examples
    --------
    >>> import numpy as np
    >>> from wheelrail.core.contact import average_roughness
    >>> x = np.arange(2000) * 1e-3
    >>> long_wave = 10e-6 * np.sin(2 * np.pi * x / 0.1)     # 100 mm: passes nearly unchanged
    >>> bool(np.abs(average_roughness(long_wave, 1e-3, boundary="wrap") - long_wave).max() < 0.2e-6)
    True
    """
    where = "average_roughness"
    line = checked_roughness(where, roughness)
    element_size = _positive(where, "element_size", element_size, "m")
    boundary = _check_boundary(where, boundary)
    if contact_length is None:
        contact_length = 2.0 * checked_contact(where, contact).hertz_semi_axes()[0]
    contact_length = _positive(where, "contact_length", contact_length, "m")
    weights = averaging_weights(contact_length, element_size)
    half = weights.size // 2
    return np.convolve(_pad(line, half, boundary), weights, mode="valid")
