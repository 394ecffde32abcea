"""CNOSSOS-EU railway rolling-noise source (Directive 2002/49/EC Annex II, section 2.3, as replaced by
Commission Directive (EU) 2015/996 with the corrigendum of OJ L 5, 10.1.2018, and as amended by Commission
Delegated Directive (EU) 2021/1226).

The source model, per one-third octave band i (50 Hz .. 10 kHz):

- roughness by wavelength band: rail ``L_r,TR`` (Table G-1b, 35 bands 2000 .. 0.8 mm), wheel ``L_r,VEH``
  (Table G-1a, its own 32-band grid 1000 .. 0.8 mm), contact filter ``A_3`` (Table G-2, in
  :mod:`wheelrail.core.reference_filters`, for the wheel load and diameter by the rule ``wheelrail filters``
  uses), each read at the wavelength ``lambda = v / f_c,i`` (v in m/s, as corrected in 2018) by one of two
  conversion rules (:data:`INTERPOLATION_RULES`), each table from its own printed grid;
- total effective roughness ``L_R,TOT,i = 10 lg(10^(L_r,TR,i/10) + 10^(L_r,VEH,i/10)) + A_3,i`` (eq. 2.3.7);
- sound power per vehicle ``L_W,0,tr,i = L_R,TOT,i + L_H,tr,i + 10 lg N_a`` (track, Table G-3a),
  ``L_W,0,veh,i = L_R,TOT,i + L_H,veh,i + 10 lg N_a`` (vehicle, Table G-3b, by wheel diameter),
  ``L_W,0,sup,i = L_R,TOT,i + L_H,veh,sup,i + 10 lg N_a`` (superstructure, Table G-3c) (eqs. 2.3.8-2.3.10),
  dB re 1 pW, N_a axles per vehicle; their A-weighted totals.

The two conversion rules, from wavelength bands to the frequency band centres (the directive says the two
corresponding wavelength bands are "averaged energetically and proportionally", without a formula):

- ``proportional`` (default): the rule of the Commission's reference source module as the public
  implementation phonometry documents it: the level is interpolated linearly between the two neighbouring
  printed wavelengths, proportionally to wavelength, at lambda = v / f with the nominal centre f;
- ``energy-log-frequency``: the rule of NoiseModelling: the mean square 10^(L/10) is interpolated linearly
  in lg f between the frequencies v / lambda_j of the printed wavelengths.

Beyond the ends of a table both rules hold its end value. They differ by up to about 1 dB per band on a
steep spectrum (:func:`interpolation_difference` and the README show by how much).

Everything inside is SI: speed in m/s, loads in N, diameters in m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.inputs.checks import check_positive
from wheelrail.core.inputs.ranges import ACCEPTED
from wheelrail.core.noise.tables import NOMINAL_FREQUENCIES_HZ, load_table
from wheelrail.core.spectra.levels import a_weighted_total, energy_sum

INTERPOLATION_RULES = ("proportional", "energy-log-frequency")
RAIL_ROUGHNESS = ("iso3095", "network-average")
WHEEL_ROUGHNESS = ("cast-iron", "composite", "disc", "none")
TRACK_TYPES = (
    "mono-block-soft",
    "mono-block-medium",
    "mono-block-hard",
    "bi-block-soft",
    "bi-block-medium",
    "bi-block-hard",
    "wooden",
    "direct-fastening",
)
WHEEL_DIAMETERS_MM = (680, 840, 920, 1200)

# The 35 wavelengths (mm) on which Table G-2 (A3) is printed, long first: the grid of Table G-1b.
_A3_PRINTED_MM = (
    2000,
    1600,
    1250,
    1000,
    800,
    630,
    500,
    400,
    315,
    250,
    200,
    160,
    125,
    100,
    80,
    63,
    50,
    40,
    31.5,
    25,
    20,
    16,
    12.5,
    10,
    8,
    6.3,
    5,
    4,
    3.15,
    2.5,
    2,
    1.6,
    1.25,
    1,
    0.8,
)


def _choice(value: str, allowed: tuple, what: str) -> str:
    if value not in allowed:
        raise WheelrailError(f"{what} must be one of {', '.join(map(str, allowed))}, got {value!r}")
    return value


def roughness_to_frequency(
    levels_db, wavelengths_m, speed: float, rule: str = "proportional", frequencies=NOMINAL_FREQUENCIES_HZ
) -> np.ndarray:
    """Levels printed on wavelength bands, read at the frequency bands of a speed (``lambda = v / f``).

    Parameters
    ----------
    levels_db : array_like
        One level per printed wavelength, dB (roughness in dB re 1 um, or a filter in dB). NaN marks a band
        without a value; a frequency band that needs it is NaN.
    wavelengths_m : array_like
        The printed wavelengths, m, in either order.
    speed : float
        Train speed v, m/s.
    rule : str
        One of :data:`INTERPOLATION_RULES` (module docstring).
    frequencies : array_like
        Band centre frequencies, Hz (default the 24 nominal centres 50 .. 10 000 Hz, as the directive prints).

    Returns
    -------
    numpy.ndarray
        One level per frequency, dB.
    """
    _choice(rule, INTERPOLATION_RULES, "roughness interpolation")
    speed = check_positive(speed, "speed", "m/s")
    levels = np.asarray(levels_db, dtype=float)
    lam = np.asarray(wavelengths_m, dtype=float)
    if levels.shape != lam.shape or levels.ndim != 1 or levels.size < 2:
        raise WheelrailError(f"roughness_to_frequency: {levels.size} levels for {lam.size} wavelengths")
    order = np.argsort(lam)
    lam, levels = lam[order], levels[order]
    f = np.asarray(frequencies, dtype=float)
    if rule == "proportional":
        return np.interp(speed / f, lam, levels)
    # energy-log-frequency: interpolate the mean square linearly in lg f (band frequencies v / lambda, rising)
    log_f = np.log10(speed / lam[::-1])
    energy = 10.0 ** (levels[::-1] / 10.0)
    with np.errstate(divide="ignore"):
        return 10.0 * np.log10(np.interp(np.log10(f), log_f, energy))


def rail_roughness(name: str, speed: float, rule: str = "proportional") -> np.ndarray:
    """Rail roughness ``L_r,TR`` (Table G-1b) on the 24 bands at ``speed`` (m/s), dB re 1 um."""
    table = load_table("rail_roughness")
    return roughness_to_frequency(
        table.column(_choice(name, RAIL_ROUGHNESS, "rail roughness")), table.grid, speed, rule
    )


def wheel_roughness(name: str, speed: float, rule: str = "proportional") -> np.ndarray:
    """Wheel roughness ``L_r,VEH`` (Table G-1a) on the 24 bands, dB re 1 um; ``none``: -inf (rail alone)."""
    if _choice(name, WHEEL_ROUGHNESS, "wheel roughness") == "none":
        return np.full(len(NOMINAL_FREQUENCIES_HZ), -np.inf)
    table = load_table("wheel_roughness")
    return roughness_to_frequency(table.column(name), table.grid, speed, rule)


def contact_filter_a3(load: float, wheel_diameter: float, speed: float, rule: str = "proportional") -> np.ndarray:
    """Contact filter ``A_3`` (Table G-2) on the 24 bands at ``speed`` (m/s), dB.

    The column for the wheel load (N) and diameter (m) is :func:`wheelrail.core.reference_filters.cnossos_filter`
    (the table's five columns exactly, other cases by its Hertz semi-axis rule), on the printed wavelengths.
    """
    from wheelrail.core.reference_filters import cnossos_filter

    column = cnossos_filter(load, wheel_diameter)
    return roughness_to_frequency(column, np.asarray(_A3_PRINTED_MM) * 1e-3, speed, rule)


def track_transfer(track_type: str) -> np.ndarray:
    """Track transfer function ``L_H,tr`` (Table G-3a), dB re 1 pW per axle for 0 dB re 1 um, 24 bands."""
    return load_table("track_transfer").column(_choice(track_type, TRACK_TYPES, "track type")).copy()


def vehicle_transfer(wheel_diameter_mm) -> np.ndarray:
    """Vehicle transfer function ``L_H,veh`` (Table G-3b) for a wheel diameter in mm (680, 840, 920, 1200)."""
    try:
        key = int(round(float(wheel_diameter_mm)))
    except (TypeError, ValueError, OverflowError):
        key = None
    if key not in WHEEL_DIAMETERS_MM or not math.isclose(float(wheel_diameter_mm), key, abs_tol=1e-6):
        shown = float(wheel_diameter_mm) / 1e3 if key is not None else wheel_diameter_mm  # SI, as errors carry
        raise WheelrailError(
            f"not one of the wheel diameters {', '.join(map(str, WHEEL_DIAMETERS_MM))} mm (the "
            "columns of CNOSSOS-EU Table G-3b)",
            Blame("wheel_diameter", shown, unit="m"),
        )
    return load_table("vehicle_transfer").column(str(key)).copy()


def superstructure_transfer() -> np.ndarray:
    """Superstructure transfer function ``L_H,veh,sup`` (Table G-3c, "EU standard"), 24 bands."""
    return load_table("superstructure_transfer").column("eu-standard").copy()


@dataclass(frozen=True, kw_only=True, eq=False)
class CnossosResult:
    """The CNOSSOS-EU rolling-noise source of one vehicle, per band (24 bands 50 Hz .. 10 kHz).

    Attributes
    ----------
    frequency_hz : numpy.ndarray
        Nominal band centres, Hz.
    rail_roughness_db, wheel_roughness_db, contact_filter_db, total_roughness_db : numpy.ndarray
        ``L_r,TR``, ``L_r,VEH`` (dB re 1 um; -inf for ``none``), ``A_3`` (or the filter given in its place,
        dB) and ``L_R,TOT`` (dB re 1 um).
    track_db, vehicle_db, superstructure_db, total_db : numpy.ndarray
        Sound power per vehicle, dB re 1 pW: track, vehicle (wheels), superstructure and their sum.
    track_dba, vehicle_dba, superstructure_dba, total_dba : float
        A-weighted totals, dB(A) re 1 pW.
    configuration : dict
        What produced it (speed, tables, load, diameter, axles, rule; SI with units in the keys).
    """

    frequency_hz: np.ndarray
    rail_roughness_db: np.ndarray
    wheel_roughness_db: np.ndarray
    contact_filter_db: np.ndarray
    total_roughness_db: np.ndarray
    track_db: np.ndarray
    vehicle_db: np.ndarray
    superstructure_db: np.ndarray
    total_db: np.ndarray
    track_dba: float
    vehicle_dba: float
    superstructure_dba: float
    total_dba: float
    configuration: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """The JSON layout of ``wheelrail noise --method cnossos --json`` (key ``cnossos``)."""
        return {
            "total_roughness_dB": self.total_roughness_db,
            "track_dB": self.track_db,
            "vehicle_dB": self.vehicle_db,
            "superstructure_dB": self.superstructure_db,
            "total_dB": self.total_db,
            "rail_roughness_dB": self.rail_roughness_db,
            "wheel_roughness_dB": self.wheel_roughness_db,
            "contact_filter_dB": self.contact_filter_db,
            "track_dBA": self.track_dba,
            "vehicle_dBA": self.vehicle_dba,
            "superstructure_dBA": self.superstructure_dba,
            "total_dBA": self.total_dba,
            "configuration": self.configuration,
        }


def _bands(values, what: str) -> np.ndarray:
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise WheelrailError(f"{what}: not numbers (dB on the 24 bands 50 Hz - 10 kHz)") from None
    if array.shape != (len(NOMINAL_FREQUENCIES_HZ),):
        raise WheelrailError(f"{what}: {array.size} values, the 24 bands 50 Hz - 10 kHz need 24")
    if np.any(array == np.inf):
        raise WheelrailError(f"{what}: a level of +inf dB")
    return array


def _roughness_and_filter(speed, rail, wheel, load, wheel_diameter, rule, contact_filter, roughness):
    """(rail dB, wheel dB, filter dB, rail name, wheel name, filter name) on the 24 bands."""
    if roughness is None:
        rail_db, wheel_db = rail_roughness(rail, speed, rule), wheel_roughness(wheel, speed, rule)
    else:
        rail, values = roughness
        rail_db, wheel_db, wheel = _bands(values, "roughness"), np.full(len(NOMINAL_FREQUENCIES_HZ), -np.inf), "none"
        if np.all(np.isnan(rail_db)):  # NaN marks a band without a value: none at all is no roughness
            raise WheelrailError("roughness: no band has a level (all NaN); a zero roughness is -inf dB")
    if contact_filter is None:
        return rail_db, wheel_db, contact_filter_a3(load, wheel_diameter, speed, rule), rail, wheel, "A3"
    name, values = contact_filter
    return rail_db, wheel_db, _bands(values, "contact filter"), rail, wheel, name


def cnossos_rolling_noise(
    speed: float,
    *,
    rail: str = "iso3095",
    wheel: str = "cast-iron",
    track_type: str = "mono-block-medium",
    wheel_diameter: float = 0.92,
    load: float = 50e3,
    axles: int = 4,
    rule: str = "proportional",
    contact_filter: tuple | None = None,
    roughness: tuple | None = None,
) -> CnossosResult:
    """The CNOSSOS-EU rolling-noise source (module docstring) for one vehicle.

    Parameters
    ----------
    speed : float
        Train speed v, m/s.
    rail, wheel : str
        Rail roughness (:data:`RAIL_ROUGHNESS`) and wheel roughness (:data:`WHEEL_ROUGHNESS`; ``none``: the
        rail's roughness alone, e.g. where the combined roughness was measured).
    track_type : str
        One of :data:`TRACK_TYPES` (Table G-3a).
    wheel_diameter : float
        Wheel diameter, m: one of 0.68, 0.84, 0.92, 1.2 (Table G-3b); it also selects A3.
    load : float
        Static wheel load, N (for A3).
    axles : int
        Axles per vehicle, N_a.
    rule : str
        Conversion rule from wavelength to frequency bands (:data:`INTERPOLATION_RULES`).
    contact_filter : (str, array_like), optional
        ``(name, dB on the 24 frequency bands)``: a contact filter used instead of A3 (e.g. a model's dynamic
        filter); NaN bands give NaN sound power there.
    roughness : (str, array_like), optional
        ``(name, dB re 1 um on the 24 frequency bands)``: a combined (rail + wheel) roughness used instead of
        Tables G-1a and G-1b (the directive allows measured roughness), e.g. a roughness set's spectrum.
    """
    # the accepted train speeds (5 to 400 km/h) hold the directive's 50 to 320 km/h and more; a speed far outside
    # shifts every printed wavelength out of the bands (1e300 m/s once gave 148.9 dB(A) from the edge values)
    speed = ACCEPTED["speed"].check(speed, "cnossos_rolling_noise: speed")
    load = check_positive(load, "preload", "N", argument="load")
    wheel_diameter = check_positive(wheel_diameter, "wheel_diameter", "m")
    if isinstance(axles, bool) or not isinstance(axles, int | np.integer) or axles < 1:
        raise WheelrailError("not a whole number of at least 1", Blame("axles", axles))
    _choice(rule, INTERPOLATION_RULES, "roughness interpolation")
    l_veh, l_tr, l_sup = vehicle_transfer(wheel_diameter * 1e3), track_transfer(track_type), superstructure_transfer()
    rail_db, wheel_db, a3, rail, wheel, filter_name = _roughness_and_filter(
        speed, rail, wheel, load, wheel_diameter, rule, contact_filter, roughness
    )
    total_roughness = energy_sum(rail_db, wheel_db) + a3  # eq. 2.3.7
    axle_term = 10.0 * math.log10(axles)
    track_db = total_roughness + l_tr + axle_term  # eq. 2.3.8
    vehicle_db = total_roughness + l_veh + axle_term  # eq. 2.3.9
    sup_db = total_roughness + l_sup + axle_term  # eq. 2.3.10
    total_db = energy_sum(track_db, vehicle_db, sup_db)
    undefined = [f for f, value in zip(NOMINAL_FREQUENCIES_HZ, total_db, strict=True) if not np.isfinite(value)]
    configuration = {
        "method": "cnossos",
        "speed_m_s": speed,
        "rail_roughness": rail,
        "wheel_roughness": wheel,
        "track_type": track_type,
        "wheel_diameter_m": wheel_diameter,
        "wheel_load_n": load,
        "axles": axles,
        "roughness_interpolation": rule,
        "contact_filter": filter_name,
        "source": "Directive 2002/49/EC Annex II 2.3 as replaced by (EU) 2015/996 (corrigendum OJ L 5, 10.1.2018) "
        "and amended by (EU) 2021/1226; Appendix G Tables G-1a, G-1b, G-2, G-3a, G-3b, G-3c",
        # bands the contact filter does not cover (A3 shifted beyond 0.8 mm, or a dynamic filter's unresolved
        # bands): null in the spectra, left out of the dB(A) totals
        "undefined_bands_hz": undefined,
    }
    return _result((rail_db, wheel_db, a3, total_roughness), (track_db, vehicle_db, sup_db), configuration)


def _result(roughness_terms, components, configuration) -> CnossosResult:
    """The result from (rail, wheel, A3, total roughness) and (track, vehicle, superstructure) levels, dB."""
    rail_db, wheel_db, a3, total_roughness = roughness_terms
    track_db, vehicle_db, sup_db = components
    total_db = energy_sum(track_db, vehicle_db, sup_db)

    def dba(levels):
        return a_weighted_total(np.where(np.isfinite(levels), levels, -np.inf))

    return CnossosResult(
        frequency_hz=np.asarray(NOMINAL_FREQUENCIES_HZ),
        rail_roughness_db=rail_db,
        wheel_roughness_db=wheel_db,
        contact_filter_db=a3,
        total_roughness_db=total_roughness,
        track_db=track_db,
        vehicle_db=vehicle_db,
        superstructure_db=sup_db,
        total_db=total_db,
        track_dba=dba(track_db),
        vehicle_dba=dba(vehicle_db),
        superstructure_dba=dba(sup_db),
        total_dba=dba(total_db),
        configuration=configuration,
    )


def interpolation_difference(speed: float, **options) -> tuple[np.ndarray, float]:
    """``energy-log-frequency`` minus ``proportional``: per band (total sound power, dB) and in dB(A)."""
    a = cnossos_rolling_noise(speed, rule="proportional", **options)
    b = cnossos_rolling_noise(speed, rule="energy-log-frequency", **options)
    return b.total_db - a.total_db, b.total_dba - a.total_dba
