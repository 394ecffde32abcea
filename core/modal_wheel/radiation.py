"""Sound radiation of a railway wheel's vibration, per mode family: axial and radial motion with n nodal diameters.

The wheel's sound power in a band is, per direction d (axial, radial) and number of nodal diameters n,

    W = rho c S_d sigma_d,n(f) <v_d,n^2>                                             (1)

with S_d the radiating area of that direction (both faces of the web and tyre for axial motion, the tread and
flange's outer cylinder for radial motion), <v^2> the spatially averaged mean-square normal velocity on it and
sigma the radiation efficiency (Thompson, *Railway Noise and Vibration*, 2009, ch. 2 and 5: TWINS computes the
wheel's power so, sigma per mode family from the wheel's geometry).

**Which radiation efficiency.** TWINS uses the simplified formulae of Thompson & Jones ("Sound radiation from a
vibrating railway wheel", J. Sound Vib. 253 (2002) 401-419; reformulated later in "A reformulation of the
simplified model for railway wheel radiation"), fitted to axisymmetric boundary-element results: sigma per n and
direction as a function of f and the wheel radius, tyre width and web. Their equations and coefficients were not
found in any source available to this project (the papers' abstracts only), so they are **not** used here: no
coefficient of theirs is restated from memory. Instead sigma is that of an exactly solvable idealisation of each
family, computed here and validated against closed forms (``tests/physics/test_wheel_radiation.py``):

- **Axial motion, n nodal diameters** (:func:`disc_radiation_efficiency`): one face of the wheel as a flat
  annulus (hub radius a_i to the tyre's outer radius a) in a rigid baffle, normal velocity v0 cos(n theta) uniform
  along the radius. The Rayleigh integral in the wavenumber domain (e.g. Fahy & Gardonio, *Sound and Structural
  Vibration*, 2nd ed., 2007, ch. 3; Williams, *Fourier Acoustics*, 1999, ch. 2): with
  F_n(kappa) = int_{a_i}^{a} J_n(kappa r) r dr,

      sigma = 2 k^2 / (a^2 - a_i^2) int_0^{pi/2} F_n(k sin t)^2 sin t dt                  (2)

  (kappa = k sin t removes the 1/sqrt(k^2 - kappa^2) singularity; only the supersonic part kappa < k radiates).
  Known answers: n = 0, a_i = 0 is the baffled piston, 1 - J1(2 k a)/(k a); at low frequency
  sigma -> 2 (k a)^(2n+2) / ((n+2)^2 (2n+1)!) (from the first term of J_n); sigma -> 1 well above the
  coincidence k a ~ n + 1 (the circumferential bending wavelength 2 pi a / n meeting the acoustic one: the
  n-dependent "critical frequency" f_n ~ (n + 1) c / (2 pi a)).
- **Radial motion, n nodal diameters** (:func:`band_radiation_efficiency`): the tyre's running surface as a band of
  width b on a rigid infinite cylinder of radius a (a cylindrical baffle), radial velocity v0 cos(n theta) on
  |z| < b/2. With the axial wavenumber transform V(k_z) = v0 2 sin(k_z b/2)/k_z and k_r = sqrt(k^2 - k_z^2)
  (Junger & Feit, *Sound, Structures, and Their Interaction*, 2nd ed., 1986, ch. 6; Williams 1999, ch. 4: the
  Wronskian J_n Y_n' - J_n' Y_n = 2 / (pi x) gives the real part of the modal impedance),

      sigma = k / (pi^2 a b v0^2) int_{-k}^{k} |V(k_z)|^2 / (k_r^2 |H_n'(k_r a)|^2) dk_z          (3)

  Known answer: for b -> infinity, the infinite cylinder's 2 / (pi k a |H_n'(k a)|^2) (e.g. Morse & Ingard,
  *Theoretical Acoustics*, 1968, section 7.3; the rail module checks its BEM against it for n = 1).

What the idealisations leave out, and in which direction: the wheel is not baffled, so below k a ~ 1 (about
120 Hz for a 920 mm wheel) the axial n = 0 and n = 1 families radiate as dipoles (the two faces in antiphase,
sigma ~ (k a)^4) rather than as baffled pistons (~ (k a)^2): eq. (2) overstates them there; the tyre's radial
motion is not in a cylindrical baffle either (the flanks end it), so eq. (3) overstates its n = 0 family below
k b ~ 1 (about 400 Hz). Both are below the bands where the wheel dominates rolling noise (above about 1.6-2 kHz;
Thompson 2009, ch. 5). The velocity's shape along the radius (web modes concentrate near the tyre) is taken as
uniform.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.special as sps

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.checks import finite_array
from wheelrail.core.noise.radiation import AIR_DENSITY, SOUND_SPEED

__all__ = [
    "DIRECTIONS",
    "band_radiation_efficiency",
    "disc_radiation_efficiency",
    "radiated_power",
    "radiation_summary",
    "wheel_radiation_efficiency",
]

DIRECTIONS = ("axial", "radial")
MAX_NODAL_DIAMETERS = 40  # n beyond any wheel mode below 10 kHz (TWINS uses n <= 10; Thompson 2009, ch. 5)
# Gauss-Legendre points of eqs. (2) and (3) per frequency: the integrands oscillate as k a sin t (k b sin t for
# the band's ends); 48 + 2 k a points hold sigma within 1e-9 of twice as many (tests/physics/test_wheel_radiation.py)
_MIN_POINTS = 48
_POINTS_PER_KA = 2.0


def _frequencies(where: str, frequency) -> np.ndarray:
    f = finite_array(f"{where}: frequency", frequency, "Hz")
    if np.any(f <= 0):
        raise WheelrailError(f"{where}: frequency must be positive (Hz)")
    return f


def _order(where: str, n) -> int:
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or not 0 <= n <= MAX_NODAL_DIAMETERS:
        raise WheelrailError(
            f"{where}: n (nodal diameters) must be a whole number 0 to {MAX_NODAL_DIAMETERS}, got {n!r}"
        )
    return int(n)


def _length(where: str, name: str, value, minimum: float = 0.0) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating) or not math.isfinite(value):
        raise WheelrailError(f"{where}: {name} must be a finite length (m), got {value!r}")
    if not minimum <= value <= 5.0:
        raise WheelrailError(f"{where}: {name} must be {minimum:g} to 5 m, got {value!r} m")
    return float(value)


def disc_radiation_efficiency(frequency, radius: float, n: int, inner_radius: float = 0.0, c: float = SOUND_SPEED):
    """sigma of a baffled flat annulus (``inner_radius`` to ``radius``, m) whose normal velocity is v0 cos(n theta),
    uniform along the radius, at ``frequency`` (Hz): eq. (2) of the module docstring (the wheel's axial motion)."""
    where = "disc_radiation_efficiency"
    f = _frequencies(where, frequency)
    a = _length(where, "radius", radius, 1e-3)
    a_i = _length(where, "inner_radius", inner_radius)
    if a_i >= a:
        raise WheelrailError(f"{where}: inner_radius {a_i:g} m must be below radius {a:g} m")
    n = _order(where, n)
    k = 2 * np.pi * np.atleast_1d(f).ravel() / c
    sigma = np.array([_disc_sigma(ki, a, a_i, n) for ki in k])
    return sigma.reshape(np.shape(f))


def _gauss(points: int, low: float, high: float) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(points)
    return low + (high - low) / 2 * (x + 1), (high - low) / 2 * w


def _points(ka: float) -> int:
    """Gauss points for an integrand oscillating as k a sin t (or kappa r): 2 per unit of k a and 48 more."""
    return _MIN_POINTS + int(math.ceil(_POINTS_PER_KA * ka))


def _disc_sigma(k: float, a: float, a_i: float, n: int) -> float:
    """Eq. (2) at one wavenumber k (rad/m)."""
    t, wt = _gauss(_points(k * a), 0.0, np.pi / 2)
    r, wr = _gauss(_points(k * a), a_i, a)
    kappa = k * np.sin(t)
    transform = sps.jv(n, kappa[:, None] * r[None, :]) @ (wr * r)  # F_n(kappa)
    return float(2 * k**2 / (a**2 - a_i**2) * np.sum(wt * transform**2 * np.sin(t)))


def band_radiation_efficiency(frequency, radius: float, width: float, n: int, c: float = SOUND_SPEED):
    """sigma of a band of ``width`` (m) on a rigid infinite cylinder of ``radius`` (m) vibrating radially with
    v0 cos(n theta), at ``frequency`` (Hz): eq. (3) of the module docstring (the wheel's radial motion)."""
    where = "band_radiation_efficiency"
    f = _frequencies(where, frequency)
    a = _length(where, "radius", radius, 1e-3)
    b = _length(where, "width", width, 1e-3)
    n = _order(where, n)
    k = 2 * np.pi * np.atleast_1d(f).ravel() / c
    sigma = np.array([_band_sigma(ki, a, b, n) for ki in k])
    return sigma.reshape(np.shape(f))


def _band_sigma(k: float, a: float, b: float, n: int) -> float:
    """Eq. (3) at one wavenumber k (rad/m); the integrand is even in k_z: twice the half k_z = k sin t, t in
    (0, pi/2), dk_z = k cos t dt."""
    t, wt = _gauss(_points(k * max(a, b)), 0.0, np.pi / 2)
    kz, kr = k * np.sin(t), k * np.cos(t)
    v_sq = (b * np.sinc(kz * b / (2 * np.pi))) ** 2  # |V / v0|^2 = (2 sin(k_z b/2) / k_z)^2
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        h_sq = np.abs(sps.h1vp(n, kr * a)) ** 2
        kernel = np.where(np.isfinite(h_sq) & (h_sq > 0), 1.0 / (kr**2 * h_sq), 0.0)  # -> 0 as k_r -> 0, n >= 1
    if n == 0:  # |H_0'(x)|^2 = |H_1(x)|^2 ~ (2 / (pi x))^2: the kernel tends to (pi a / 2)^2
        kernel = np.where(kr * a < 1e-8, (np.pi * a / 2) ** 2, kernel)
    return float(k / (np.pi**2 * a * b) * 2 * np.sum(wt * v_sq * kernel * kr))


def wheel_radiation_efficiency(
    frequency, n: int, direction: str, *, radius: float, tyre_width: float, hub_radius: float = 0.0
) -> np.ndarray:
    """sigma of the wheel's ``direction`` ("axial" or "radial") motion with ``n`` nodal diameters at ``frequency``
    (Hz), for a wheel of outer ``radius`` (m, the tyre's), ``tyre_width`` (m, the running surface's width) and
    ``hub_radius`` (m): the axial family by eq. (2) on the annulus hub to tyre, the radial one by eq. (3)."""
    if direction == "axial":
        return disc_radiation_efficiency(frequency, radius, n, inner_radius=hub_radius)
    if direction == "radial":
        return band_radiation_efficiency(frequency, radius, tyre_width, n)
    raise WheelrailError(
        f"wheel_radiation_efficiency: direction must be one of {', '.join(DIRECTIONS)}, got {direction!r}"
    )


def radiated_power(mean_square_velocity, area: float, sigma, rho: float = AIR_DENSITY, c: float = SOUND_SPEED):
    """Eq. (1): W = rho c S sigma <v^2> (W), with <v^2> the spatially averaged mean-square normal velocity
    ((m/s)^2, rms), S the radiating area (m^2) and sigma the radiation efficiency; arrays broadcast."""
    v_sq = finite_array("radiated_power: mean_square_velocity", mean_square_velocity, "(m/s)^2")
    s = finite_array("radiated_power: sigma", sigma, "-")
    if np.any(v_sq < 0) or np.any(s < 0):
        raise WheelrailError("radiated_power: mean_square_velocity and sigma must be >= 0")
    if (
        isinstance(area, bool)
        or not isinstance(area, int | float | np.floating)
        or not (math.isfinite(area) and area > 0)
    ):
        raise WheelrailError(f"radiated_power: area must be a positive number (m^2), got {area!r}")
    return rho * c * float(area) * s * v_sq


def radiation_summary(profile, frequencies) -> dict:
    """The radiation efficiency of every family of a wheel ``profile`` (a ``WheelProfile``; its running radius,
    tyre width and bore) at ``frequencies`` (Hz), for ``wheelrail wheel``'s summary: ``frequency_hz``, ``axial`` and
    ``radial`` (each a list over n = 0..10 of sigma at the frequencies) and ``model`` (what sigma is, in words)."""
    f = _frequencies("radiation_summary", frequencies)
    geometry = {"radius": profile.wheel_radius, "tyre_width": profile.tyre_width, "hub_radius": profile.bore_radius}
    return {
        "frequency_hz": f,
        **{
            d: [wheel_radiation_efficiency(f, n, d, **geometry) for n in range(11)]
            for d in DIRECTIONS  # n = 0..10: the chain's harmonics
        },
        "model": "axial n: a baffled annulus bore to running radius; radial n: the tread's band on a cylindrical "
        "baffle (wheelrail.core.modal_wheel.radiation, eqs. 2 and 3)",
    }
