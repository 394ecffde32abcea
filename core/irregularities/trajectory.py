"""The wheel-centre trajectory: the envelope of a rigid wheel of radius R rolling over a profile.

With heights in the combined-roughness convention (positive pushes wheel and rail together, eq. 14), a rigid
wheel whose lowest point is above x touches the profile r where it first meets it; its centre is lifted by

    z_c(x) = max over xi of [ r(xi) - (R - sqrt(R^2 - (xi - x)^2)) ],   |xi - x| < R.

Where the profile curves upwards less than 1/R the wheel touches it at one point, R r' ahead of its centre,
and the centre runs on the profile's parallel curve at distance R (r lifted by R r'^2 / 2 to leading order: r
itself on a level stretch); a dip whose bottom curves more sharply is bridged, the wheel resting on its flanks.
A Hertz spring driven by z_c instead of r sees the irregularity as a rigid wheel would (Pieringer, Kropp &
Nielsen, Wear 2014). The maximum is exact over the grid's samples; the scan from each x stops where the circle
has dropped below the highest sample still ahead and skips blocks of samples too low to matter, so a level
stretch costs one sample.
"""

from __future__ import annotations

import math
import numbers

import numpy as np
from numba import njit

from wheelrail.core.errors import Blame, WheelrailError

__all__ = ["positive_length", "wheel_centre_trajectory"]


_BLOCK = 32  # samples per block whose maximum lets the scan skip it


@njit(cache=True)
def _envelope(profile, spacing, radius):
    """z_c at every sample of ``profile`` (spacing in m, radius R in m); see the module docstring.

    From each sample the scan runs outwards both ways and stops where the circle's drop exceeds the highest
    sample still ahead minus the best lift so far (``ahead``, ``behind``: running maxima from either end); a
    block of ``_BLOCK`` samples whose maximum minus the drop at its nearest sample cannot beat the best is
    skipped whole (the drop only grows further out).
    """
    n = profile.shape[0]
    ahead = np.empty(n)  # max of profile[j:], the highest a sample at or after j can be
    behind = np.empty(n)  # max of profile[:j + 1]
    top = -np.inf
    for j in range(n - 1, -1, -1):
        top = max(top, profile[j])
        ahead[j] = top
    top = -np.inf
    for j in range(n):
        top = max(top, profile[j])
        behind[j] = top
    blocks = np.full((n + _BLOCK - 1) // _BLOCK, -np.inf)
    for j in range(n):
        blocks[j // _BLOCK] = max(blocks[j // _BLOCK], profile[j])
    out = np.empty(n)
    for i in range(n):
        best = profile[i]
        for direction in (1, -1):
            j = i + direction
            while 0 <= j < n:
                d = abs(j - i) * spacing
                if d >= radius:
                    break
                drop = d * d / (radius + math.sqrt(radius * radius - d * d))  # R - sqrt(R^2 - d^2), no cancellation
                reach = ahead[j] if direction > 0 else behind[j]
                if drop >= reach - best:
                    break
                block = j // _BLOCK
                if blocks[block] - drop <= best:  # nothing in the rest of this block can lift the wheel more
                    j = (block + 1) * _BLOCK if direction > 0 else block * _BLOCK - 1
                    continue
                value = profile[j] - drop
                if value > best:
                    best = value
                j += direction
        out[i] = best
    return out


def wheel_centre_trajectory(profile, spacing: float, wheel_radius: float) -> np.ndarray:
    """The centre of a rigid wheel rolling over a profile: its lift z_c(x) over the samples (module docstring).

    Parameters
    ----------
    profile : array_like, 1-D
        r at equally spaced positions along the rail, m (the combined roughness plus the irregularities'
        :func:`~wheelrail.core.irregularities.surface.raw_profile`); at least 2 samples.
    spacing : float
        Distance between samples, m.
    wheel_radius : float
        R, m.

    Returns
    -------
    ndarray
        z_c at every sample, m: r's convention (the Hertz spring's equivalent roughness); only the given samples
        count, so a wheel near either end sees nothing beyond it (extend the profile by sqrt(2 R span) to avoid
        that).

    Raises
    ------
    WheelrailError
        If the profile is not a 1-D array of at least 2 finite heights, or the spacing or radius is not positive.

    Examples
    --------
    A rigid wheel (R = 0.46 m) over a 0.1 mm deep, 10 mm wide notch bridges it (it sags 27 um):

    >>> import numpy as np
    >>> from wheelrail.core.irregularities import wheel_centre_trajectory
    >>> x = np.arange(-0.05, 0.05, 1e-4)
    >>> notch = np.where(np.abs(x) < 0.005, -1e-4, 0.0)
    >>> f"{wheel_centre_trajectory(notch, 1e-4, 0.46).min() * 1e6:.1f} um"
    '-27.2 um'
    """
    try:
        heights = np.ascontiguousarray(profile, dtype=float)
    except (TypeError, ValueError):
        raise WheelrailError("the profile must be an array of heights in m") from None
    if heights.ndim != 1 or heights.size < 2 or not np.all(np.isfinite(heights)):
        raise WheelrailError(
            f"the profile must be a 1-D array of at least 2 finite heights in m, got shape {heights.shape}"
        )
    return _envelope(heights, positive_length("spacing", spacing), positive_length("wheel_radius", wheel_radius))


def positive_length(name: str, value) -> float:
    """``value`` as a positive finite length in m, else one WheelrailError keyed ``name``."""
    number = isinstance(value, numbers.Real) and not isinstance(value, bool)
    if not (number and math.isfinite(value) and value > 0):
        raise WheelrailError(
            "must be a positive number", Blame(name, value=float(value) if number else str(value), unit="m")
        )
    return float(value)
