"""Model parameters: frozen dataclasses in SI units holding the paper's defaults (sections 2.1-2.3 and 3).

Every class validates itself on construction (``__post_init__``): a non-finite or non-positive value, or one outside
its accepted range (``ranges.ACCEPTED`` for what the front ends set, ``ranges.MODEL_BOUNDS`` for the rest) is one
:class:`WheelrailError` that carries the parameter, its value, unit and range.
"""

from __future__ import annotations

import math
import typing
from dataclasses import asdict, dataclass, field, fields, is_dataclass

from wheelrail.core.contact.hertz import HertzContact, elliptic_hertz
from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.inputs import ranges
from wheelrail.core.inputs.ranges import ACCEPTED, MAX_SPEED_KMH, MIN_SPEED_KMH
from wheelrail.core.inputs.run_records import check_run_irregularities, tagged_run, untagged_run
from wheelrail.core.lateral_parameters import LateralParameters

KMH = 1.0 / 3.6  # m/s per km/h; convert only at the edges (CLI, GUI, files)
__all__ = [  # MIN_SPEED_KMH and MAX_SPEED_KMH are wheelrail.core.inputs.ranges', re-exported
    "FOH_MAX_STEP",
    "KMH",
    "MAX_SPEED_KMH",
    "MIN_SPEED_KMH",
    "ContactParameters",
    "ModelParameters",
    "RailParameters",
    "RunParameters",
    "SupportParameters",
    "TrackNumerics",
    "TrackParameters",
    "WheelParameters",
    "as_dict",
    "field_names",
    "from_dict",
    "hertz_constant",
    "reduced_modulus",
]

# Longest loop time step (s) at which wheel (eq. 1) and rail (eq. 2) are discretised with a first-order hold; a
# longer step uses the trapezoidal rule, stable wherever the physical system is (docs: physics, Accepted speeds)
FOH_MAX_STEP = 0.25e-3

# Wheel and rail material, steel: the paper gives neither E nor nu; these common values reproduce its stated
# a = 5.48 mm at 65 kN with R = 0.39 m. ContactParameters and every function's default read them from here.
STEEL_YOUNGS_MODULUS = 210e9  # Pa
STEEL_POISSON_RATIO = 0.3


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
    ranges.check_model_input(f"{type(owner).__name__}.{name}", getattr(owner, name), unit, allow_zero=allow_zero)


def _check_int(owner: object, name: str, minimum: int) -> None:
    ranges.check_model_input(f"{type(owner).__name__}.{name}", getattr(owner, name), "", minimum=minimum)


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

    Each within its range in ``ranges.WHEEL_SYSTEM`` (else one WheelrailError naming it).
    """

    unsprung_mass: float = 592.5
    contact_mass: float = 3.0
    suspension_stiffness: float = 1.12e6
    suspension_damping: float = 13.2e3
    wheel_stiffness: float = 2.4e9
    wheel_damping: float = 155e3

    def __post_init__(self) -> None:
        for item in fields(self):  # each within a railway wheelset's range (ranges.WHEEL_SYSTEM)
            ranges.WHEEL_SYSTEM[item.name].check(getattr(self, item.name), f"WheelParameters.{item.name}")


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
    loss_factor : float
        eta, the rail's loss factor on its bending and shear stiffness, EI (1 + i eta) and kGA (1 + i eta)
        (0: the paper's undamped rail; ``ranges.ACCEPTED["rail_loss_factor"]``: 0 to 0.1). Exact in the
        frequency domain; in the time domain a fit of a few relaxation terms (``track.fe.rail_relaxation``).
    """

    bending_stiffness: float = 6.4e6
    shear_stiffness: float = 250e6
    mass_per_length: float = 60.0
    rotary_inertia_per_length: float = 60.0 * 3055e-8 / 76.70e-4
    loss_factor: float = 0.0

    def __post_init__(self) -> None:
        _check(self, "bending_stiffness", "N m^2")
        _check(self, "shear_stiffness", "N")
        _check(self, "mass_per_length", "kg/m")
        _check(self, "rotary_inertia_per_length", "kg m", allow_zero=True)
        ACCEPTED["rail_loss_factor"].check(self.loss_factor, "RailParameters.loss_factor")


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
    pad_width : float
        w, the length of rail the pad supports, m: k_P and c_P spread evenly over x_S - w/2 .. x_S + w/2 (a
        Winkler layer k_P / w per metre under the rail, the sleeper rigid); 0: the paper's point support.
        ``ranges.ACCEPTED["pad_width"]``: 0 to 0.3 m, and at most half the sleeper spacing.

    Raises
    ------
    WheelrailError
        Keyed by the input (``"pad_stiffness"``) if a value is outside its accepted range
        (``wheelrail.core.inputs.declared.INPUTS``: pads 10 to 3000 MN/m, ...).
    """

    sleeper_spacing: float = 0.65
    pad_stiffness: float = 120e6
    pad_damping: float = 16e3
    sleeper_mass: float = 125.0
    ballast_stiffness: float = 140e6
    ballast_damping: float = 165e3
    pad_width: float = 0.0

    def __post_init__(self) -> None:
        for item in fields(self):  # each a declared input (wheelrail.core.inputs.declared), checked against its range
            ACCEPTED[item.name].check(getattr(self, item.name), f"SupportParameters.{item.name}")
        if self.pad_width > (half := 0.5 * self.sleeper_spacing):
            raise WheelrailError(
                f"a pad {self.pad_width} m wide overlaps the next sleeper's {self.sleeper_spacing} m away "
                "(at most half the sleeper spacing)",
                Blame("pad_width", self.pad_width, "m", maximum=half, argument="SupportParameters.pad_width"),
            )


@dataclass(frozen=True, kw_only=True)
class TrackParameters:
    """The discretely supported track: rail on ``n_bays`` identical supports (paper section 2.2).

    Attributes
    ----------
    rail : RailParameters
    support : SupportParameters
    n_bays : int
        Number of sleeper bays of the finite track model (70 in the paper; 4 to 1000: ``ranges.MODEL_BOUNDS``).
    lateral : LateralParameters
        The rail's section and its supports' lateral stiffness (``wheelrail.core.lateral_parameters``).
    """

    rail: RailParameters = field(default_factory=RailParameters)
    support: SupportParameters = field(default_factory=SupportParameters)
    n_bays: int = 70
    lateral: LateralParameters = field(default_factory=LateralParameters)

    def __post_init__(self) -> None:
        ranges.check_parts(self)
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
        Rayleigh-Timoshenko beam elements per sleeper bay away from the excitation (16: 40.6 mm, >= 7
        elements per bending wavelength up to 8 kHz); also the grid on which the response is stored
        beyond ``near_field``.
    positions_per_bay : int
        Excitation positions x0 per bay at which Green's functions are computed (nodes of the refined
        mesh). In between, each row handed to the loop is read from its two neighbouring positions at the
        same rail point (``track.bay_rows``). 32 (every 20.3 mm) is converged to 0.2 dB per third-octave
        band against 64 (``validation/bay_convergence.py``).
    refined_elements_per_bay : int
        Elements per bay in the central bay (where the excitation positions are), the ``refined_bays - 1`` after
        it and the one before it (``fe.REFINED_LEAD_IN_BAYS``); a multiple of the two counts per bay.
        A receiver moving through the elements near the load sees their size: the force carries a tone
        at the element-passing frequency v / h (1.37 kHz at 100 km/h for 32 elements per bay, +2.6 dB in
        that band); 64 elements put it at 2.7 kHz at 100 km/h and 5.5 kHz at 200 km/h.
    refined_bays : int
        Bays meshed with ``refined_elements_per_bay`` from the central bay on (the receiver's path during the
        first ~23 ms at 100 km/h per bay), besides the bay before the central one.
    near_field : float
        The response is stored at every node of the refined mesh up to this distance after the
        excitation point, m; beyond it at the nodes of the coarse grid, read with the shape functions of a
        coarse element (keeps the stored responses to ~100 MB).
    time_step : float
        Step of the implicit (Newmark average-acceleration) integration of the impulse responses, s.
    duration : float
        Length of the Green's functions in time (the truncation), s.
    max_speed : float
        Highest train speed the cached stationary responses cover, m/s (the stored response is the
        wedge of points a wheel at up to this speed can reach).
    store_every : int
        Store every n-th integration step (2: responses kept at 10 us, i.e. 50 kHz sampling).
    rows_per_position : int
        Rows of the moving Green's functions handed to the loop per stored excitation position
        (``track.bay_rows``: each read between its two neighbouring positions at the same rail point); the
        loop interpolates linearly between rows. Not part of the stored responses (nor their cache key).

    Raises
    ------
    WheelrailError
        If a count or length is not positive, a count does not divide ``refined_elements_per_bay`` or the
        duration is under 20 time steps.
    """

    elements_per_bay: int = 16
    positions_per_bay: int = 64
    refined_elements_per_bay: int = 64
    refined_bays: int = 2
    near_field: float = 0.1
    time_step: float = 5e-6
    duration: float = 0.05
    max_speed: float = MAX_SPEED_KMH * KMH
    store_every: int = 2
    rows_per_position: int = 4

    def __post_init__(self) -> None:
        _check_int(self, "elements_per_bay", 2)
        _check_int(self, "rows_per_position", 1)
        _check_int(self, "store_every", 1)
        _check_int(self, "positions_per_bay", 1)
        _check_int(self, "refined_elements_per_bay", 2)
        _check_int(self, "refined_bays", 1)
        for name in ("positions_per_bay", "elements_per_bay"):
            if self.refined_elements_per_bay % getattr(self, name):
                raise WheelrailError(
                    f"TrackNumerics.{name} ({getattr(self, name)}) must divide refined_elements_per_bay "
                    f"({self.refined_elements_per_bay}) so that every excitation position and stored grid point "
                    "is an FE node"
                )
        _check(self, "near_field", "m")
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

    The undeformed gap between wheel and rail near the contact point is x^2 / (2 R_x) + y^2 / (2 R_y)
    (x along the rail, y across it), with the relative radii R_x = ``wheel_radius`` (the rail is straight)
    and 1 / R_y = 1 / ``rail_crown_radius`` + 1 / ``wheel_transverse_radius``. The paper's case is the
    default: both radii R = ``radius`` and a cylindrical tread (a sphere of radius R on a flat, a circular
    patch).

    Attributes
    ----------
    youngs_modulus : float
        E of wheel and rail (same material), Pa. 210 GPa (steel): the paper gives neither E nor nu; these
        common values for steel reproduce its stated a = 5.48 mm at 65 kN with R = 0.39 m. Accepted: 0.1 to
        1200 GPa (``ranges.YOUNGS_MODULUS``).
    poisson_ratio : float
        nu, dimensionless, 0 <= nu < 0.5; 0.3 (steel; see ``youngs_modulus``).
    radius : float
        R, the paper's single radius, m: the default of ``wheel_radius`` and ``rail_crown_radius`` (files
        written before those existed carry only this one).
    preload : float
        P, static wheel load, N.
    wheel_radius : float or None
        Wheel rolling radius (curvature along the rail), m; None: ``radius``.
    rail_crown_radius : float or None
        Transverse radius of the rail head (curvature across, convex), m; None: ``radius``.
    wheel_transverse_radius : float
        Transverse radius of the wheel tread, m: infinite (a cylindrical/conical tread, the default; None
        reads as infinite), negative for a concave (worn, hollow) tread. The relative curvature across,
        1 / rail_crown_radius + 1 / wheel_transverse_radius, must stay positive.

    Raises
    ------
    WheelrailError
        Naming the input, unless the preload and the radii lie in their accepted ranges
        (``wheelrail.core.inputs.ranges.ACCEPTED``: 1 to 500 kN; wheel 0.1 to 1.25 m, crown 0.05 to 5 m, tread at least
        0.05 m in magnitude) and the Hertz patch at the preload within a tenth of the radii (``ranges.check_patch``).

    Examples
    --------
    The paper's crossed cylinders of R = 0.39 m under 65 kN, then a 0.46 m wheel on a 0.30 m rail crown:

    >>> from wheelrail.core.parameters import ContactParameters
    >>> hertz = ContactParameters().hertz()
    >>> round(hertz.semi_axis_along * 1e3, 2), round(hertz.peak_pressure / 1e6)   # a in mm, p0 in MPa
    (5.48, 1033)
    >>> real = ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30)
    >>> [round(axis * 1e3, 2) for axis in real.hertz_semi_axes()]   # mm, along and across the rail
    [6.2, 4.67]
    >>> ContactParameters(preload=5e6)       # SI: N
    Traceback (most recent call last):
    ...
    wheelrail.core.errors.WheelrailError: ContactParameters.preload 5e+06 N is outside the accepted 1000 to 500000 N ...
    """

    youngs_modulus: float = STEEL_YOUNGS_MODULUS
    poisson_ratio: float = STEEL_POISSON_RATIO
    radius: float = 0.39
    preload: float = 65e3
    wheel_radius: float | None = None
    rail_crown_radius: float | None = None
    wheel_transverse_radius: float | None = math.inf

    def __post_init__(self) -> None:
        ranges.YOUNGS_MODULUS.check(self.youngs_modulus, "ContactParameters.youngs_modulus")
        nu = self.poisson_ratio
        if not (isinstance(nu, int | float) and not isinstance(nu, bool) and 0.0 <= nu < 0.5):
            raise WheelrailError(f"ContactParameters.poisson_ratio must be in [0, 0.5), got {nu!r}")
        for name in ("radius", "preload"):  # only the radii default to another field when None
            if getattr(self, name) is None:
                raise WheelrailError("not a number", Blame(name, None, argument=f"ContactParameters.{name}"))
        if self.wheel_transverse_radius is None:  # JSON has no infinity: a written file says null
            object.__setattr__(self, "wheel_transverse_radius", math.inf)
        for name in ("radius", "preload", "wheel_radius", "rail_crown_radius", "wheel_transverse_radius"):
            if getattr(self, name) is not None:  # the accepted ranges of a railway wheel and rail
                ACCEPTED[name].check(getattr(self, name), f"ContactParameters.{name}")
        if isinstance(tread := self.wheel_transverse_radius, int):  # an integer, maybe beyond float64: inf
            object.__setattr__(self, "wheel_transverse_radius", ACCEPTED["wheel_transverse_radius"].check(tread))
        self._check_geometry()

    def _check_geometry(self) -> None:
        """The tread must not conform with the crown, and the patch must stay small (``ranges.check_patch``)."""
        crown = self.crown_radius
        tread = self.wheel_transverse_radius

        def semi_axis_across(radius_across: float) -> float:
            return elliptic_hertz(self.preload, self.radius_along, radius_across, self.reduced_modulus)[1]

        if math.isfinite(tread) and 1.0 / crown + 1.0 / tread <= 0.0:
            ranges.raise_concave_tread(
                f"a concave tread of radius {-tread:.4g} m fits the rail crown of radius {crown:.4g} "
                "m or closer: the surfaces conform across the rail",
                tread,
                crown,
                semi_axis_across,
            )
        ranges.check_patch(self.hertz_semi_axes(), (self.radius_along, crown, tread), self.preload, semi_axis_across)

    @property
    def radius_along(self) -> float:
        """R_x, relative radius of curvature along the rail: the wheel's rolling radius, m."""
        return self.radius if self.wheel_radius is None else float(self.wheel_radius)

    @property
    def crown_radius(self) -> float:
        """R_crown, the rail head's radius across the rail in use: ``rail_crown_radius``, or ``radius`` unset, m."""
        return self.radius if self.rail_crown_radius is None else float(self.rail_crown_radius)

    @property
    def radius_across(self) -> float:
        """R_y, relative radius of curvature across the rail, 1 / (1/R_crown + 1/R_tread), m."""
        crown = self.crown_radius
        if math.isinf(self.wheel_transverse_radius):
            return crown
        return 1.0 / (1.0 / crown + 1.0 / self.wheel_transverse_radius)

    @property
    def circular(self) -> bool:
        """The patch is a circle (R_x = R_y, the paper's case)."""
        return self.radius_along == self.radius_across

    @property
    def reduced_modulus(self) -> float:
        """E* = E / (2 (1 - nu^2)) for two bodies of the same material, Pa."""
        return reduced_modulus(self.youngs_modulus, self.poisson_ratio)

    def hertz(self, load: float | None = None) -> HertzContact:
        """Hertz's (elliptic) contact of these radii under a load.

        Parameters
        ----------
        load : float, optional
            Normal load, N; default the preload.

        Returns
        -------
        HertzContact
            Semi-axes, peak pressure, approach and constant of :func:`~wheelrail.core.contact.hertz.elliptic_hertz`.
        """
        load = self.preload if load is None else load
        return elliptic_hertz(load, self.radius_along, self.radius_across, self.reduced_modulus)

    @property
    def hertz_constant(self) -> float:
        """C of F = C delta^1.5, N/m^1.5: (2/3) E / (1 - nu^2) sqrt(R) of eq. (13) for the paper's circle."""
        if self.circular:
            return hertz_constant(self.youngs_modulus, self.poisson_ratio, self.radius_along)
        return self.hertz().constant

    def patch_radii(self) -> tuple[float, float]:
        """The radii that give the Hertz semi-axes at any approach: a = sqrt(rho_x delta), b = sqrt(rho_y delta).

        Returns
        -------
        tuple of float
            (rho_x, rho_y), m: (R, R) for the paper's circle, a^2 / delta and b^2 / delta of the elliptic solution
            otherwise.
        """
        if self.circular:
            return self.radius_along, self.radius_along
        contact = self.hertz()
        return contact.radius_along, contact.radius_across

    def hertz_semi_axes(self, load: float | None = None) -> tuple[float, float]:
        """Hertz semi-axes, a along the rail and b across it.

        Parameters
        ----------
        load : float, optional
            Normal load, N; default the preload.

        Returns
        -------
        tuple of float
            (a, b), m (5.48 mm each at the defaults, the paper's value).
        """
        contact = self.hertz(load)
        return contact.semi_axis_along, contact.semi_axis_across

    def hertz_radius(self, load: float | None = None) -> float:
        """Hertz contact radius a = (3 P R / (4 E*))^(1/3); for an elliptic patch that of the same area, sqrt(a b).

        Parameters
        ----------
        load : float, optional
            Normal load, N; default the preload.

        Returns
        -------
        float
            Radius, m (5.48 mm at the defaults).
        """
        load = self.preload if load is None else load
        if self.circular:
            return (3.0 * load * self.radius_along / (4.0 * self.reduced_modulus)) ** (1.0 / 3.0)
        a, b = self.hertz_semi_axes(load)
        return math.sqrt(a * b)

    def hertz_approach(self, load: float | None = None) -> float:
        """Hertz approach delta = (P / C)^(2/3).

        Parameters
        ----------
        load : float, optional
            Normal load, N; default the preload.

        Returns
        -------
        float
            Approach, m (77.07 µm at the defaults).
        """
        load = self.preload if load is None else load
        return (load / self.hertz_constant) ** (2.0 / 3.0)

    def hertz_peak_pressure(self, load: float | None = None) -> float:
        """Hertz peak pressure p0 = 3 P / (2 pi a b).

        Parameters
        ----------
        load : float, optional
            Normal load, N; default the preload.

        Returns
        -------
        float
            Peak pressure, Pa (1032.6 MPa at the defaults).
        """
        load = self.preload if load is None else load
        if self.circular:
            return 3.0 * load / (2.0 * math.pi * self.hertz_radius(load) ** 2)
        return self.hertz(load).peak_pressure


@dataclass(frozen=True, kw_only=True)
class RunParameters:
    """Stepping of a run: train speed and element size (dt = element_size / speed).

    Attributes
    ----------
    speed : float
        v, train speed, m/s (100 km/h in the paper); ``ranges.ACCEPTED["speed"]``: 5 to 400 km/h.
    element_size : float
        Delta x, contact element length and step length along the rail, m (1 mm).
    irregularities : tuple
        Discrete irregularities on the run (``wheelrail.core.irregularities``), by position; default none.
    irregularity_input : str
        What the Hertz models are driven by: "trajectory" (default) or "raw" (the choice ``irregularity_input``).
    """

    speed: float = 100.0 * KMH
    element_size: float = 1e-3
    irregularities: tuple = ()
    irregularity_input: str = "trajectory"

    def __post_init__(self) -> None:
        ACCEPTED["speed"].check(self.speed, "RunParameters.speed")
        _check(self, "element_size", "m")
        check_run_irregularities(self)

    @property
    def time_step(self) -> float:
        """dt = element_size / speed, s."""
        return self.element_size / self.speed


@dataclass(frozen=True, kw_only=True)
class ModelParameters:
    """Everything that defines a wheel/rail interaction model, paper defaults throughout.

    Attributes
    ----------
    wheel : WheelParameters
    track : TrackParameters
    contact : ContactParameters
    run : RunParameters
    """

    wheel: WheelParameters = field(default_factory=WheelParameters)
    track: TrackParameters = field(default_factory=TrackParameters)
    contact: ContactParameters = field(default_factory=ContactParameters)
    run: RunParameters = field(default_factory=RunParameters)

    def __post_init__(self) -> None:
        ranges.check_parts(self)


def as_dict(params: object) -> dict:
    """Nested plain-dict view of a parameter dataclass (for JSON, cache keys and recordings)."""
    if not is_dataclass(params) or isinstance(params, type):
        raise WheelrailError(f"as_dict: expected a parameter dataclass instance, got {type(params).__name__}")
    return tagged_run(params, asdict(params))


def field_names(cls: type) -> list[str]:
    """Names of a parameter dataclass's fields, in declaration order."""
    if not is_dataclass(cls):
        raise WheelrailError(f"field_names: expected a parameter dataclass, got {cls!r:.60}")
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
    return cls(**untagged_run(cls, kwargs))
