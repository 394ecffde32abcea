"""Reference contact filters: the CNOSSOS-EU A3 table and the analytic filters of the literature.

A contact filter |H|^2 is the ratio of the mean square of the roughness the contact "sees" to that of
the roughness on one line; its level ``10 log10 |H|^2`` (dB, <= 0) is what the time-domain models give as
the level difference of Fig. 10 (``wheelrail.core.study.contact_filter``). Two kinds of reference:

**CNOSSOS-EU contact filter A3** (Commission Directive (EU) 2015/996, Annex II Appendix G, Table G-2, as
replaced by Commission Delegated Directive (EU) 2021/1226, Annex point (20)(b)): five columns, wheel load
25/50/100 kN and wheel diameter 360/680/920 mm, on the 35 wavelength bands 2000 .. 0.8 mm
(:data:`wheelrail.core.spectra.bands.CNOSSOS_WAVELENGTH_RANGE`). :data:`CNOSSOS_A3` holds the values cell by cell
as two public implementations print them, which agree in every cell: Universite-Gustave-Eiffel/
NoiseModelling, ``noisemodelling-emission/src/main/resources/org/noise_planet/noisemodelling/emission/
railway/RailwayCnossosEU_2020.json`` (entries ``ContactFilter`` 3..7), and jmrplens/phonometry, whose
CNOSSOS railway source module transcribes "Table G-2 - contact filter A_3,i, as replaced by (EU)
2021/1226 Annex point (20)(b)" (which notes that 2021/1226 reads "wheel load" where 2015/996 read "axle
load", and changed the column order and the values).

Other loads and diameters (:func:`cnossos_filter`): each column is read as a function of wavelength over
the Hertz semi-axis along the rail, a(P, R) = (3 P R / (4 E*))^(1/3) of the circular contact of
:class:`wheelrail.core.parameters.ContactParameters` with R the wheel radius: the column is shifted in
log wavelength by the ratio of semi-axes and the two columns whose semi-axes bracket the wanted one are
interpolated linearly in log a (outside the tabulated range, the nearest column alone); bands the shifted
columns do not cover are NaN. Every column rebuilt this way from its neighbours alone is within
:data:`CNOSSOS_RULE_ERROR_DB` of the table (``tests/physics/test_reference_filters.py``; why the worst case
is what it is: the documentation's physics page, "Reference filters").

**Analytic filters**, for a contact patch of semi-axis a along the rail, as band levels averaged over each band
(the mean of |H(k)|^2 over the band's wavenumbers, i.e. the filter white roughness sees; not |H|^2 at
the centre), with k the angular wavenumber 2 pi / lambda:

- ``averaging``: the roughness averaged uniformly over the contact length 2a,
  |H|^2 = (sin ka / ka)^2 (the ``hertz-average`` model's prefilter, paper eq. 19 dips at lambda = 2a/n);
- ``patch-correlated``: averaged over the elliptical (here circular) patch, roughness identical across
  its width: the chord 2a sqrt(1 - x^2/a^2) weights the line, |H|^2 = (2 J1(ka) / ka)^2 (these two are the
  filters of the literature: Remington 1987; Remington & Webb 1996; Thompson, *Railway Noise and
  Vibration*, 2009, ch. 5);
- ``patch-incoherent``, **this project's construction** (not a filter of those sources, nor checked
  against measurements; the counterpart of ``patch-correlated`` for roughness with no lateral coherence):
  averaged over the patch, roughness of independent lateral strips (incoherent
  across the width): each strip at lateral position y = b u averages its own line over its chord
  2c = 2a sqrt(1 - u^2) and carries the area share w ∝ c, so
  |H|^2 = ∫ (1 - u^2) (sin kc / kc)^2 du / ∫ (1 - u^2) du over 0 <= u <= 1.
  With u = sin(theta) the integral is closed: |H|^2 = 3 pi H1(2ka) / (8 (ka)^2), H1 the Struve function.
  It is normalised to 0 dB at long wavelengths: the absolute reduction by averaging independent strips
  depends on how many the patch holds (the lateral correlation length), not on the patch; the shape does
  not. It falls as 0.75 / (ka)^2 at short wavelength, slower than the correlated (2 J1/x)^2 ~ (ka)^-3.

Everything is SI: loads in N, radii and semi-axes in m, wavelengths in m, speeds in m/s; levels in dB.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.special

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.ranges import ACCEPTED
from wheelrail.core.parameters import ContactParameters
from wheelrail.core.spectra.bands import FORCE_BAND_RANGE, Bands, frequency_bands, map_levels, wavelength_bands

ANALYTIC_FILTERS = ("averaging", "patch-correlated", "patch-incoherent")
REFERENCE_FILTERS = ("cnossos", *ANALYTIC_FILTERS)
CNOSSOS_RULE_ERROR_DB = 3.2  # dB: worst band of any column rebuilt from its neighbours (see module docstring)

# Table G-2, A3 in dB on the 35 wavelength bands 2000 .. 0.8 mm (long first); keys (wheel load N,
# wheel diameter m). Cells as printed by the two sources cited in the module docstring.
_ZEROS = (0.0,) * 11
# fmt: off
CNOSSOS_A3: dict[tuple[float, float], tuple[float, ...]] = {
    (50e3, 0.360): _ZEROS + (
        0.0, 0.0, 0.0, -0.1, -0.2, -0.3, -0.6, -1.0, -1.8, -3.2, -5.4, -8.7,
        -12.2, -16.7, -17.7, -17.8, -20.7, -22.1, -22.8, -24.0, -24.5, -24.7, -27.0, -27.8,
    ),
    (50e3, 0.680): _ZEROS + (
        0.0, 0.0, -0.1, -0.2, -0.3, -0.7, -1.2, -2.0, -4.1, -6.0, -9.2, -13.8,
        -17.2, -17.7, -18.6, -21.5, -22.3, -23.1, -24.4, -24.5, -25.0, -28.0, -28.8, -29.6,
    ),
    (50e3, 0.920): _ZEROS + (
        0.0, -0.1, -0.1, -0.3, -0.6, -1.1, -1.3, -3.5, -5.3, -8.0, -12.0, -16.8,
        -17.7, -18.0, -21.5, -21.8, -22.8, -24.0, -24.5, -25.0, -27.3, -28.1, -28.9, -29.7,
    ),
    (25e3, 0.920): _ZEROS + (
        0.0, 0.0, 0.0, -0.1, -0.3, -0.5, -1.1, -1.8, -3.3, -5.3, -7.9, -12.8,
        -16.8, -17.7, -18.2, -20.5, -22.0, -22.8, -24.2, -24.5, -25.0, -27.4, -28.2, -29.0,
    ),
    (100e3, 0.920): _ZEROS + (
        -0.1, -0.2, -0.3, -0.6, -1.0, -1.8, -3.2, -5.4, -8.7, -12.2, -16.7, -17.7,
        -17.8, -20.7, -22.1, -22.8, -24.0, -24.5, -24.7, -27.0, -27.8, -28.6, -29.4, -30.2,
    ),
}
# fmt: on


def _positive(value, name: str, unit: str) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise WheelrailError(f"{name} must be a number in {unit}, got {value!r}") from None
    if not (math.isfinite(number) and number > 0):
        raise WheelrailError(f"{name} must be a positive number in {unit}, got {value!r}")
    return number


def hertz_semi_axes(contact: ContactParameters, load: float | None = None) -> tuple[float, float]:
    """Contact semi-axes (a along the rail, b across), m, of the Hertz contact of ``contact`` at ``load`` N.

    :meth:`ContactParameters.hertz_semi_axes`: a follows the wheel's rolling radius, b the relative radius
    across (rail crown and tread); the paper's circle (both radii 0.39 m) gives a = b = 5.48 mm at 65 kN.
    """
    return contact.hertz_semi_axes(contact.preload if load is None else _positive(load, "load", "N"))


def _column_semi_axis(load: float, diameter: float, contact: ContactParameters) -> float:
    """The rule's semi-axis of a column: the circular contact of radius D/2 (whatever ``contact``'s geometry)."""
    circle = replace(
        contact,
        radius=0.5 * diameter,
        wheel_radius=None,
        rail_crown_radius=None,
        wheel_transverse_radius=math.inf,
        preload=load,
    )
    return circle.hertz_radius()


def _shifted(column: tuple[float, ...], ratio: float) -> np.ndarray:
    """A column read at wavelength lambda * ratio, on the 35 table bands (NaN beyond its short end)."""
    index = np.arange(3, -32, -1, dtype=float)  # band centre = 10^(index / 10) m
    wanted = index + 10.0 * math.log10(ratio)
    values = np.interp(wanted, index[::-1], np.asarray(column)[::-1], left=np.nan, right=0.0)
    return values


def cnossos_filter(load: float, wheel_diameter: float, contact: ContactParameters | None = None) -> np.ndarray:
    """CNOSSOS-EU contact filter A3, dB, on the 35 wavelength bands 2000 .. 0.8 mm (long first).

    The five tabulated (load, diameter) cases return their column exactly; other cases follow the rule of
    the module docstring (columns shifted by the Hertz semi-axis along the rail and interpolated in log a),
    whose error against the table is at most :data:`CNOSSOS_RULE_ERROR_DB`.

    Parameters
    ----------
    load : float
        Static wheel load P, N.
    wheel_diameter : float
        Wheel diameter D, m.
    contact : ContactParameters, optional
        Material for the Hertz semi-axes (E, nu); its radius and preload are replaced by D/2 and P.
        E* cancels in the ratios the rule uses, so only the load and diameter matter.

    Returns
    -------
    numpy.ndarray
        35 levels, dB; NaN in bands the rule does not cover.

    Raises
    ------
    WheelrailError
        For a load or diameter that is not a positive number.

    See Also
    --------
    reference_filters : every reference filter, also by frequency band.

    References
    ----------
    .. [1] Commission Directive (EU) 2015/996, Annex II, 2.3.2 (CNOSSOS-EU), Table G-2 (contact filter A3).
    """
    load = _positive(load, "CNOSSOS filter: wheel load", "N")
    wheel_diameter = _positive(wheel_diameter, "CNOSSOS filter: wheel diameter", "m")
    for (table_load, table_diameter), column in CNOSSOS_A3.items():
        if math.isclose(load, table_load, rel_tol=1e-9) and math.isclose(wheel_diameter, table_diameter, rel_tol=1e-9):
            return np.asarray(column, dtype=float)
    contact = ContactParameters() if contact is None else contact
    return _cnossos_rule(_column_semi_axis(load, wheel_diameter, contact), CNOSSOS_A3, contact)


def _cnossos_rule(semi_axis: float, columns: dict, contact: ContactParameters) -> np.ndarray:
    """Interpolate ``columns`` (a subset of the table) to a contact of semi-axis ``semi_axis`` m."""
    axes = {key: _column_semi_axis(*key, contact) for key in columns}
    below = [key for key in columns if axes[key] <= semi_axis]
    above = [key for key in columns if axes[key] > semi_axis]
    if not below or not above:
        nearest = max(below, key=axes.get) if below else min(above, key=axes.get)
        return _shifted(columns[nearest], axes[nearest] / semi_axis)
    lo, hi = max(below, key=axes.get), min(above, key=axes.get)
    weight = math.log(semi_axis / axes[lo]) / math.log(axes[hi] / axes[lo])
    return (1.0 - weight) * _shifted(columns[lo], axes[lo] / semi_axis) + weight * _shifted(
        columns[hi], axes[hi] / semi_axis
    )


# --------------------------------------------------------------------------------------------------
# Analytic filters
# --------------------------------------------------------------------------------------------------
_K_NODES, _K_WEIGHTS = np.polynomial.legendre.leggauss(96)  # across one band (<= 4 periods of sin^2 at 0.8 mm)


def _sinc2(x: np.ndarray) -> np.ndarray:
    return np.sinc(x / np.pi) ** 2  # numpy's sinc is sin(pi t) / (pi t)


def filter_transfer(kind: str, wavenumber, semi_axis: float) -> np.ndarray:
    """|H(k)|^2 of an analytic filter at angular wavenumbers ``wavenumber`` (rad/m), patch semi-axis a (m).

    ``kind`` is one of :data:`ANALYTIC_FILTERS` (formulas in the module docstring; ``averaging`` and
    ``patch-correlated`` from the literature, ``patch-incoherent`` this project's construction).
    """
    ka = np.asarray(wavenumber, dtype=float) * semi_axis
    if kind == "averaging":
        return _sinc2(ka)
    if kind == "patch-correlated":
        safe = np.where(ka == 0.0, 1.0, ka)
        return np.where(ka == 0.0, 1.0, (2.0 * scipy.special.j1(safe) / safe) ** 2)
    if kind == "patch-incoherent":
        safe = np.where(ka == 0.0, 1.0, ka)
        return np.where(ka == 0.0, 1.0, 3.0 * np.pi / 8.0 * scipy.special.struve(1, 2.0 * safe) / safe**2)
    raise WheelrailError(f"unknown analytic filter {kind!r}; choose one of {', '.join(ANALYTIC_FILTERS)}")


def analytic_filter_levels(kind: str, k_lower, k_upper, semi_axis: float) -> np.ndarray:
    """Band levels of an analytic filter: 10 log10 of the mean of |H(k)|^2 over each band, dB.

    Parameters
    ----------
    kind : str
        One of :data:`ANALYTIC_FILTERS`.
    k_lower, k_upper : array_like
        Band edges as spatial frequencies 1/lambda, cycles/m (``Bands.wavenumber_edges()``).
    semi_axis : float
        Contact semi-axis along the rail, a, m.

    Returns
    -------
    numpy.ndarray
        dB per band (<= 0), the mean over the band's wavenumbers, i.e. the filter white roughness sees.
    """
    semi_axis = _positive(semi_axis, "contact semi-axis", "m")
    lo = 2.0 * np.pi * np.asarray(k_lower, dtype=float)
    hi = 2.0 * np.pi * np.asarray(k_upper, dtype=float)
    nodes = 0.5 * (lo + hi)[:, None] + 0.5 * (hi - lo)[:, None] * _K_NODES
    mean = 0.5 * filter_transfer(kind, nodes, semi_axis) @ _K_WEIGHTS
    return 10.0 * np.log10(mean)


# --------------------------------------------------------------------------------------------------
# Everything for one load, wheel and speed
# --------------------------------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True, eq=False)
class ReferenceFilterSet:
    """All reference filters for one wheel load, wheel radius and speed, as band levels in dB.

    Attributes
    ----------
    load : float
        Static wheel load P, N.
    wheel_radius : float
        Wheel rolling radius R, m (the CNOSSOS diameter is 2R).
    speed : float or None
        Train speed, m/s; None: no frequency bands.
    semi_axes : tuple of float
        Hertz contact semi-axes (a along the rail, b across), m.
    wavelength_bands : Bands
        The 35 CNOSSOS-EU wavelength bands, 2000 .. 0.8 mm.
    by_wavelength : dict of str to numpy.ndarray
        Filter name (:data:`REFERENCE_FILTERS`) -> dB per wavelength band (NaN where undefined).
    frequency_bands : Bands or None
        Frequency bands at ``speed``.
    by_frequency : dict of str to numpy.ndarray
        Filter name -> dB per frequency band: analytic filters averaged over the band's own
        wavenumbers; CNOSSOS mapped from its wavelength bands with :func:`wheelrail.core.spectra.bands.map_levels`.
    """

    load: float
    wheel_radius: float
    speed: float | None
    semi_axes: tuple[float, float]
    wavelength_bands: Bands
    by_wavelength: dict
    frequency_bands: Bands | None = None
    by_frequency: dict = field(default_factory=dict)


def reference_filters(
    load: float,
    wheel_radius: float,
    speed: float | None = None,
    *,
    contact: ContactParameters | None = None,
    frequency_range: tuple[float, float] = FORCE_BAND_RANGE,
) -> ReferenceFilterSet:
    """Every reference filter (CNOSSOS-EU A3 and the analytic ones) for a load, wheel radius and speed.

    The one call for studies and the explorer: e.g. ``reference_filters(65e3, 0.39, 100 / 3.6)`` gives the
    paper's case by wavelength band and by frequency band (50 Hz .. 8 kHz).

    Parameters
    ----------
    load : float
        Static wheel load P, N (``ranges.ACCEPTED``: 1 to 500 kN).
    wheel_radius : float
        Wheel rolling radius R, m (0.1 to 1.25 m).
    speed : float, optional
        Train speed, m/s (5 to 400 km/h); omitted: wavelength bands only.
    contact : ContactParameters, optional
        Material (E, nu) and geometry across the rail for the Hertz semi-axes (paper defaults); its preload
        and rolling radius are replaced by ``load`` and ``wheel_radius``. Its rail crown is the one a run
        with it has (:attr:`ContactParameters.crown_radius`: unset, the paper's R = 0.39 m whatever the
        wheel), so another wheel radius alone gives an ellipse, as in ``run``.
    frequency_range : (float, float)
        Lowest and highest frequency band centre, Hz.

    Returns
    -------
    ReferenceFilterSet
        Each filter's levels by wavelength band and, with a speed, by frequency band, dB.

    Raises
    ------
    WheelrailError
        For a load, radius or speed outside its accepted range.

    See Also
    --------
    cnossos_filter : the CNOSSOS-EU A3 filter alone.
    wheelrail.core.spectra.levels.contact_filter : a model's filter, to compare with these.

    Examples
    --------
    >>> from wheelrail.core.reference_filters import reference_filters
    >>> filters = reference_filters(65e3, 0.39, 100 / 3.6)      # the paper's case: N, m, m/s
    >>> filters.frequency_bands.centres.size                     # the force bands, 50 Hz to 8 kHz
    23
    >>> sorted(filters.by_frequency)
    ['averaging', 'cnossos', 'patch-correlated', 'patch-incoherent']
    """
    load = ACCEPTED["preload"].check(load, "load")
    wheel_radius = ACCEPTED["wheel_radius"].check(wheel_radius, "wheel_radius")
    contact = replace(ContactParameters() if contact is None else contact, wheel_radius=wheel_radius, preload=load)
    a, b = hertz_semi_axes(contact)
    by_wavelength = {"cnossos": cnossos_filter(load, 2.0 * wheel_radius, contact)}
    lambda_bands = wavelength_bands()
    for kind in ANALYTIC_FILTERS:
        by_wavelength[kind] = analytic_filter_levels(kind, *lambda_bands.wavenumber_edges(), a)
    if speed is None:
        return ReferenceFilterSet(
            load=load,
            wheel_radius=wheel_radius,
            speed=None,
            semi_axes=(a, b),
            wavelength_bands=lambda_bands,
            by_wavelength=by_wavelength,
        )
    speed = ACCEPTED["speed"].check(speed, "speed")
    f_bands = frequency_bands(speed, frequency_range)
    by_frequency = {"cnossos": map_levels(by_wavelength["cnossos"], lambda_bands, f_bands)}
    for kind in ANALYTIC_FILTERS:
        by_frequency[kind] = analytic_filter_levels(kind, *f_bands.wavenumber_edges(), a)
    return ReferenceFilterSet(
        load=load,
        wheel_radius=wheel_radius,
        speed=speed,
        semi_axes=(a, b),
        wavelength_bands=lambda_bands,
        by_wavelength=by_wavelength,
        frequency_bands=f_bands,
        by_frequency=by_frequency,
    )


def run_reference_filters(
    contact: ContactParameters, speed: float, frequency_range: tuple[float, float] = FORCE_BAND_RANGE
) -> ReferenceFilterSet:
    """The reference filters beside a run's dynamic ones: for the run's own preload, rolling radius and geometry
    across the rail, exactly as the run has them."""
    return reference_filters(
        contact.preload, contact.radius_along, speed, contact=contact, frequency_range=frequency_range
    )
