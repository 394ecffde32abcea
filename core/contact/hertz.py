"""Hertz's solution and the non-linear Hertzian contact spring (paper section 2.3.3, eqs. 12-14).

:func:`elliptic_hertz` is Hertz's contact of two bodies whose gap is x^2 / (2 R_x) + y^2 / (2 R_y) (Johnson,
*Contact Mechanics*, section 4.2; the circle in closed form), which ``parameters.ContactParameters`` reads.
The spring: the compression is Delta zeta = xi_W - xi_R + r_eq (eq. 14), m, z positive downwards into the
rail; F = C_H Delta zeta^1.5 for Delta zeta >= 0 and F = 0 otherwise (loss of contact). The functions here check
their input and work on arrays; the loop's compiled kernels of the same law are in ``contact.hertz_law`` (kept
apart so that ``parameters``, which reads Hertz's solution, does not import numba), the ``hertz*`` contact models
in ``contact.hertz_model``.
"""

from __future__ import annotations

import math
import typing

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs import checks
from wheelrail.core.inputs.checks import finite_array

__all__ = ["HertzContact", "elliptic_hertz", "hertz_approach", "hertz_force", "hertz_stiffness"]


class HertzContact(typing.NamedTuple):
    """Hertz's solution for two bodies whose undeformed gap is x^2 / (2 R_x) + y^2 / (2 R_y).

    ``semi_axis_along`` a (along x, the rail) and ``semi_axis_across`` b (across, y), m; ``peak_pressure``
    p0, Pa; ``approach`` delta, m; ``constant`` C of F = C delta^1.5, N/m^1.5. Both semi-axes grow as
    sqrt(delta), so ``radius_along`` = a^2 / delta and ``radius_across`` = b^2 / delta (m) give them at any
    approach (both are R for a circle: a = sqrt(R delta)).

    Attributes
    ----------
    semi_axis_along, semi_axis_across : float
        a along the rail and b across it, m.
    peak_pressure : float
        p0, Pa.
    approach : float
        delta, m.
    constant : float
        C of F = C delta^1.5, N/m^1.5.

    See Also
    --------
    elliptic_hertz : the solution for given radii and load.
    """

    semi_axis_along: float
    semi_axis_across: float
    peak_pressure: float
    approach: float
    constant: float

    @property
    def radius_along(self) -> float:
        return self.semi_axis_along**2 / self.approach

    @property
    def radius_across(self) -> float:
        return self.semi_axis_across**2 / self.approach


def _ellipse_eccentricity(ratio: float) -> float:
    """m = e^2 = 1 - (b/a)^2 of the ellipse whose curvature ratio is ``ratio`` = B / A >= 1 (Johnson, Contact
    Mechanics, eq. 4.39a: B/A = ((a/b)^2 E(e) - K(e)) / (K(e) - E(e)), a >= b). Written with Carlson's R_D,
    (K - E)/m = R_D(0, 1-m, 1)/3 and (E - (1-m) K)/m = (1-m) R_D(0, 1, 1-m)/3, which do not cancel near
    the circle; solved for k = b/a by Brent's method to round-off."""
    from scipy.optimize import brentq
    from scipy.special import elliprd

    def excess(k: float) -> float:  # B/A - ratio as a function of k = b/a (1 at k = 1, growing as k falls)
        k2 = k * k
        return elliprd(0.0, 1.0, k2) / elliprd(0.0, k2, 1.0) - ratio

    k = brentq(excess, 1e-9, 1.0, xtol=1e-17, rtol=1e-15, maxiter=200)
    return 1.0 - float(k) * float(k)


def elliptic_hertz(load: float, radius_x: float, radius_y: float, modulus: float) -> HertzContact:
    """Hertz's elliptic contact (Johnson, Contact Mechanics, section 4.2) under ``load`` (N) for the relative
    radii of curvature ``radius_x`` along the rail and ``radius_y`` across it (m) and E* = ``modulus`` (Pa).

    With A = 1/(2 R) the smaller and B the larger relative curvature, the major semi-axis a lies along A's
    direction and, for m = e^2 = 1 - (b/a)^2 (eq. 4.39a fixes it from B/A),
    a^3 = 3 P (K - E) / (2 pi m A E*),  p0 = 3 P / (2 pi a b),  delta = p0 b K(e) / E*  (eqs. 4.36-4.38),
    and C = P / delta^1.5. Equal radii give the circle, a = b = (3 P R / (4 E*))^(1/3), delta = a^2 / R,
    C = (4/3) E* sqrt(R) (computed with those closed forms, so the paper's case is unchanged to the bit).

    Parameters
    ----------
    load : float
        Normal load P, N.
    radius_x, radius_y : float
        Relative radii of curvature along and across the rail, m.
    modulus : float
        E* = E / (2 (1 - nu^2)) for two bodies of one material, Pa.

    Returns
    -------
    HertzContact
        The semi-axes, peak pressure, approach and constant.

    References
    ----------
    K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985, section 4.2.

    Examples
    --------
    >>> from wheelrail.core.contact.hertz import elliptic_hertz
    >>> from wheelrail.core.parameters import ContactParameters
    >>> contact = elliptic_hertz(65e3, 0.39, 0.39, ContactParameters().reduced_modulus)
    >>> round(contact.semi_axis_along * 1e3, 2)   # mm, the paper's a
    5.48
    """
    if radius_x == radius_y:
        a = (3.0 * load * radius_x / (4.0 * modulus)) ** (1.0 / 3.0)
        constant = 4.0 / 3.0 * modulus * math.sqrt(radius_x)
        return HertzContact(a, a, 3.0 * load / (2.0 * math.pi * a**2), (load / constant) ** (2.0 / 3.0), constant)
    from scipy.special import ellipk, elliprd

    r_major, r_minor = max(radius_x, radius_y), min(radius_x, radius_y)
    m = _ellipse_eccentricity(r_major / r_minor)
    curvature = 1.0 / (2.0 * r_major)
    k_minus_e_over_m = elliprd(0.0, 1.0 - m, 1.0) / 3.0
    major = (3.0 * load * k_minus_e_over_m / (2.0 * math.pi * curvature * modulus)) ** (1.0 / 3.0)
    major = float(major)
    minor = major * math.sqrt(1.0 - m)
    p0 = 3.0 * load / (2.0 * math.pi * major * minor)
    approach = p0 * minor * float(ellipk(m)) / modulus
    a, b = (major, minor) if radius_x >= radius_y else (minor, major)
    return HertzContact(a, b, p0, approach, load / approach**1.5)


def hertz_force(compression, constant: float) -> np.ndarray:
    """Contact force of the Hertzian spring, eq. (12).

    Parameters
    ----------
    compression : array_like
        Delta zeta of eq. (14), m (negative = no contact).
    constant : float
        C_H of eq. (13), N/m^1.5.

    Returns
    -------
    ndarray
        F_n in N, same shape as ``compression``; 0 where compression < 0.

    Raises
    ------
    WheelrailError
        If ``compression`` is not finite numbers or ``constant`` not a positive number.

    See Also
    --------
    hertz_constant, hertz_stiffness, hertz_approach

    References
    ----------
    A. Pieringer, W. Kropp, D. J. Thompson, Wear 271 (2011) 328-338, eq. (12).

    Examples
    --------
    >>> from wheelrail.core.contact import hertz_constant, hertz_force
    >>> round(float(hertz_force(77.07e-6, hertz_constant())) / 1e3, 1)   # kN at the static approach
    65.0
    """
    compression = finite_array("hertz_force: compression", compression, "m")
    constant = checks.positive("hertz_force", "constant", constant, "N/m^1.5")
    positive = np.maximum(compression, 0.0)
    return constant * positive * np.sqrt(positive)


def hertz_stiffness(compression, constant: float) -> np.ndarray:
    """Tangent stiffness dF/d(Delta zeta) = 1.5 C_H Delta zeta^0.5 of eq. (12), N/m (0 out of contact).

    Parameters
    ----------
    compression : array_like
        Delta zeta, m.
    constant : float
        C_H, N/m^1.5.

    Returns
    -------
    ndarray
        N/m, same shape as ``compression``.

    Raises
    ------
    WheelrailError
        As :func:`hertz_force`.

    See Also
    --------
    hertz_force

    Examples
    --------
    >>> from wheelrail.core.contact import hertz_constant, hertz_stiffness
    >>> f"{float(hertz_stiffness(77.07e-6, hertz_constant())):.3g}"   # N/m: 1.5 F / delta
    '1.27e+09'
    """
    compression = finite_array("hertz_stiffness: compression", compression, "m")
    constant = checks.positive("hertz_stiffness", "constant", constant, "N/m^1.5")
    return 1.5 * constant * np.sqrt(np.maximum(compression, 0.0))


def hertz_approach(force, constant: float) -> np.ndarray:
    """Inverse of eq. (12): compression Delta zeta = (F / C_H)^(2/3), m, for F >= 0.

    Parameters
    ----------
    force : array_like
        F_n >= 0, N.
    constant : float
        C_H, N/m^1.5.

    Returns
    -------
    ndarray
        Delta zeta in m (77.07 um at 65 kN with the paper's values).

    Raises
    ------
    WheelrailError
        If ``force`` is not finite numbers >= 0 or ``constant`` not a positive number.

    See Also
    --------
    hertz_force

    Examples
    --------
    >>> from wheelrail.core.contact import hertz_approach, hertz_constant
    >>> round(float(hertz_approach(65e3, hertz_constant())) * 1e6, 2)   # um
    77.07
    """
    force = finite_array("hertz_approach: force", force, "N")
    constant = checks.positive("hertz_approach", "constant", constant, "N/m^1.5")
    if np.any(force < 0.0):
        raise WheelrailError(f"hertz_approach: force must be >= 0 N, got minimum {force.min()!r}")
    return (force / constant) ** (2.0 / 3.0)
