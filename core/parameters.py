"""Model parameters: frozen dataclasses in SI units holding the paper's defaults.

Every class validates itself on construction (``__post_init__``) and rejects a non-positive or
non-finite mass, stiffness, damping, speed, preload or element size with a :class:`WheelrailError`
that names the parameter and its unit. Defaults are those of Pieringer, Kropp & Thompson (2011),
sections 2.1-2.3 and 3, and SPEC.md §2.
"""

from __future__ import annotations

import math
import typing
from dataclasses import asdict, dataclass, field, fields, is_dataclass

from wheelrail.core.checks import integer, real
from wheelrail.core.errors import WheelrailError

KMH = 1.0 / 3.6  # m/s per km/h; convert only at the edges (CLI, GUI, files)


def reduced_modulus(youngs_modulus: float, poisson_ratio: float) -> float:
    """E* = E / (2 (1 - nu^2)) of two bodies of the same material, Pa.

    The one place this formula lives: the Hertz law, the Winkler bedding (whose stiffness per unit
    length, eq. 5, equals E*) and the half-space influence coefficients all use it.
    """
    return youngs_modulus / (2.0 * (1.0 - poisson_ratio**2))


def hertz_constant(youngs_modulus: float, poisson_ratio: float, radius: float) -> float:
    """C_H = (2/3) E / (1 - nu^2) sqrt(R) = (4/3) E* sqrt(R) of eq. (13), N/m^1.5 (9.608e10 at the defaults)."""
    return 4.0 / 3.0 * reduced_modulus(youngs_modulus, poisson_ratio) * math.sqrt(radius)


def _check(owner: object, name: str, unit: str, *, allow_zero: bool = False) -> None:
    real(f"{type(owner).__name__}.{name}", getattr(owner, name), unit, sign="nonnegative" if allow_zero else "positive")


def _check_int(owner: object, name: str, minimum: int) -> None:
    integer(f"{type(owner).__name__}.{name}", getattr(owner, name), minimum)


@dataclass(frozen=True, kw_only=True)
class WheelParameters:
    """Two-degree-of-freedom wheel of the paper's Figure 1 (freight wheel SJ57).

    Attributes
    ----------
    unsprung_mass : float
        M_W, (half) the wheelset mass above the contact spring, kg.
    contact_mass : float
        m_W, small mass at the contact point, included for numerical convenience, kg.
    suspension_stiffness : float
        k_S, primary suspension stiffness, N/m.
    suspension_damping : float
        c_S, primary suspension damping, N s/m.
    wheel_stiffness : float
        k_W, stiffness representing the wheel's high-frequency modes, N/m.
    wheel_damping : float
        c_W, damping in parallel with k_W, N s/m.
    """

    unsprung_mass: float = 592.5
    contact_mass: float = 3.0
    suspension_stiffness: float = 1.12e6
    suspension_damping: float = 13.2e3
    wheel_stiffness: float = 2.4e9
    wheel_damping: float = 155e3

    def __post_init__(self) -> None:
        _check(self, "unsprung_mass", "kg")
        _check(self, "contact_mass", "kg")
        _check(self, "suspension_stiffness", "N/m")
        _check(self, "suspension_damping", "N s/m", allow_zero=True)
        _check(self, "wheel_stiffness", "N/m")
        _check(self, "wheel_damping", "N s/m", allow_zero=True)


@dataclass(frozen=True, kw_only=True)
class RailParameters:
    """Undamped Rayleigh-Timoshenko beam of a UIC60 rail (paper section 2.2).

    Attributes
    ----------
    bending_stiffness : float
        EI, N m^2.
    shear_stiffness : float
        kGA (shear coefficient times shear modulus times area), N.
    mass_per_length : float
        m', kg/m.
    rotary_inertia_per_length : float
        rho I, rotary inertia per unit length, kg m. UIC60: m' I / A with I = 3055 cm^4 and
        A = 76.70 cm^2 gives 0.239 kg m.
    """

    bending_stiffness: float = 6.4e6
    shear_stiffness: float = 250e6
    mass_per_length: float = 60.0
    rotary_inertia_per_length: float = 60.0 * 3055e-8 / 76.70e-4

    def __post_init__(self) -> None:
        _check(self, "bending_stiffness", "N m^2")
        _check(self, "shear_stiffness", "N")
        _check(self, "mass_per_length", "kg/m")
        _check(self, "rotary_inertia_per_length", "kg m", allow_zero=True)


@dataclass(frozen=True, kw_only=True)
class SupportParameters:
    """One discrete support: rail pad, (half) sleeper, ballast (paper Figure 3).

    Attributes
    ----------
    sleeper_spacing : float
        L_S, distance between supports, m.
    pad_stiffness, pad_damping : float
        k_P in N/m and c_P in N s/m.
    sleeper_mass : float
        m_SL, (half) sleeper mass, kg.
    ballast_stiffness, ballast_damping : float
        k_B in N/m and c_B in N s/m.
    """

    sleeper_spacing: float = 0.65
    pad_stiffness: float = 120e6
    pad_damping: float = 16e3
    sleeper_mass: float = 125.0
    ballast_stiffness: float = 140e6
    ballast_damping: float = 165e3

    def __post_init__(self) -> None:
        _check(self, "sleeper_spacing", "m")
        _check(self, "pad_stiffness", "N/m")
        _check(self, "pad_damping", "N s/m", allow_zero=True)
        _check(self, "sleeper_mass", "kg")
        _check(self, "ballast_stiffness", "N/m")
        _check(self, "ballast_damping", "N s/m", allow_zero=True)


@dataclass(frozen=True, kw_only=True)
class TrackParameters:
    """The discretely supported track: rail on ``n_bays`` identical supports (paper section 2.2).

    Attributes
    ----------
    rail : RailParameters
    support : SupportParameters
    n_bays : int
        Number of sleeper bays of the finite track model (70 in the paper).
    """

    rail: RailParameters = field(default_factory=RailParameters)
    support: SupportParameters = field(default_factory=SupportParameters)
    n_bays: int = 70

    def __post_init__(self) -> None:
        _check_int(self, "n_bays", 4)

    @property
    def length(self) -> float:
        """Length of the track model, m."""
        return self.n_bays * self.support.sleeper_spacing


@dataclass(frozen=True, kw_only=True)
class TrackNumerics:
    """How the track's Green's functions are computed and truncated (see ``wheelrail.core.track``).

    Attributes
    ----------
    elements_per_bay : int
        Rayleigh-Timoshenko beam elements per sleeper bay (16: 40.6 mm, >= 7 elements per bending
        wavelength up to 8 kHz).
    positions_per_bay : int
        Excitation positions x0 per bay at which Green's functions are computed, on FE nodes (it must
        divide ``elements_per_bay``); positions in between are interpolated linearly (16: every 40.6 mm).
        A load between nodes is not used: its early response converges slowly with the mesh (at 16
        elements per bay the first-step compliance of a mid-element load is 42 % below the converged
        value, a node's 1.5 %), which would modulate the contact at the element-passing frequency.
    time_step : float
        Step of the implicit (Newmark average-acceleration) integration of the impulse responses, s.
    duration : float
        Length of the Green's functions in time (the truncation), s.
    max_speed : float
        Highest train speed the cached stationary responses cover, m/s (the stored response is the
        wedge of points a wheel at up to this speed can reach).
    store_every : int
        Store every n-th integration step (2: responses kept at 10 us, i.e. 50 kHz sampling).
    """

    elements_per_bay: int = 16
    positions_per_bay: int = 16
    time_step: float = 5e-6
    duration: float = 0.05
    max_speed: float = 300.0 * KMH
    store_every: int = 2

    def __post_init__(self) -> None:
        _check_int(self, "elements_per_bay", 2)
        _check_int(self, "store_every", 1)
        if self.elements_per_bay % self.positions_per_bay:
            raise WheelrailError(
                f"TrackNumerics.positions_per_bay ({self.positions_per_bay}) must divide elements_per_bay "
                f"({self.elements_per_bay}) so that every excitation position is an FE node"
            )
        _check_int(self, "positions_per_bay", 1)
        _check(self, "time_step", "s")
        _check(self, "duration", "s")
        _check(self, "max_speed", "m/s")
        if self.duration < 20 * self.time_step:
            raise WheelrailError(
                f"TrackNumerics.duration must be at least 20 time steps ({20 * self.time_step} s), "
                f"got {self.duration} s"
            )


@dataclass(frozen=True, kw_only=True)
class ContactParameters:
    """Contact material and geometry (paper sections 2.3 and 3).

    Attributes
    ----------
    youngs_modulus : float
        E of wheel and rail (same material), Pa.
    poisson_ratio : float
        nu, dimensionless, 0 <= nu < 0.5.
    radius : float
        R, wheel rolling radius = transverse radius of the railhead, m. Crossed cylinders of equal
        radius R have the gap (x^2 + y^2) / (2R): a sphere of radius R on a flat.
    preload : float
        P, static wheel load, N.
    """

    youngs_modulus: float = 210e9
    poisson_ratio: float = 0.3
    radius: float = 0.39
    preload: float = 65e3

    def __post_init__(self) -> None:
        _check(self, "youngs_modulus", "Pa")
        _check(self, "radius", "m")
        _check(self, "preload", "N")
        nu = self.poisson_ratio
        if not (isinstance(nu, int | float) and math.isfinite(nu) and 0.0 <= nu < 0.5):
            raise WheelrailError(f"ContactParameters.poisson_ratio must be in [0, 0.5), got {nu!r}")

    @property
    def reduced_modulus(self) -> float:
        """E* = E / (2 (1 - nu^2)) for two bodies of the same material, Pa."""
        return reduced_modulus(self.youngs_modulus, self.poisson_ratio)

    @property
    def hertz_constant(self) -> float:
        """C_H = (2/3) E / (1 - nu^2) sqrt(R) of eq. (13), N/m^1.5."""
        return hertz_constant(self.youngs_modulus, self.poisson_ratio, self.radius)

    def hertz_radius(self, load: float | None = None) -> float:
        """Hertz contact radius a = (3 P R / (4 E*))^(1/3), m (5.48 mm at the defaults)."""
        load = self.preload if load is None else load
        return (3.0 * load * self.radius / (4.0 * self.reduced_modulus)) ** (1.0 / 3.0)

    def hertz_approach(self, load: float | None = None) -> float:
        """Hertz approach delta = (P / C_H)^(2/3), m (77.07 um at the defaults)."""
        load = self.preload if load is None else load
        return (load / self.hertz_constant) ** (2.0 / 3.0)

    def hertz_peak_pressure(self, load: float | None = None) -> float:
        """Hertz peak pressure p0 = 3 P / (2 pi a^2), Pa (1032.6 MPa at the defaults)."""
        load = self.preload if load is None else load
        return 3.0 * load / (2.0 * math.pi * self.hertz_radius(load) ** 2)


@dataclass(frozen=True, kw_only=True)
class RunParameters:
    """Stepping of a run: train speed and element size (dt = element_size / speed, SPEC.md §2).

    Attributes
    ----------
    speed : float
        v, train speed, m/s (100 km/h in the paper).
    element_size : float
        Delta x, contact element length and step length along the rail, m (1 mm).
    """

    speed: float = 100.0 * KMH
    element_size: float = 1e-3

    def __post_init__(self) -> None:
        _check(self, "speed", "m/s")
        _check(self, "element_size", "m")

    @property
    def time_step(self) -> float:
        """dt = element_size / speed, s."""
        return self.element_size / self.speed


@dataclass(frozen=True, kw_only=True)
class ModelParameters:
    """Everything that defines a wheel/rail interaction model, paper defaults throughout."""

    wheel: WheelParameters = field(default_factory=WheelParameters)
    track: TrackParameters = field(default_factory=TrackParameters)
    contact: ContactParameters = field(default_factory=ContactParameters)
    run: RunParameters = field(default_factory=RunParameters)


def as_dict(params: object) -> dict:
    """Nested plain-dict view of a parameter dataclass (for JSON, cache keys and recordings)."""
    return asdict(params)


def field_names(cls: type) -> list[str]:
    """Names of a parameter dataclass's fields, in declaration order."""
    return [f.name for f in fields(cls)]


def from_dict(cls: type, values: dict):
    """Rebuild a parameter dataclass (nested ones too) from :func:`as_dict`'s plain dict, validated.

    Unknown keys and values of the wrong kind are one-line :class:`WheelrailError`s; missing keys take
    their defaults (files written before a parameter existed).
    """
    if not isinstance(values, dict):
        raise WheelrailError(f"{cls.__name__}: expected a mapping of parameters, got {type(values).__name__}")
    hints = typing.get_type_hints(cls)
    known = {f.name for f in fields(cls)}
    unknown = sorted(set(values) - known)
    if unknown:
        raise WheelrailError(f"{cls.__name__}: unknown parameter(s) {', '.join(unknown)}")
    kwargs = {}
    for name, value in values.items():
        kind = hints.get(name)
        kwargs[name] = from_dict(kind, value) if is_dataclass(kind) else value
    return cls(**kwargs)
