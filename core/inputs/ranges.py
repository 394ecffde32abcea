"""Accepted ranges of the physical inputs, in one table: what a railway wheel, rail and train can be.

:data:`ACCEPTED` gives each input its key, SI unit, range and the reason for the range. The parameter classes
(``RunParameters.speed``, ``ContactParameters``' preload and radii), the studies, the reference filters, the
command line (its help and its messages, in its own units) and the explorer (its field hints and messages)
all read it; an input outside its range is one :class:`~wheelrail.core.errors.WheelrailError` that carries
the key, the value and the range, so that each front end names it in its own terms.

Two rules relate inputs to each other:

* **The patch stays small against the radii** (:func:`check_patch`): the Hertz semi-axes at the preload are
  at most ``PATCH_FRACTION`` = 1/10 of each body's radius in their direction (along the rail: the wheel's
  rolling radius; across it: the rail crown's and the tread's). Every model here describes the surfaces by
  the paraboloid x^2/(2 R) of Hertz's theory, a half-space loaded on a patch small against the radii
  (Johnson, *Contact Mechanics*, 4.1). A circle of radius R departs from its paraboloid by y^4/(8 R^3), a
  fraction (y/R)^2/4 of it (0.25 % at y = R/10); the gap between a concave tread and the crown, the
  difference of two such profiles, by at most 3 (y/R)^2 / 4 (0.75 % at R/10). A patch wider than that no
  longer fits the theory: a concave tread of -300.5 mm on a 300 mm crown gives, under a 390 mm wheel at
  65 kN, a patch 0.15 m across (measured with ``ContactParameters.hertz_semi_axes``).
* **A wheel set's circumference is the wheel's** (:func:`check_wheel_circumference`): a wheel roughness set
  added to a rail set (combined roughness) repeats every circumference, so it must be within
  ``CIRCUMFERENCE_TOLERANCE`` = 1 % of 2 pi R of the run's rolling radius R (the bundled wheel sets are
  2.900 m round: R = 461.5 mm). A wheel set run alone, as the one rough surface, stays the paper's
  idealisation (a roughness record, run as given) and is not checked.

Each range contains the values it is meant for with room to spare and leaves out a value given in the wrong
unit (a radius in mm given as m, or in m as mm, is 1000 times off and lands outside).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable
from dataclasses import dataclass, fields

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.inputs.checks import integer, real

__all__ = [
    "ACCEPTED",
    "CIRCUMFERENCE_TOLERANCE",
    "MAX_ELEMENT_MM",
    "MAX_SPEED_KMH",
    "MIN_ELEMENT_MM",
    "MIN_SPEED_KMH",
    "MODEL_BOUNDS",
    "PATCH_FRACTION",
    "WHEEL_SYSTEM",
    "YOUNGS_MODULUS",
    "Accepted",
    "check_model_input",
    "check_parts",
    "check_patch",
    "check_wheel_circumference",
    "raise_concave_tread",
]


PATCH_FRACTION = 0.1  # largest Hertz semi-axis at the preload / the bodies' radius in its direction
CIRCUMFERENCE_TOLERANCE = 0.01  # largest |C - 2 pi R| / (2 pi R) of a wheel set C added to a wheel of radius R
ROUND_OFF = 1e-12  # relative: a bound met after a unit conversion (km/h -> m/s) is met
# Accepted train speeds: the range over which the interaction loop is shown stable (FOH_MAX_STEP in
# parameters.py; smooth-rail speed scans in tests/physics/test_stability.py and validation/speed_scan.py).
# Below MIN_SPEED_KMH steps get so long (7.2 ms at 0.5 km/h: 8 lags) that the 50 ms truncation of the
# trapezoidal weights matters and the loop chattered again at 0.5 km/h. MAX_SPEED_KMH is the reach of the
# cached track responses (``TrackNumerics.max_speed``).
MIN_SPEED_KMH = 5.0
MAX_SPEED_KMH = 400.0
# Accepted element sizes at the front ends (the Python API's RunParameters takes MODEL_BOUNDS' wider range): the
# 2/1/0.5 mm convergence table of docs/validation.md (validation/element_convergence.py) and tests/physics'
# runs of every model at both ends.
MIN_ELEMENT_MM = 0.5
MAX_ELEMENT_MM = 2.0


@dataclass(frozen=True)
class Accepted:
    """One input's accepted range: ``key`` (the stable name front ends map to their own), SI ``unit``,
    ``minimum`` and ``maximum`` (SI), the ``reason`` for them; ``magnitude``: the range bounds |value| (a
    radius whose sign means concave), ``maximum`` then inf."""

    key: str
    unit: str
    minimum: float
    maximum: float
    reason: str
    magnitude: bool = False

    def check(self, value, argument: str | None = None) -> float:
        """``value`` as a float within the range, else one WheelrailError naming ``argument`` (default the key)."""
        blame = Blame(self.key, value, self.unit, argument=argument)
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise WheelrailError("not a number", blame)
        try:
            number = float(value)
        except OverflowError:  # an integer beyond float64: outside any range
            number = math.inf if value > 0 else -math.inf
        if math.isnan(number):
            raise WheelrailError("not a number", blame)
        size = abs(number) if self.magnitude else number
        if not self.minimum * (1 - ROUND_OFF) <= size <= self.maximum * (1 + ROUND_OFF):
            raise WheelrailError(
                None,
                blame._replace(
                    minimum=self.minimum,
                    maximum=None if self.magnitude else self.maximum,
                    reason=self.reason,
                    magnitude=self.magnitude,
                ),
            )
        return number

    def in_unit(self, scale: float) -> tuple[float, float]:
        """(minimum, maximum) in a front end's unit (``scale`` of it per SI unit), rounded for display."""
        return float(f"{self.minimum * scale:.6g}"), float(f"{self.maximum * scale:.6g}")


_WHEEL_RADIUS = (0.1, 1.25, "a railway wheel, around the CNOSSOS-EU table's 360 to 920 mm diameters")

ACCEPTED: dict[str, Accepted] = {
    entry.key: entry
    for entry in (
        Accepted(
            "speed",
            "m/s",
            MIN_SPEED_KMH / 3.6,
            MAX_SPEED_KMH / 3.6,
            "where the interaction loop is shown stable and the cached track responses reach",
        ),
        Accepted(
            "preload", "N", 1e3, 500e3, "a railway wheel's static load, around the CNOSSOS-EU table's 25 to 100 kN"
        ),
        Accepted(
            "element_size",
            "m",
            MIN_ELEMENT_MM * 1e-3,
            MAX_ELEMENT_MM * 1e-3,
            "the contact grid and the step along the rail: at 2 mm the paper's Hertz patch (2a = 11 mm) spans 5 "
            "elements; the convergence of the force spectra with it is docs/validation.md's element table",
        ),
        Accepted("radius", "m", *_WHEEL_RADIUS),
        Accepted("wheel_radius", "m", *_WHEEL_RADIUS),
        Accepted(
            "rail_crown_radius", "m", 0.05, 5.0, "a rail head, from a sharp 50 mm crown to a worn, nearly flat 5 m"
        ),
        Accepted(
            "rail_loss_factor",
            "",
            0.0,
            0.1,
            "0: the paper's undamped rail; a bare steel rail's loss factor is of order 0.01 to 0.02; up to 0.1 the "
            "time-domain track's receptance stays within 1 dB per band of the constant loss factor's",
        ),
        Accepted(
            "pad_width",
            "m",
            0.0,
            0.3,
            "the length of rail a pad supports: 0 is the paper's point support; rail seats are 0.12 to 0.2 m long "
            "(a sleeper's width at the seat is 0.2 to 0.3 m), and the pad must stay within half a sleeper bay",
        ),
        Accepted(
            "wheel_transverse_radius",
            "m",
            0.05,
            math.inf,
            "inf: a cylindrical or conical tread; negative: a concave, worn one",
            magnitude=True,
        ),
        Accepted(
            "pad_stiffness", "N/m", 10e6, 3000e6, "from the softest baseplate fastenings of slab track to stiff pads"
        ),
        Accepted(
            "pad_damping",
            "N s/m",
            5e3,
            500e3,
            "a pad's loss factor of about 0.05 to 0.5 at the rail-on-pad resonance; below 5 kNs/m a soft support rings "
            "beyond the 50 ms of response the loop keeps",
        ),
        Accepted(
            "sleeper_mass", "kg", 20.0, 300.0, "half a sleeper: from a light timber sleeper to a heavy concrete one"
        ),
        Accepted("sleeper_spacing", "m", 0.5, 0.9, "the sleeper spacings of ballasted and slab track"),
        Accepted(
            "ballast_stiffness",
            "N/m",
            10e6,
            3000e6,
            "per half sleeper: from soft subgrade with under-sleeper pads to a slab's rigid support",
        ),
        Accepted(
            "ballast_damping",
            "N s/m",
            20e3,
            1000e3,
            "per half sleeper, around the paper's 165 kNs/m; below 20 kNs/m a heavy sleeper on soft ballast rings "
            "beyond the 50 ms of response the loop keeps (the time stepping is then unstable at low speeds)",
        ),
        # the lateral track (wheelrail.core.lateral_parameters): pads several times softer in shear than in
        # compression, roll stiffness k_P b^2 / 12 of 10-3000 MN/m pads across 0.1-0.2 m feet
        Accepted("pad_lateral_stiffness", "N/m", 2e6, 1000e6, "a pad's lateral (shear) stiffness per support"),
        Accepted(
            "pad_rotational_stiffness", "N m/rad", 5e3, 10e6, "a pad's stiffness against the rail's roll, per support"
        ),
        Accepted("pad_lateral_loss_factor", "", 0.0, 1.0, "the loss factor of a pad's lateral and roll stiffness"),
        Accepted(
            "train_length",
            "m",
            2.0,
            5000.0,
            "from one short wagon to a heavy-haul freight train (about 3.5 km)",
        ),
        Accepted("train_axles", "", 1, 2000, "one axle to a heavy-haul freight train's (about 1 200)"),
        # the contact's lateral position (wheelrail.core.inputs.contact_position): the noise chain's, not the run's
        Accepted(
            "contact_offset_rail",
            "m",
            -0.03,
            0.03,
            "on the railhead's crown: a 60E1 head is 72 mm wide, running bands lie within about 20 mm of its centre",
        ),
        Accepted(
            "contact_offset_wheel",
            "m",
            -0.04,
            0.04,
            "on the tread: a 135 mm rim, running bands lie within about 30 mm of the nominal rolling circle",
        ),
        # the modal wheel's cross-section (wheelrail.core.modal_wheel.profile): solid wheels of 0.2 to 2.5 m with room
        # to spare around the 640 to 1250 mm wheels of wagons, coaches and locomotives
        Accepted("wheel_tyre_width", "m", 0.08, 0.2, "a rim's width: 135 mm on standard-gauge wheels"),
        Accepted("wheel_tyre_depth", "m", 0.015, 0.12, "a rim's depth under the tread, worn to new"),
        Accepted("wheel_web_thickness", "m", 0.01, 0.08, "a solid wheel's web, about 20 to 35 mm thick"),
        Accepted("wheel_web_offset", "m", -0.15, 0.15, "the dish of the web, hub to rim, within a hub's width"),
        Accepted("wheel_web_curvature", "m", -0.08, 0.08, "the bulge of a curved (S- or C-shaped) web at mid-height"),
        Accepted("wheel_hub_inner_radius", "m", 0.03, 0.2, "the axle seat: axles of 60 to 400 mm diameter"),
        Accepted("wheel_hub_outer_radius", "m", 0.05, 0.3, "a hub's outer radius, beyond the axle seat"),
        Accepted("wheel_hub_width", "m", 0.05, 0.3, "a hub's length along the axle"),
        Accepted("wheel_contact_offset", "m", -0.08, 0.08, "the running circle's offset from the web, on the rim"),
        Accepted("wheel_flange_height", "m", 0.0, 0.05, "0: no flange; standard flanges are about 28 to 30 mm high"),
        Accepted("wheel_flange_thickness", "m", 0.0, 0.05, "0: no flange; standard flanges are about 30 mm thick"),
    )
}
"""The accepted ranges by key (SI). Wheel radii 0.1 to 1.25 m (diameters 0.2 to 2.5 m) hold the CNOSSOS-EU
table's 360 to 920 mm wheels and the paper's 780 mm (R = 0.39 m) with room for small wagon and large
locomotive wheels; rail crowns 0.05 to 5 m; treads at least 0.05 m in magnitude (no tread is curved more
sharply than a rail crown); loads 1 to 500 kN around the table's 25 to 100 kN wheel loads. The track's ranges
hold real ballasted and slab tracks with room to spare (Thompson, *Railway Noise and Vibration*, Elsevier 2009,
section 3.6 and table 3.1: pads from about 20 MN/m, the soft baseplate fastenings of slab track, to over 1 GN/m,
stiff studded HDPE pads; half concrete sleepers of 100-160 kg, half timber ones around 40 kg; spacings of
0.6-0.7 m; ballast of 50-200 MN/m per half sleeper). A pass-by's train is 2 m to 5 km long with 1 to 2 000
axles (and at most one axle per ``run_noise.MIN_AXLE_SPACING`` = 1 m). The user-facing inputs
(``wheelrail.core.inputs.declared``) take their ranges from here."""

MODEL_BOUNDS: dict[str, Accepted] = {
    entry.key: entry
    for entry in (
        Accepted(
            "youngs_modulus",
            "Pa",
            0.1e9,
            1200e9,
            "an elastic solid, from a stiff polymer to diamond; steel is 210 GPa: a value in GPa given as Pa falls "
            "outside",
        ),
        # the paper's 2-DOF wheel (WheelParameters): each holds the paper's value (592.5 kg, 3 kg, 1.12 MN/m,
        # 13.2 kNs/m, 2.4 GN/m, 155 kNs/m) with decades to spare; beyond them the wheel's discrete-time system
        # overflows (a contact mass of 1e-308 kg) or has no steady start
        Accepted("unsprung_mass", "kg", 50.0, 5000.0, "half a wheelset, light rail to a locomotive's with its motor"),
        Accepted("contact_mass", "kg", 0.5, 50.0, "a small mass at the contact; lighter, the wheel's step overflows"),
        Accepted("suspension_stiffness", "N/m", 0.1e6, 20e6, "a primary suspension, per wheel"),
        Accepted("suspension_damping", "N s/m", 0.0, 500e3, "a primary suspension's damper, per wheel"),
        Accepted("wheel_stiffness", "N/m", 0.1e9, 50e9, "the wheel's stiffness at the contact above its first modes"),
        Accepted("wheel_damping", "N s/m", 0.0, 5e6, "damping in parallel with the wheel's stiffness"),
        Accepted("bending_stiffness", "N m^2", 1e3, 1e13, "a rail's EI, light rails to a stiff beam"),
        Accepted("shear_stiffness", "N", 1e5, 1e15, "a rail's kGA"),
        Accepted("mass_per_length", "kg/m", 1.0, 1e4, "a rail's mass per metre"),
        Accepted("rotary_inertia_per_length", "kg m", 0.0, 1e3, "a rail's rotary inertia per metre"),
        Accepted("n_bays", "", 4, 1000, "a track model of up to 1000 sleeper bays"),
        Accepted("element_size", "m", 1e-5, 10.0, "the step along the rail (front ends: ACCEPTED's 0.5 to 2 mm)"),
        Accepted("ballast_lateral_stiffness", "N/m", 5e6, 1000e6, "the ballast's lateral stiffness, per half sleeper"),
        Accepted("ballast_lateral_loss_factor", "", 0.0, 2.0, "the loss factor of the ballast's lateral stiffness"),
        Accepted("elements_per_bay", "", 2, 4096, "finite elements per sleeper bay"),
        Accepted("refined_elements_per_bay", "", 2, 4096, "finite elements per refined sleeper bay"),
        Accepted("positions_per_bay", "", 1, 4096, "excitation positions per sleeper bay"),
        Accepted("refined_bays", "", 1, 100, "refined sleeper bays around the load"),
        Accepted("store_every", "", 1, 1000, "time steps per stored response sample"),
        Accepted("rows_per_position", "", 1, 1000, "response rows per excitation position"),
        Accepted("near_field", "m", 1e-3, 10.0, "the track's near field around the load"),
        Accepted("time_step", "s", 1e-8, 1e-3, "the track responses' time step"),
        Accepted("duration", "s", 1e-4, 10.0, "the track responses' duration"),
        Accepted("max_speed", "m/s", 0.1, 1000.0, "the fastest speed the track responses serve"),
    )
}
"""Bounds of the model's inputs that only the Python API sets (SI): generous around the paper's values, they
refuse what no wheel, rail or numerical setting is and what would overflow the model's arithmetic."""


YOUNGS_MODULUS = MODEL_BOUNDS["youngs_modulus"]
"""The accepted Young's modulus of wheel and rail (``ContactParameters.youngs_modulus``), a Python API input
only: the front ends run steel."""

WHEEL_SYSTEM: dict[str, Accepted] = {
    key: MODEL_BOUNDS[key]
    for key in (
        "unsprung_mass",
        "contact_mass",
        "suspension_stiffness",
        "suspension_damping",
        "wheel_stiffness",
        "wheel_damping",
    )
}
"""The accepted ranges of the paper's 2-DOF wheel (``WheelParameters``), Python API inputs only (in
:data:`MODEL_BOUNDS`, with the reason of each)."""


def check_patch(
    semi_axes: tuple[float, float],
    radii: tuple[float, float, float],
    preload: float,
    semi_axis_across: Callable[[float], float],
) -> None:
    """The Hertz patch at the preload is at most ``PATCH_FRACTION`` of the bodies' radii (module docstring).

    Parameters
    ----------
    semi_axes : (float, float)
        Hertz semi-axes at the preload, a along the rail and b across it, m.
    radii : (float, float, float)
        The wheel's rolling radius, the rail crown's radius and the tread's radius across (inf: cylindrical,
        negative: concave), m.
    preload : float
        The static load they were computed at, N.
    semi_axis_across : callable
        b at the preload for another relative radius across (m -> m): finds the tread radius a concave
        tread must exceed.

    Raises
    ------
    WheelrailError
        Blaming the tread (a concave one too close to the crown) with the largest accepted radius, else the
        preload with the largest accepted load (the semi-axes grow as P^(1/3)).
    """
    a, b = semi_axes
    wheel, crown, tread = radii
    across = min(crown, abs(tread))
    fraction = max(a / wheel, b / across)
    if fraction <= PATCH_FRACTION * (1 + 1e-9):  # round-off: the largest load reported is accepted
        return
    wide = f"{2 * a:.3g} m long" if a / wheel >= b / across else f"{2 * b:.3g} m wide across the rail"
    problem = (
        f"the Hertz patch at the preload would be {wide}, {fraction:.0%} of the radius in that direction "
        f"(at most {PATCH_FRACTION:.0%}: the models take the surfaces as paraboloids, as Hertz does)"
    )
    if tread < 0 and b / across > PATCH_FRACTION * (1 + 1e-9):
        raise_concave_tread(problem, tread, crown, semi_axis_across)
    raise WheelrailError(
        problem,
        Blame(
            "preload",
            preload,
            unit="N",
            maximum=preload * (PATCH_FRACTION / fraction) ** 3,
            argument="ContactParameters.preload",
        ),
    )


def raise_concave_tread(problem: str, tread: float, crown: float, semi_axis_across: Callable[[float], float]):
    """One WheelrailError blaming a concave tread too close to the crown, with the largest radius (the most
    negative is least conforming) whose patch across stays within ``PATCH_FRACTION`` of the crown."""
    from scipy.optimize import brentq

    def excess(curvature: float) -> float:  # b - PATCH_FRACTION crown for a tread of curvature -curvature
        return semi_axis_across(1.0 / (1.0 / crown - curvature)) - PATCH_FRACTION * crown

    if excess(0.0) >= 0:  # even a cylindrical tread's patch is too wide (a soft material): no concave one fits
        limit = None
    else:
        limit = -1.0 / brentq(excess, 0.0, (1.0 - 1e-6) / crown, xtol=1e-12, rtol=1e-10)
    raise WheelrailError(
        problem,
        Blame(
            "wheel_transverse_radius",
            tread,
            unit="m",
            maximum=limit,
            argument="ContactParameters.wheel_transverse_radius",
        ),
        advice="a convex or cylindrical tread is accepted too",
    )


def check_wheel_circumference(circumference: float, wheel_radius: float, label: str) -> None:
    """A wheel set added to a rail set must be within ``CIRCUMFERENCE_TOLERANCE`` of 2 pi R of the wheel it is
    the roughness of; else one WheelrailError blaming the wheel radius, with the radii accepted for this set."""
    implied = circumference / (2.0 * math.pi)
    mismatch = abs(2.0 * math.pi * wheel_radius - circumference) / (2.0 * math.pi * wheel_radius)
    if mismatch <= CIRCUMFERENCE_TOLERANCE * (1 + ROUND_OFF):
        return
    own = 2.0 * math.pi * wheel_radius
    raise WheelrailError(
        f"the wheel set {label} is {circumference:.4g} m round (a wheel of radius {implied:.4g} m), and this wheel "
        f"{own:.4g} m, {mismatch:.0%} {'shorter' if own < circumference else 'longer'}",
        Blame(
            "wheel_radius",
            wheel_radius,
            unit="m",
            minimum=circumference / (2.0 * math.pi * (1 + CIRCUMFERENCE_TOLERANCE)),
            maximum=circumference / (2.0 * math.pi * (1 - CIRCUMFERENCE_TOLERANCE)),
            argument="ContactParameters.wheel_radius",
            reason=f"a wheel set repeats with the wheel's circumference; at most {CIRCUMFERENCE_TOLERANCE:.0%} apart",
        ),
    )


def check_model_input(argument: str, value, unit: str, *, allow_zero: bool = False, minimum: int | None = None) -> None:
    """One input of the model's parameter classes: a finite number of its sign (an integer >= ``minimum`` when
    given) within its :data:`MODEL_BOUNDS` if it has some (the key: ``argument``'s last part), else one
    WheelrailError naming ``argument`` ("ContactParameters.youngs_modulus")."""
    if minimum is not None:
        integer(argument, value, minimum)
    else:
        real(argument, value, unit, sign="nonnegative" if allow_zero else "positive")
    bounds = MODEL_BOUNDS.get(argument.rsplit(".", 1)[-1])
    if bounds is not None:
        bounds.check(value, argument)


def check_parts(owner: object) -> None:
    """Each field of a parameter dataclass annotated with a parameter class (``...Parameters``; a string:
    postponed annotations) holds an instance of it, else one WheelrailError."""
    for part in fields(owner):
        value = getattr(owner, part.name)
        if str(part.type).endswith("Parameters") and type(value).__name__ != part.type:
            kind = type(value).__name__
            raise WheelrailError(f"{type(owner).__name__}.{part.name} must be a {part.type}, got {kind}")
