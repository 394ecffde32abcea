"""The rail's lateral and torsional parameters: its cross-section (:class:`RailSection`, 60E1 bundled) and the
lateral and rotational stiffness of its supports (:class:`LateralParameters`), frozen dataclasses in SI units.

``TrackParameters.lateral`` holds them; the vertical track (paper section 2.2) does not read them. The model that
does, frequency domain only: :mod:`wheelrail.core.track.lateral`.

The section of 60E1 (EN 13674-1:2011, the profile the paper's UIC60 became; the same 172 mm x 150 mm shape):
area A = 76.70 cm^2, second moments I_y = 3038.3 cm^4 (vertical bending) and I_z = 512.3 cm^4 (lateral bending),
section moduli 333.6 cm^3 (head) and 375.5 cm^3 (foot), so the centroid is I_y / W_foot = 80.9 mm above the foot;
height 172 mm, foot 150 mm, head 72 mm wide. The torsion constant J = 209.2 cm^4: the rail database of Rolland
(Mantel & Nehls, TU Berlin; ``rolland/database/rail/db_rail.py``, UIC60 ``Itr``). The shear centre and the warping
constant from the thin-walled formulas of a monosymmetric I-section (Timoshenko & Gere, *Theory of Elastic
Stability*, 2nd ed., 1961, section 5.5; Trahair, *Flexural-Torsional Buckling of Structures*, 1993, appendix):
head and foot as flanges of lateral second moments I_1, I_2 at a distance h apart, the shear centre at
h I_1 / (I_1 + I_2) from the foot's centroid and I_w = h^2 I_1 I_2 / (I_1 + I_2). With the head a 72 mm x 51 mm
block (its centroid 146.5 mm above the foot; I_1 = 158.6 cm^4), the web 16.5 mm thick (3.4 cm^4) and the foot the
rest of I_z (I_2 = 350.3 cm^4, its centroid 11.5 mm above the foot's underside): h = 135 mm, the shear centre
53.6 mm above the foot's underside and I_w = 1.99e-8 m^6. These are estimates (the head's radii and the foot's
taper are not modelled): +-20 % on I_w moves the lateral decay rates by up to +-12 % (the paper's undamped rail;
+-8 % with a rail loss factor of 0.02), +-10 % on J by up to 6 %, the shear centre 20 % lower by up to 27 % (400 Hz)
(docs/noise.md, "The lateral track").
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields

from wheelrail.core.inputs import ranges
from wheelrail.core.inputs.ranges import ACCEPTED

__all__ = ["RAIL_60E1", "LateralParameters", "RailSection"]


@dataclass(frozen=True, kw_only=True)
class RailSection:
    """A rail's cross-section for lateral bending and torsion (module docstring: 60E1's values and sources).

    Heights are measured up from the underside of the rail foot.

    Attributes
    ----------
    name : str
        The profile's name ("60E1").
    area : float
        A, m^2.
    lateral_second_moment : float
        I_z, second moment of area about the vertical axis (lateral bending), m^4.
    vertical_second_moment : float
        I_y, second moment of area about the horizontal axis, m^4 (with I_z: the polar moment about the
        centroid, I_y + I_z).
    torsion_constant : float
        J, St Venant's torsion constant, m^4.
    warping_constant : float
        I_w, m^6 (about the shear centre).
    shear_centre_height : float
        z_s, the shear centre's height, m: the axis the rail twists about.
    centroid_height : float
        z_c, the centroid's height, m (the rail's mass acts there: lateral and torsional inertia couple when it is
        not the shear centre).
    head_height : float
        z_h, the height of the railhead's running surface, m: where the wheel's lateral force acts.
    foot_width : float
        The foot's width, m.
    youngs_modulus, shear_modulus : float
        E and G of the rail steel, Pa.
    lateral_shear_coefficient : float
        kappa of lateral shear (the shear area kappa A): assumed 0.4, the vertical rail's of the paper
        (kGA = 250 MN is 0.40 G A); shear moves the lateral receptance by under 1 dB below 5 kHz.
    """

    name: str = "60E1"
    area: float = 76.70e-4
    lateral_second_moment: float = 512.3e-8
    vertical_second_moment: float = 3038.3e-8
    torsion_constant: float = 209.2e-8
    warping_constant: float = 1.99e-8
    shear_centre_height: float = 0.0536
    centroid_height: float = 0.0809
    head_height: float = 0.172
    foot_width: float = 0.150
    youngs_modulus: float = 210e9
    shear_modulus: float = 81e9
    lateral_shear_coefficient: float = 0.4

    def __post_init__(self) -> None:
        for item in fields(self):
            if item.name != "name":
                ranges.check_model_input(f"RailSection.{item.name}", getattr(self, item.name), "SI")
        if not self.shear_centre_height < self.head_height or not self.centroid_height < self.head_height:
            from wheelrail.core.errors import WheelrailError

            raise WheelrailError(
                f"RailSection: the shear centre ({self.shear_centre_height} m) and the centroid "
                f"({self.centroid_height} m) must lie below the railhead's surface ({self.head_height} m)"
            )

    @property
    def polar_second_moment(self) -> float:
        """I_p = I_y + I_z about the centroid, m^4."""
        return self.vertical_second_moment + self.lateral_second_moment


RAIL_60E1 = RailSection()
"""The bundled rail, 60E1 (module docstring)."""


@dataclass(frozen=True, kw_only=True)
class LateralParameters:
    """The rail's section and its supports' lateral and rotational stiffness (the lateral track's inputs).

    Each support (at the sleeper spacing and over the pad width of ``SupportParameters``) holds the rail's foot
    laterally through the pad and the half sleeper's mass (``SupportParameters.sleeper_mass``: a sleeper moves
    laterally as one body, half of it per rail) on the ballast's lateral stiffness, and resists the rail's
    twist through the pad's rotational stiffness to the sleeper, taken as rigid in roll (a sleeper is stiff
    about the rail's axis). Damping is a loss factor on each stiffness (hysteretic: k (1 + i eta)).

    Attributes
    ----------
    section : RailSection
        The rail's cross-section (60E1).
    pad_lateral_stiffness : float
        k_Py, the pad's lateral (shear) stiffness per support, N/m: assumed a quarter of the paper's vertical
        120 MN/m (a pad is several times softer in shear than in compression).
    pad_rotational_stiffness : float
        k_Pphi, the pad's stiffness against the rail's roll per support, N m/rad: the vertical pad's 120 MN/m
        spread evenly across the 150 mm foot, k_P b^2 / 12.
    pad_lateral_loss_factor : float
        eta_P of the pad's lateral and rotational stiffness (0.25, a rubber pad's).
    ballast_lateral_stiffness : float
        k_By, the ballast's lateral stiffness under a half sleeper, N/m (assumed 50 MN/m).
    ballast_lateral_loss_factor : float
        eta_B of the ballast's lateral stiffness (1.0: ballast is about critically damped, as the paper's 165 kNs/m
        on 140 MN/m is at 135 Hz).

    Raises
    ------
    WheelrailError
        Keyed by the input (``"pad_lateral_stiffness"``) if a pad's value is outside its accepted range
        (``wheelrail.core.inputs.ranges.ACCEPTED``), naming the field if a ballast's is outside its
        ``ranges.MODEL_BOUNDS``.
    """

    section: RailSection = field(default_factory=RailSection)
    pad_lateral_stiffness: float = 30e6
    pad_rotational_stiffness: float = 120e6 * 0.150**2 / 12
    pad_lateral_loss_factor: float = 0.25
    ballast_lateral_stiffness: float = 50e6
    ballast_lateral_loss_factor: float = 1.0

    def __post_init__(self) -> None:
        if not isinstance(self.section, RailSection):
            from wheelrail.core.errors import WheelrailError

            raise WheelrailError(f"LateralParameters.section must be a RailSection, got {type(self.section).__name__}")
        for item in fields(
            self
        ):  # the pad's: declared inputs (wheelrail.core.inputs.declared); the ballast's: API only
            if item.name.startswith("pad_"):
                ACCEPTED[item.name].check(getattr(self, item.name), f"LateralParameters.{item.name}")
            elif item.name != "section":
                name = f"LateralParameters.{item.name}"
                ranges.check_model_input(name, getattr(self, item.name), "", allow_zero=item.name.endswith("factor"))
