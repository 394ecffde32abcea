"""The Hertzian spring's compiled kernels for the time-stepping loop (paper section 2.3.3, eqs. 12-14): scalar in,
scalar out, no checks (the checked array functions of the same law are in ``contact.hertz``). A module of their
own so that importing ``parameters`` (Hertz's solution) does not import numba: a command that reads results only
(``wheelrail spectra``) starts without it.
"""

from __future__ import annotations

import math

from numba import njit

__all__ = ["hertz_law"]


@njit(cache=True)
def _hertz_force(compression, constant):
    """F = C_H compression^1.5 for compression >= 0 else 0 (eq. 12), N."""
    if compression <= 0.0:
        return 0.0
    return constant * compression * math.sqrt(compression)


@njit(cache=True)
def _hertz_force_and_stiffness(compression, constant):
    """(F, dF/d compression) of eq. (12): (C_H c^1.5, 1.5 C_H c^0.5), or (0, 0) out of contact."""
    if compression <= 0.0:
        return 0.0, 0.0
    root = math.sqrt(compression)
    return constant * compression * root, 1.5 * constant * root


@njit(cache=True)
def _hertz_compression(target, compliance, constant):
    """Solve u + c C_H u^1.5 = target for the compression u >= 0 (target <= 0: no contact). Newton from
    u = target, monotone for this increasing convex function."""
    if target <= 0.0:
        return 0.0
    u = target
    for _ in range(60):
        root = math.sqrt(u)
        residual = u + compliance * constant * u * root - target
        step = residual / (1.0 + 1.5 * compliance * constant * root)
        u -= step
        if u <= 0.0:
            u = 1e-300
        if abs(step) <= 1e-15 * target + 1e-22:
            break
    return u


@njit(cache=True, inline="always")
def hertz_law(approach_known, compliance, roughness, constant, radius_along, radius_across):
    """The interaction loop's Hertz law (eqs. 12-14 coupled with delta = delta_known - c F).

    The compression is u = delta + r_eq, so u + c C u^1.5 = delta_known + r_eq. Returns (F = C u^1.5,
    contact length 2a = 2 sqrt(rho_x u), area pi a b with b = sqrt(rho_y u)) for the equivalent roughness
    r_eq at this step; rho_x, rho_y: ``ContactParameters.patch_radii`` (both R for the paper's circle).
    """
    u = _hertz_compression(approach_known + roughness, compliance, constant)
    length = 2.0 * math.sqrt(radius_along * u)
    half = length / 2.0
    return _hertz_force(u, constant), length, math.pi * (half * math.sqrt(radius_across * u))
