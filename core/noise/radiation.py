"""Sound radiation of the rail (own 2D boundary elements) and of the sleepers (baffled pistons).

Radiation efficiency sigma = W' / (rho c P <v_n^2>): the radiated power per unit length W' over that of a
plane wave from the same perimeter P and spatially averaged mean-square normal velocity <v_n^2> (Thompson,
*Railway Noise and Vibration*, 2009, ch. 2 defines it so; sigma -> 1 at high frequency).

**Rail, vertical motion (2D BEM, this module's own).** A long rail vibrating in a bending wave much longer
than its cross-section radiates like a 2D body (Thompson 2009, ch. 6; the TWINS rail model), so the radiation
per unit length is that of the cross-section moving rigidly up and down in the (x, y) plane. It is computed
with a collocation boundary-element method for the exterior Helmholtz problem (time convention e^{-i w t}):
for a point x on the boundary, ``p(x)/2 = sum_j [p_j dG/dn_j - G (i w rho v_n,j)]`` integrated over straight
constant elements, ``G = (i/4) H0^(1)(k r)`` (the free-space Green's function in 2D), the self-element's
integral of G in closed form (Struve functions), CHIEF points inside the section to remove the fictitious
interior resonances (Schenck 1968), solved in the least-squares sense. The section is a simplified I-shape
with the published principal dimensions of the 60E1 (UIC60) rail, EN 13674-1: height 172 mm, head width
72 mm, foot width 150 mm, web thickness 16.5 mm; the head depth (51 mm) and the foot thickness (11.5 mm at
its edge rising to 31.5 mm at the web) are approximate, giving 83 cm^2 against the 60E1's 76.7 cm^2
(60.2 kg/m). The rail is in free field: neither the ground nor the sleepers are in the model.

Validated (``tests/physics/test_noise_radiation.py``) against the exact radiation of a rigid circular
cylinder oscillating transversely: sigma = 2 / (pi k a |H1'(k a)|^2) (from the n = 1 cylindrical wave, e.g.
Morse & Ingard, *Theoretical Acoustics*, 1968, section 7.3). It has not been compared with the Southampton
rail-radiation data set (Knuth, Squicciarini & Thompson 2025), which is not available here.

**Rail, lateral motion.** The same section moving rigidly side to side (``direction="lateral"``: the normal
velocity v n_x), as TWINS radiates the rail's lateral vibration: the railhead's lateral velocity taken as the whole
section's, radiating as a 2D body (Thompson, *Railway Noise and Vibration*, 2009, section 6.5, the rail's radiation
ratios for vertical and lateral motion from 2D boundary elements; Thompson, Jones & Turner, *A study of the sound
radiation from railway rails*, 2003, the same idealisation). A section that also turns (lateral bending with
torsion, the foot held by the pads) moves its foot less than its head: taking the head's velocity for the whole
section overstates the lateral power, most where the rail twists about a point near its foot.

**Sleepers.** Each sleeper is a rigid piston in a rigid baffle (the ballast surface) with the half sleeper's
area per rail; a baffled circular piston of the same area: sigma = 1 - J1(2 k a) / (k a) (Kinsler et al.,
*Fundamentals of Acoustics*, 4th ed., 2000, section 7.5; Thompson 2009, ch. 6 uses the same idealisation).
Its bending modes are not modelled (the FE track's sleeper is a mass).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
import scipy.special as sps

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.checks import finite_array, real

AIR_DENSITY = 1.21  # kg/m^3, air at 20 degC, 101.325 kPa
SOUND_SPEED = 343.0  # m/s
EULER_GAMMA = 0.5772156649015329

# The simplified 60E1 section (m), counter-clockwise, y up from the rail foot; see the module docstring.
_H, _HEAD_W, _HEAD_D, _WEB_T = 0.172, 0.072, 0.051, 0.0165
_FOOT_W, _FOOT_EDGE, _FOOT_WEB = 0.150, 0.0115, 0.0315
UIC60_POLYGON = np.array(
    [
        (-_FOOT_W / 2, 0.0),
        (_FOOT_W / 2, 0.0),
        (_FOOT_W / 2, _FOOT_EDGE),
        (_WEB_T / 2, _FOOT_WEB),
        (_WEB_T / 2, _H - _HEAD_D),
        (_HEAD_W / 2, _H - _HEAD_D),
        (_HEAD_W / 2, _H),
        (-_HEAD_W / 2, _H),
        (-_HEAD_W / 2, _H - _HEAD_D),
        (-_WEB_T / 2, _H - _HEAD_D),
        (-_WEB_T / 2, _FOOT_WEB),
        (-_FOOT_W / 2, _FOOT_EDGE),
    ]
)
UIC60_CHIEF_POINTS = np.array(
    [
        (0.0, _H - _HEAD_D / 2),
        (0.013, _H - 0.3 * _HEAD_D),
        (0.0, 0.08),
        (-0.05, 0.008),
        (0.04, 0.01),
        (-0.02, _H - 0.7 * _HEAD_D),
    ]
)


def polygon_area(vertices) -> float:
    """Area (m^2) of a simple polygon given counter-clockwise (shoelace formula)."""
    v = finite_array("polygon_area: vertices", vertices, "m")
    if v.ndim != 2 or v.shape[1] != 2 or len(v) < 3:
        raise WheelrailError(f"polygon_area: vertices must be at least 3 (x, y) pairs (m), got shape {v.shape}")
    x, y = v[:, 0], v[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


@dataclass(frozen=True, eq=False)
class Boundary:
    """A closed boundary cut into straight constant elements (outward normals, counter-clockwise).

    Attributes: ``mid`` (n, 2) collocation points, ``normal`` (n, 2), ``length`` (n,), ``start``/``end`` (n, 2).
    """

    start: np.ndarray
    end: np.ndarray

    @property
    def mid(self) -> np.ndarray:
        return 0.5 * (self.start + self.end)

    @property
    def length(self) -> np.ndarray:
        return np.linalg.norm(self.end - self.start, axis=1)

    @property
    def normal(self) -> np.ndarray:
        t = (self.end - self.start) / self.length[:, None]
        return np.stack([t[:, 1], -t[:, 0]], axis=1)  # outward for a counter-clockwise boundary

    @property
    def perimeter(self) -> float:
        return float(self.length.sum())


def discretise(vertices, max_element: float) -> Boundary:
    """Cut each side of a counter-clockwise polygon into equal elements no longer than ``max_element`` m."""
    v = np.asarray(vertices, dtype=float)
    if polygon_area(v) <= 0:
        raise WheelrailError("boundary polygon must be given counter-clockwise with a positive area")
    starts, ends = [], []
    for a, b in zip(v, np.roll(v, -1, axis=0), strict=True):
        n = max(1, math.ceil(np.linalg.norm(b - a) / max_element))
        s = np.linspace(0.0, 1.0, n + 1)
        pts = a + s[:, None] * (b - a)
        starts.append(pts[:-1])
        ends.append(pts[1:])
    return Boundary(start=np.concatenate(starts), end=np.concatenate(ends))


def circle(radius: float, n: int) -> np.ndarray:
    """A regular n-gon inscribed in a circle, counter-clockwise (for the validation against the cylinder)."""
    t = 2 * np.pi * np.arange(n) / n
    return np.stack([radius * np.cos(t), radius * np.sin(t)], axis=1)


_GAUSS_FAR = np.polynomial.legendre.leggauss(4)
_GAUSS_NEAR = np.polynomial.legendre.leggauss(20)


def _self_integral_g(k: float, length: np.ndarray) -> np.ndarray:
    """Integral of (i/4) H0(k|s|) over a straight element of ``length`` centred on the collocation point.

    Closed forms (Abramowitz & Stegun 11.1.7, 11.1.8): int_0^x J0 = x J0 + pi x/2 (J1 H0 - J0 H1) and the same
    with Y; H0, H1 here are Struve functions.
    """
    x = k * length / 2
    s0, s1 = sps.struve(0, x), sps.struve(1, x)
    int_j0 = x * sps.j0(x) + np.pi * x / 2 * (sps.j1(x) * s0 - sps.j0(x) * s1)
    int_y0 = x * sps.y0(x) + np.pi * x / 2 * (sps.y1(x) * s0 - sps.y0(x) * s1)
    return (1j / 4) * 2 * (int_j0 + 1j * int_y0) / k


def _pair_integrals(points, a, b, normal, length, k, rule):
    """int G and int dG/dn_y over elements (a, b) seen from ``points``, for matching 1D arrays of pairs."""
    nodes, weights = rule
    s = 0.5 * (nodes + 1.0)
    y = a[:, None, :] + s[None, :, None] * (b - a)[:, None, :]  # (pair, q, 2)
    diff = y - points[:, None, :]
    r = np.linalg.norm(diff, axis=2)
    kr = k * r
    w = 0.5 * weights[None, :] * length[:, None]
    g = np.sum(w * (1j / 4) * sps.hankel1(0, kr), axis=1)
    proj = np.einsum("pqu,pu->pq", diff, normal) / r
    dg = np.sum(w * (-(1j * k / 4)) * sps.hankel1(1, kr) * proj, axis=1)
    return g, dg


def _influence(points: np.ndarray, boundary: Boundary, k: float, self_rows: bool):
    """Matrices G[i, j] = int_j G(x_i, y) dS and D[i, j] = int_j dG/dn_y(x_i, y) dS.

    4 Gauss points per element in general, 20 where the point is within two element lengths (the
    neighbours), the closed form on the element itself.
    """
    n_el = len(boundary.length)
    a, b, normal, length = boundary.start, boundary.end, boundary.normal, boundary.length
    dist = np.linalg.norm(points[:, None, :] - boundary.mid[None, :, :], axis=2)
    near = dist < 2.0 * length[None, :]
    if self_rows:
        near[np.arange(n_el), np.arange(n_el)] = False
    G = np.zeros(dist.shape, dtype=complex)
    D = np.zeros(dist.shape, dtype=complex)
    for mask, rule in ((~near, _GAUSS_FAR), (near, _GAUSS_NEAR)):
        if self_rows:
            mask = mask & ~np.eye(n_el, dtype=bool)
        i, j = np.nonzero(mask)
        if len(i):
            G[i, j], D[i, j] = _pair_integrals(points[i], a[j], b[j], normal[j], length[j], k, rule)
    if self_rows:
        idx = np.arange(n_el)
        G[idx, idx] = _self_integral_g(k, length)
        D[idx, idx] = 0.0  # flat element: (y - x) . n = 0
    return G, D


def radiated_power(
    boundary: Boundary,
    normal_velocity: np.ndarray,
    frequency: float,
    chief_points=None,
    rho: float = AIR_DENSITY,
    c: float = SOUND_SPEED,
) -> float:
    """Time-averaged power per unit length (W/m) radiated by the boundary's normal velocity amplitudes (m/s)."""
    k = 2 * np.pi * frequency / c
    omega = 2 * np.pi * frequency
    vn = np.asarray(normal_velocity, dtype=complex)
    G, D = _influence(boundary.mid, boundary, k, self_rows=True)
    A = D - 0.5 * np.eye(len(vn))
    rhs = G @ (1j * omega * rho * vn)
    if chief_points is not None and len(chief_points):
        Gc, Dc = _influence(np.asarray(chief_points, dtype=float), boundary, k, self_rows=False)
        A = np.vstack([A, Dc])
        rhs = np.concatenate([rhs, Gc @ (1j * omega * rho * vn)])
    p = np.linalg.lstsq(A, rhs, rcond=None)[0]
    return float(0.5 * np.real(np.sum(p * np.conj(vn) * boundary.length)))


def vertical_radiation_efficiency(
    boundary: Boundary, frequency, chief_points=None, rho: float = AIR_DENSITY, c: float = SOUND_SPEED
) -> np.ndarray:
    """sigma of the section moving rigidly up and down (unit vertical velocity), at each frequency (Hz)."""
    return section_radiation_efficiency(boundary, frequency, "vertical", chief_points, rho, c)


DIRECTIONS = {"lateral": 0, "vertical": 1}  # a rigid section's motion: the component of its normals it moves


def section_radiation_efficiency(
    boundary: Boundary,
    frequency,
    direction: str = "vertical",
    chief_points=None,
    rho: float = AIR_DENSITY,
    c: float = SOUND_SPEED,
) -> np.ndarray:
    """sigma of the section moving rigidly in ``direction`` ("vertical": up and down; "lateral": side to side),
    a unit velocity, at each frequency (Hz): W' / (rho c P <v_n^2>) with v_n the normal component of the motion."""
    if direction not in DIRECTIONS:
        raise WheelrailError(f"section_radiation_efficiency: direction {direction!r}; one of {', '.join(DIRECTIONS)}")
    vn = boundary.normal[:, DIRECTIONS[direction]].astype(complex)  # normal component of a unit velocity
    mean_square = 0.5 * float(np.sum(np.abs(vn) ** 2 * boundary.length)) / boundary.perimeter
    out = []
    for f in np.atleast_1d(frequency):
        power = radiated_power(boundary, vn, float(f), chief_points, rho, c)
        out.append(power / (rho * c * boundary.perimeter * mean_square))
    return np.asarray(out)


def cylinder_radiation_efficiency(ka) -> np.ndarray:
    """Exact sigma of a rigid circular cylinder oscillating transversely: 2 / (pi ka |H1'(ka)|^2)."""
    ka = finite_array("cylinder_radiation_efficiency: ka", ka, "-")
    if np.any(ka <= 0):
        raise WheelrailError("cylinder_radiation_efficiency: ka must be positive")
    # beyond these the Hankel function over- or underflows; its limits there (the 2D dipole's pi (ka)^3 / 2 and
    # the plane piston's 1) are within 1e-5 of the exact form
    small, large = ka < 1e-3, ka > 1e4
    inside = np.where(small | large, 1.0, ka)
    exact = 2.0 / (np.pi * inside * np.abs(sps.h1vp(1, inside)) ** 2)
    return np.where(small, np.pi * np.minimum(ka, 1e-3) ** 3 / 2.0, np.where(large, 1.0, exact))


# BEM mesh: elements of at most lambda / 8 and 10 mm. Halving to 5 mm changes sigma by 0.03 dB at 1-3.15 kHz, and
# the power through a circle 5 m away equals the surface power within 0.5 % (tests/physics/test_noise_radiation.py).
RAIL_ELEMENTS_PER_WAVELENGTH = 8
RAIL_MAX_ELEMENT = 0.010  # m
RAIL_TABLE_HZ = (20.0, 12500.0, 68)  # log grid of the cached sigma table: 24 points per decade


def rail_boundary(
    frequency: float, per_wavelength: int = RAIL_ELEMENTS_PER_WAVELENGTH, max_element: float = RAIL_MAX_ELEMENT
) -> Boundary:
    """The 60E1 section's BEM mesh for ``frequency`` (Hz): elements of at most lambda / per_wavelength."""
    frequency = real("rail_boundary: frequency", frequency, "Hz")
    # the mesh grows as f: above 1 MHz (elements of 43 um) no audible question is asked
    if frequency > 1e6:
        raise WheelrailError(f"rail_boundary: frequency {frequency:g} Hz is above 1 MHz")
    return discretise(UIC60_POLYGON, max_element=min(max_element, SOUND_SPEED / frequency / per_wavelength))


@functools.cache
def _rail_sigma_table(direction: str = "vertical") -> tuple[np.ndarray, np.ndarray]:
    """sigma of the 60E1 section moving in ``direction`` on :data:`RAIL_TABLE_HZ` (disk-cached by content: a
    boundary-element solve per frequency of the grid)."""
    from wheelrail.core.files.cache import cache_key, load_entry, save_entry

    f = np.geomspace(*RAIL_TABLE_HZ)
    key = cache_key(
        "rail-radiation",
        {
            "polygon": UIC60_POLYGON.tolist(),
            "chief": UIC60_CHIEF_POINTS.tolist(),
            "grid": list(RAIL_TABLE_HZ),
            "per_wavelength": RAIL_ELEMENTS_PER_WAVELENGTH,
            "max_element": RAIL_MAX_ELEMENT,
            "rho": AIR_DENSITY,
            "c": SOUND_SPEED,
            "version": 1,
            **({} if direction == "vertical" else {"direction": direction}),  # the vertical table's key as it was
        },
    )
    entry = load_entry("rail-radiation", key, ("sigma",))
    if entry is not None:
        return f, entry["sigma"]
    sigma = np.asarray(
        [section_radiation_efficiency(rail_boundary(fi), fi, direction, UIC60_CHIEF_POINTS)[0] for fi in f]
    )
    save_entry("rail-radiation", key, {"sigma": sigma})
    return f, sigma


def rail_radiation_efficiency(frequency) -> np.ndarray:
    """sigma of the 60E1 rail in vertical motion at ``frequency`` (Hz), from the BEM (interpolated in lg f; below
    the table's 20 Hz as f^3, the 2D dipole's law: sigma = pi (ka)^3 / 2 for a cylinder, from the small-argument
    H1'; :func:`decaying_rail_radiation` asks for the reduced frequencies c k_r / 2 pi down to 0)."""
    return _rail_sigma(frequency, "vertical")


def lateral_rail_radiation_efficiency(frequency) -> np.ndarray:
    """sigma of the 60E1 rail moving rigidly side to side at ``frequency`` (Hz), from the same BEM (module
    docstring: the TWINS rail's lateral radiation, the section's rigid lateral motion, Thompson 2009, ch. 6);
    interpolated in lg f, below the table's 20 Hz as f^3 (the 2D dipole's law)."""
    return _rail_sigma(frequency, "lateral")


def _rail_sigma(frequency, direction: str) -> np.ndarray:
    f = finite_array("rail_radiation_efficiency: frequency", frequency, "Hz")
    if np.any(f <= 0):
        raise WheelrailError("rail_radiation_efficiency: frequency must be positive (Hz)")
    f_tab, s_tab = _rail_sigma_table(direction)
    inside = 10 ** np.interp(np.log10(f), np.log10(f_tab), np.log10(s_tab))
    return np.where(f < f_tab[0], s_tab[0] * (np.minimum(f, f_tab[0]) / f_tab[0]) ** 3, inside)


def decaying_rail_radiation(velocity, dx: float, frequency: float, sigma=None, c: float = SOUND_SPEED) -> float:
    """The rail's radiation from a vibration field that varies along it, in the wavenumber domain: the quantity
    Q (m^3/s^2) such that the radiated power is W = rho c P <n_y^2> Q.

    A rail whose vertical velocity v(x) (amplitudes on a uniform grid of spacing ``dx`` m) varies along x radiates,
    per axial wavenumber k_x, as the 2D cross-section at the reduced wavenumber k_r = sqrt(k^2 - k_x^2); only the
    supersonic part |k_x| < k radiates (Thompson, *Railway Noise and Vibration*, 2009, ch. 6, the TWINS rail model
    for a decaying wave; the k / k_r factor is the supersonic plate's 1 / sqrt(1 - (k_x/k)^2), Fahy & Gardonio,
    *Sound and Structural Vibration*, 2007, ch. 3):

        Q = (1 / 2 pi) int_{|k_x| < k} |V(k_x)|^2 (k / k_r) sigma_2D(c k_r / 2 pi) dk_x,  V = int v e^{-i k_x x} dx

    For a field that varies slowly (|V|^2 within |k_x| << k), Q = sigma_2D(f) int |v|^2 dx (Parseval): the 2D
    ratio applied to the whole field (the plain 2D estimate). A field that
    decays fast (beta = 1.3 /m at 50 Hz on the paper's track, against k = 0.92 rad/m) puts much of its spectrum
    at |k_x| > k, where it does not radiate. ``sigma``: sigma_2D as a function of frequency (default
    :func:`rail_radiation_efficiency`); the grid is zero-padded to twice its length (k_x steps of pi / (n dx)).
    """
    v = np.asarray(velocity, dtype=complex).ravel()
    sigma = rail_radiation_efficiency if sigma is None else sigma
    k = 2 * np.pi * float(frequency) / c
    n = 2 * len(v)
    spectrum = dx * np.fft.fft(v, n)  # V(k_x) on k_x = 2 pi m / (n dx)
    kx = 2 * np.pi * np.fft.fftfreq(n, dx)
    supersonic = np.abs(kx) < k
    kr = np.sqrt(k**2 - kx[supersonic] ** 2)
    weight = np.zeros(n)
    positive = kr > 0
    weight_s = np.zeros(kr.shape)
    weight_s[positive] = k / kr[positive] * sigma(c * kr[positive] / (2 * np.pi))
    weight[supersonic] = weight_s
    step = 2 * np.pi / (n * dx)
    return float(np.sum(np.abs(spectrum) ** 2 * weight) * step / (2 * np.pi))


def rail_section() -> dict:
    """What :func:`rail_radiation_efficiency` and :func:`lateral_rail_radiation_efficiency` radiate: perimeter
    (m), mean of n_y^2 (vertical) and n_x^2 (lateral) over it, area (m^2)."""
    boundary = discretise(UIC60_POLYGON, max_element=0.002)
    ny2 = float(np.sum(boundary.normal[:, 1] ** 2 * boundary.length) / boundary.perimeter)
    nx2 = float(np.sum(boundary.normal[:, 0] ** 2 * boundary.length) / boundary.perimeter)
    return {
        "perimeter_m": boundary.perimeter,
        "mean_normal_y_squared": ny2,
        "mean_normal_x_squared": nx2,
        "area_m2": polygon_area(UIC60_POLYGON),
    }


def piston_radiation_efficiency(frequency, area: float, c: float = SOUND_SPEED) -> np.ndarray:
    """sigma of a baffled circular piston of ``area`` (m^2): 1 - J1(2ka)/(ka), a = sqrt(area / pi)."""
    a = math.sqrt(area / math.pi)
    ka = 2 * np.pi * np.asarray(frequency, dtype=float) / c * a
    return 1.0 - sps.j1(2 * ka) / ka
