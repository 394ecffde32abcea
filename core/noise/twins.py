"""Rolling noise from this project's own models, the TWINS way (Thompson, Hemsworth & Vincent, J. Sound Vib.
193 (1996) 123-135; Thompson, *Railway Noise and Vibration*, 2009, ch. 5-7): vertical excitation only.

Chain, per frequency f (time convention e^{i w t}, amplitudes; band values are means over
``points_per_band`` frequencies spread evenly in lg f across each band and over the excitation positions):

1. **Force per unit roughness** at the contact: |F / r| = 1 / |alpha_W + alpha_R(x0) + alpha_C|, with the 2-DOF
   wheel's receptance (:func:`wheelrail.core.wheel.wheel_receptance`), the FE track's point receptance at the
   contact position x0 (above a sleeper and at midspan) and the linearised Hertz contact,
   alpha_C = 1 / k_H, k_H = 3 P / (2 delta_0) at the preload P (eqs. 12-13 of the paper).
2. **Rail and sleeper vibration** for a unit force at x0: the FE track of :func:`wheelrail.core.track.assemble_track`
   (the paper's track, or any other) lengthened to ``track_bays`` bays so that waves reflected at its free ends
   come back attenuated by the track's own decay (the paper's 70 bays suffice for the contact force, not for
   the vibration far along the rail); rail displacement at every node, each sleeper's displacement. The rail's
   loss factor eta is exact here (hysteretic: K_rail (1 + i eta)); pads of a width act as the time-domain track's.
3. **Decay rates**: EN 15461's formula DR = 10 lg(e) / sum_n (|A(x_n)|^2 / |A(x_0)|^2) dx_n on the model's
   band-averaged transfer receptances (excitation at midspan, responses on one side), evaluated on the model's
   node grid (every element) up to ``decay_length`` instead of the standard's measurement positions; and the
   decay of the free wave: the slope of the band level at the sleeper positions 3 to 20 bays from the load
   (a least-squares line in dB against distance).
4. **Sound power per unit force^2**, W/N^2: rail rho c P <n_y^2> (1 / 2 pi) int_{|k_x| < k} |V(k_x)|^2 (k / k_r)
   sigma_rail(c k_r / 2 pi) dk_x, the rail's field v(x) radiated in the wavenumber domain with the rail's 2D BEM
   radiation efficiency at the reduced wavenumber k_r = sqrt(k^2 - k_x^2)
   (:func:`wheelrail.core.noise.radiation.decaying_rail_radiation`; P the section's perimeter, <n_y^2> the
   mean square of its normals' vertical component: the normal velocity of a vertical motion v is v n_y). For a
   field that decays slowly it is sigma_rail(f) int |v|^2 dx; at 50-100 Hz, where the field decays within a
   wavelength, it is 1.5-4 dB less (``rail_decay_correction_dB``);
   sleepers rho c sigma_sleeper S sum_j |v_j|^2, baffled pistons of the half sleeper's area S per rail.
5. **Track transfer function** (the quantity CNOSSOS-EU tabulates as L_H,tr): rail + sleeper sound power per
   axle (two wheels, two rails) for 0 dB re 1 um effective roughness in the band:
   L_H,tr = 10 lg(2 <(W_rail + W_sleeper) |F / r|^2> (1 um)^2 / 1 pW).
6. **Wheel** (``wheel_model``, :mod:`wheelrail.core.noise.wheel_power`): ``directive`` (the default): this
   project's wheel is the paper's 2-DOF model (a mass on a spring): it has no radiating modes, so its sound power
   is the directive's vehicle transfer function L_H,veh (CNOSSOS-EU Table G-3b) for the tabulated diameter
   nearest the model's wheel (2 R), per axle for the effective roughness. ``modal``: the axisymmetric FE wheel of
   the same radius radiates from its own modes, W / F^2 per band, and its radial point receptance (plus the
   unsprung mass's) replaces the 2-DOF's in alpha_W of step 1 (so the rail's and sleepers' transfer functions
   are those of the modal wheel's contact force too); its L_H,veh-equivalent is 10 lg(2 <W / F^2 |F / r|^2>
   (1 um)^2 / 1 pW). The modal wheel is then driven by the force as the rail is (its component entry,
   :func:`wheelrail.core.noise.components.chain_components`): a run's force level times its W / F^2, weighted by
   the coupled force's shape within the band (:mod:`wheelrail.core.noise.wheel_power`, step 5), is its sound
   power. The model used is stated wherever it is (``wheel_transfer_source``).
7. **The contact's lateral position** (``contact_position``,
   :class:`wheelrail.core.inputs.contact_position.ContactPosition`; default centred, the chain of steps 1-6): the
   vertical force off the rail's centreline twists the rail, whose lateral vibration radiates (the
   ``rail_lateral`` component, :mod:`wheelrail.core.noise.rail_lateral`: the lateral track's cross receptance, its
   lateral decay rate and the section's lateral radiation efficiency; a part of L_H,tr); off the wheel's nominal
   rolling circle the radial force drives the modal wheel's axial modes through their radial displacement there
   (:mod:`wheelrail.core.noise.wheel_power`, step 6).

The only excitation is the vertical contact force: the lateral (creep) force of the contact, which drives the rail
and the wheel laterally in TWINS, is not modelled, nor the wheel's rotation (its modes split into forward and
backward waves), the rail's cross-section deformation, the ground's reflection (the rail radiates in free field)
or the sleepers' bending (they are rigid).

The rail (vertical and lateral), the sleepers and the wheel are the entries of
:mod:`wheelrail.core.noise.components` (steps 4, 6 and 7 are their ``radiation``, ``response`` and ``transfer``);
the chain computes every registered component: one driven by the force as the rail and sleepers of steps 4-5, one
driven by the roughness as the wheel of step 6.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.noise.components import NoiseChain, noise_components
from wheelrail.core.noise.radiation import piston_radiation_efficiency, rail_radiation_efficiency, rail_section
from wheelrail.core.noise.track_part_store import stored_track_part
from wheelrail.core.noise.track_vibration import banded_solver, decay_grid, track_vibration
from wheelrail.core.parameters import ModelParameters, TrackParameters
from wheelrail.core.spectra.bands import BAND_HALF_WIDTH, NOISE_BAND_RANGE, noise_bands

LOG10_E = 10.0 * math.log10(math.e)  # 4.343 dB per neper of energy decay
MIN_TRACK_BAYS = 40  # the lengthened track's fewest bays: 20 each side of the load (the free wave, step 3)


@dataclass(frozen=True, kw_only=True)
class NoiseNumerics:
    """How the track's vibration and sound power are computed.

    Attributes
    ----------
    track_bays : int
        Sleeper bays of the lengthened FE track (240: 156 m; the load in the middle, 78 m of rail each side); at
        least :data:`MIN_TRACK_BAYS`.
    elements_per_bay : int
        Rayleigh-Timoshenko elements per bay (16 as the interaction's track: >= 7 per bending wavelength to 8 kHz).
    points_per_band : int
        Frequencies per one-third octave band, evenly spread in lg f (20: doubling it moves L_H,tr by <= 0.2 dB
        except in the 4 kHz band, 3.3 dB, where the undamped rail's second pinned-pinned resonance, a mode with
        still pads, is too sharp for any fixed sampling; doubling ``elements_per_bay`` moves the 4 and 8 kHz bands
        by 5.2 and 3.4 dB for the same reason, every other band by <= 0.3 dB; ``validation/noise.py``). With a
        rail loss factor of 0.02 (``RailParameters.loss_factor``) both doublings move every band up to 8 kHz by
        <= 0.5 dB (``validation/track_damping.py``).
    decay_length : float
        m of rail over which EN 15461's sum is taken.
    sleeper_area : float
        Radiating area of the sleeper per rail, m^2 (assumed: half of a 2.6 m x 0.25 m mono-block sleeper; the
        paper gives the sleeper's mass only).
    """

    track_bays: int = 240
    elements_per_bay: int = 16
    points_per_band: int = 20
    decay_length: float = 60.0
    sleeper_area: float = 0.325

    def __post_init__(self) -> None:
        for name in ("track_bays", "elements_per_bay", "points_per_band"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise WheelrailError(f"NoiseNumerics.{name} must be a whole number >= 1, got {value!r}")
        if self.track_bays < MIN_TRACK_BAYS:
            raise WheelrailError(
                f"NoiseNumerics.track_bays must be at least {MIN_TRACK_BAYS} (the free wave's decay is fitted 3 to "
                f"20 bays from the load in the middle), got {self.track_bays}"
            )
        for name in ("decay_length", "sleeper_area"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
                raise WheelrailError(f"NoiseNumerics.{name} must be a positive number, got {value!r}")


def chain_numerics(track_numerics=None) -> NoiseNumerics:
    """The default's, with the fields of ``track_numerics`` (a TrackNumerics; None: the default) the frequency-domain
    track takes (``inputs.numerics.frequency_domain_fields``): one track for a run's force and its noise."""
    from wheelrail.core.inputs.numerics import frequency_domain_fields

    return NoiseNumerics(**frequency_domain_fields(track_numerics))


def band_frequencies(points_per_band: int) -> np.ndarray:
    """(24, points) frequencies, Hz: each band's width split evenly in lg f, the middle of each part."""
    from wheelrail.core.inputs.checks import integer

    points_per_band = integer("band_frequencies: points_per_band", points_per_band, 1)
    centres = noise_bands()
    parts = (np.arange(points_per_band) + 0.5) / points_per_band  # fractions of the band's width in lg f
    return centres[:, None] / BAND_HALF_WIDTH * BAND_HALF_WIDTH ** (2 * parts[None, :])


@dataclass(frozen=True, kw_only=True, eq=False)
class TrackNoiseModel:
    """The model track's noise transfer functions on the 24 bands 50 Hz .. 10 kHz (module docstring).

    Attributes
    ----------
    frequency_hz : numpy.ndarray
        Exact band centres, Hz.
    power_per_force : dict of str to numpy.ndarray
        Per component driven by the force (:mod:`wheelrail.core.noise.components`: the rail, the sleepers, and the
        wheel for ``wheel_model`` "modal"): band means of its sound power (one rail, its sleepers; one wheel) per
        unit mean-square contact force, W/N^2.
    force_per_roughness_db : numpy.ndarray
        10 lg <|F/r|^2> in dB re 1 N/um.
    effective_roughness_per_force_db : numpy.ndarray
        10 lg <|alpha_W + alpha_R + alpha_C|^2> in dB re 1 um/N: turns a force level into the effective
        roughness that would cause it in the linear model.
    track_transfer_db : numpy.ndarray
        L_H,tr of the model, dB re 1 pW per axle for 0 dB re 1 um (the components driven by the force, two rails).
    transfer_db : dict of str to numpy.ndarray
        Per component, its sound power per axle for 0 dB re 1 um effective roughness, dB re 1 pW: the parts of
        L_H,tr for the rail and sleepers; for the wheel CNOSSOS-EU L_H,veh (Table G-3b) for ``wheel_model``
        "directive", the modal wheel's equivalent for "modal".
    decay_rate_db_per_m : numpy.ndarray
        EN 15461's formula on the model's transfer receptances, dB/m.
    free_wave_decay_db_per_m : numpy.ndarray
        Decay of the free wave 3 to 20 bays from the load, dB/m.
    rail_radiation_efficiency, sleeper_radiation_efficiency : numpy.ndarray
        Band means of sigma (the rail's: the 2D cross-section's at f).
    rail_decay_correction_db : numpy.ndarray
        The rail's power radiated by its field in the wavenumber domain against the 2D ratio applied to the whole
        field (step 4), dB: negative where the field decays within an acoustic wavelength (-4 dB at 50 Hz on the
        paper's track).
    wheel_diameter_mm : int
        The directive's column nearest the model's 2 R (used by "directive"; stated beside "modal").
    configuration : dict
        What produced it.
    wheel_model : str
        "directive" or "modal" (:data:`wheelrail.core.noise.wheel_power.WHEEL_MODELS`).
    wheel_power_per_force : numpy.ndarray or None
        "modal": one wheel's sound power per unit mean-square radial contact force in a band, W/N^2: its W / F^2
        weighted by the coupled force's shape within the band (:mod:`wheelrail.core.noise.wheel_power`, step 5).
    wheel_source : str
        What the wheel's transfer function is, in words (``wheel_transfer_source``).
    track_parts : tuple of str
        The components that radiate from the track's vibration (their sum is ``track_transfer_db``).
    """

    frequency_hz: np.ndarray
    power_per_force: dict
    force_per_roughness_db: np.ndarray
    effective_roughness_per_force_db: np.ndarray
    track_transfer_db: np.ndarray
    transfer_db: dict
    decay_rate_db_per_m: np.ndarray
    free_wave_decay_db_per_m: np.ndarray
    rail_radiation_efficiency: np.ndarray
    sleeper_radiation_efficiency: np.ndarray
    wheel_diameter_mm: int
    configuration: dict = field(default_factory=dict)
    rail_decay_correction_db: np.ndarray | None = None
    wheel_model: str = "directive"
    wheel_power_per_force: np.ndarray | None = None
    wheel_source: str = ""
    track_parts: tuple = ()  # the registry's track parts (NoiseComponent.track_part), as track_noise_model sets them

    def to_dict(self) -> dict:
        """The JSON layout of ``wheelrail noise --method twins --json`` (key ``twins``)."""
        return {
            "track_transfer_dB": self.track_transfer_db,
            **{f"{name}_transfer_dB": levels for name, levels in self.transfer_db.items()},
            "decay_rate_dB_per_m": self.decay_rate_db_per_m,
            "free_wave_decay_dB_per_m": self.free_wave_decay_db_per_m,
            "rail_radiation_efficiency": self.rail_radiation_efficiency,
            "rail_decay_correction_dB": self.rail_decay_correction_db,
            "sleeper_radiation_efficiency": self.sleeper_radiation_efficiency,
            "force_per_roughness_dB_re_1N_per_um": self.force_per_roughness_db,
            "wheel_model": self.wheel_model,
            "wheel_transfer_source": self.wheel_source,
            **(
                {}
                if self.wheel_power_per_force is None
                else {"wheel_power_per_force_W_per_N2": self.wheel_power_per_force}
            ),
            "configuration": self.configuration,
        }


def nearest_table_diameter_mm(wheel_radius: float) -> int:
    """The CNOSSOS-EU Table G-3b wheel diameter (mm) nearest 2 R (R in m)."""
    from wheelrail.core.inputs.ranges import ACCEPTED
    from wheelrail.core.noise.cnossos import WHEEL_DIAMETERS_MM

    wheel_radius = ACCEPTED["wheel_radius"].check(wheel_radius, "nearest_table_diameter_mm: wheel_radius")
    return min(WHEEL_DIAMETERS_MM, key=lambda d: abs(d - 2e3 * wheel_radius))


def track_noise_model(
    params: ModelParameters | None = None,
    numerics: NoiseNumerics | None = None,
    wheel_model: str = "directive",
    wheel_profile=None,
    contact_position=None,
) -> TrackNoiseModel:
    """The model track's noise transfer functions (module docstring) for the wheel, track and contact of
    ``params`` (default: the paper's) and the wheel's ``wheel_model`` ("directive" or "modal", step 6; the modal
    wheel's cross-section ``wheel_profile``, a :class:`wheelrail.core.modal_wheel.WheelProfile`, default the named
    wheel nearest R at R), with the contact at ``contact_position``
    (:class:`wheelrail.core.inputs.contact_position.ContactPosition`, default centred: step 7). Cached per process
    by the parameters, and in parts by what each depends on (the track's vibration, the wheel by its position on
    the tread, the lateral track), so that a new position computes only what it changes."""
    from wheelrail.core.inputs.contact_position import ContactPosition
    from wheelrail.core.noise.wheel_power import checked_wheel_model

    params = ModelParameters() if params is None else params
    if not isinstance(params, ModelParameters):
        raise WheelrailError(f"track_noise_model: params must be ModelParameters, got {type(params).__name__}")
    if numerics is not None and not isinstance(numerics, NoiseNumerics):
        raise WheelrailError(f"track_noise_model: numerics must be NoiseNumerics, got {type(numerics).__name__}")
    contact_position = ContactPosition() if contact_position is None else contact_position
    if not isinstance(contact_position, ContactPosition):
        raise WheelrailError(
            f"track_noise_model: contact_position must be ContactPosition, got {type(contact_position).__name__}"
        )
    # the transfer functions do not depend on the speed: cache on the wheel, track and contact only
    return _track_noise_model(
        ModelParameters(wheel=params.wheel, track=params.track, contact=params.contact),
        NoiseNumerics() if numerics is None else numerics,
        checked_wheel_model(wheel_model),
        _checked_profile(wheel_profile, wheel_model),
        noise_components(),  # in the cache's key: a component registered later has its own chain
        contact_position,
    )


def _checked_profile(wheel_profile, wheel_model: str):
    from wheelrail.core.modal_wheel import OutlineProfile, WheelProfile

    if wheel_profile is None:
        return None
    if wheel_model != "modal":
        raise WheelrailError("track_noise_model: wheel_profile is the modal wheel's; give wheel_model='modal'")
    if not isinstance(wheel_profile, WheelProfile | OutlineProfile):
        raise WheelrailError(
            "track_noise_model: wheel_profile must be a WheelProfile or OutlineProfile, got "
            f"{type(wheel_profile).__name__}"
        )
    return wheel_profile


@functools.lru_cache(maxsize=4)
def _track_part(track: TrackParameters, contact, numerics: NoiseNumerics, driven: tuple) -> dict:
    """:func:`~wheelrail.core.noise.track_vibration.track_vibration` of ``track`` and ``contact`` for the track's
    parts ``driven``, kept per process: it depends on neither the wheel nor the contact's lateral position (every
    wheel model and position reads the same); on disk too (:mod:`~wheelrail.core.noise.track_part_store`)."""
    k_hertz = 1.5 * contact.preload / contact.hertz_approach()  # dF/d delta at the preload (eq. 12)
    freqs = band_frequencies(numerics.points_per_band)
    vibration = functools.partial(track_vibration, ModelParameters(track=track, contact=contact), numerics, k_hertz)
    return stored_track_part(track, k_hertz, numerics, freqs, driven, lambda: vibration(freqs, driven))


def track_decay_rates(
    track: TrackParameters | None = None, numerics: NoiseNumerics | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The vertical decay rates of the noise model's track alone (step 3 of the module docstring; the same
    numbers as :func:`track_noise_model`'s without its other steps): the lengthened FE track of ``track``
    (default the paper's), excited at midspan only.

    Returns
    -------
    (frequency_hz, decay_rate_db_per_m, free_wave_decay_db_per_m) : ndarrays
        Exact band centres 50 Hz-10 kHz; EN 15461's decay rate and the free wave's, dB/m.
    """
    from wheelrail.core.track import assemble_track

    track = TrackParameters() if track is None else track
    numerics = NoiseNumerics() if numerics is None else numerics
    if not isinstance(track, TrackParameters):
        raise WheelrailError(f"track_decay_rates: track must be TrackParameters, got {type(track).__name__}")
    if not isinstance(numerics, NoiseNumerics):
        raise WheelrailError(f"track_decay_rates: numerics must be NoiseNumerics, got {type(numerics).__name__}")
    model = assemble_track(replace(track, n_bays=numerics.track_bays), numerics.elements_per_bay)
    solve = banded_solver(model)
    positions, decay_nodes, free_nodes, free_distance = decay_grid(model, numerics)
    load = model.load_vector(positions[1])
    freqs = band_frequencies(numerics.points_per_band)
    vib = {
        "transfer_sq": np.zeros((freqs.shape[0], decay_nodes.stop - decay_nodes.start)),
        "free_sq": np.zeros((freqs.shape[0], len(free_nodes))),
        "free_distance": free_distance,
        "dx": model.element_length,
    }
    for (b, _), f in np.ndenumerate(freqs):
        rail = solve(f, load)[model.w_dof]
        vib["transfer_sq"][b] += np.abs(rail[decay_nodes]) ** 2
        vib["free_sq"][b] += np.abs(rail[free_nodes]) ** 2
    decay, free = _decay_rates(vib)
    return noise_bands(), decay, free


def _decay_rates(vib: dict) -> tuple[np.ndarray, np.ndarray]:
    """EN 15461's formula on the midspan transfer receptances, and the free wave's slope (dB/m)."""
    ratio = vib["transfer_sq"] / vib["transfer_sq"][:, :1]
    sum_ratio = vib["dx"] * (np.sum(ratio, axis=1) - 0.5 * (ratio[:, 0] + ratio[:, -1]))
    slope = np.polyfit(vib["free_distance"], 10 * np.log10(vib["free_sq"]).T, 1)[0]
    return LOG10_E / sum_ratio, -slope


def _wheel_receptances(
    params: ModelParameters, freqs: np.ndarray, wheel_model: str, profile, tread_offset: float = 0.0
) -> tuple[np.ndarray, dict]:
    """alpha_W at ``freqs`` (step 1) for the wheel model (step 6; the modal wheel's at the contact ``tread_offset``
    m along its tread, step 7), and the modal wheel's response (else {})."""
    from wheelrail.core.noise.wheel_power import modal_wheel_profile, modal_wheel_response
    from wheelrail.core.wheel import wheel_receptance

    if wheel_model == "modal":
        if profile is None:
            profile = modal_wheel_profile(params.contact.radius_along)
        response = modal_wheel_response(profile, freqs, params.wheel.unsprung_mass, tread_offset)
        return response["receptance"], response
    alpha = np.empty(freqs.shape, dtype=complex)
    for index, f in np.ndenumerate(freqs):
        alpha[index] = wheel_receptance(params.wheel, f)
    return alpha, {}


def _wheel_transfer(params: ModelParameters, modal: dict, vib: dict, freqs: np.ndarray, tread_offset=0.0) -> dict:
    """Step 6: the wheel's transfer function per axle (dB), its source in words and, for the modal wheel, the
    band means of W / F^2 (W/N^2), on the wheel's own dense band sampling
    (:func:`wheelrail.core.noise.wheel_power.modal_wheel_band_means`) with alpha_R + alpha_C interpolated in
    lg f (real and imaginary parts) between the chain's points."""
    from wheelrail.core.noise import wheel_power
    from wheelrail.core.noise.cnossos import vehicle_transfer
    from wheelrail.core.noise.wheel_power import modal_wheel_band_means, profile_name

    radius = params.contact.radius_along
    diameter = nearest_table_diameter_mm(radius)
    directive = f"CNOSSOS-EU Table G-3b L_H,veh, {diameter} mm (nearest the model's 2R = {2e3 * radius:.0f} mm)"
    if not modal:
        return {
            "db": vehicle_transfer(diameter),
            "power_per_force": None,
            "source": f"{directive}: the 2-DOF wheel model has no radiating modes",
        }
    lg_f = np.log10(freqs.ravel())
    track = vib["alpha_track"].reshape(-1, vib["alpha_track"].shape[-1])

    def alpha_track(f):
        x = np.log10(f)
        return np.stack([np.interp(x, lg_f, t.real) + 1j * np.interp(x, lg_f, t.imag) for t in track.T], axis=1)

    profile = modal["modes"].profile
    dense = band_frequencies(wheel_power.WHEEL_POINTS_PER_BAND)  # read at the call: a test may change it
    means = modal_wheel_band_means(profile, params.wheel.unsprung_mass, alpha_track, dense, tread_offset)
    return {
        "db": 10 * np.log10(2 * means["power_per_roughness"]),  # (1 um)^2 / 1 pW = 1
        "power_per_force": means["power_per_force_weighted"],  # per a band's force (wheel_power, step 5)
        "source": f"modal wheel ({profile_name(profile)}, 2R = {2e3 * profile.wheel_radius:.0f} mm): axisymmetric "
        f"FE modes n = 0..{modal['modes'].max_harmonic} and their radiation (wheelrail.core.modal_wheel)"
        + (f", driven {tread_offset * 1e3:g} mm along the tread from the rolling circle" if tread_offset else "")
        + f"; not the directive's {directive}",
    }


@functools.lru_cache(maxsize=8)
def _wheel_part(
    params: ModelParameters, numerics: NoiseNumerics, wheel_model: str, profile, tread_offset: float, driven: tuple
) -> tuple[np.ndarray, dict]:
    """alpha_W (step 1) and the wheel's transfer (step 6, :func:`_wheel_transfer`), kept per process: they depend on
    the wheel, the track and, for the modal wheel, the contact's position on the tread, not on the railhead's."""
    freqs = band_frequencies(numerics.points_per_band)
    vib = _track_part(params.track, params.contact, numerics, driven)
    alpha_wheel, modal = _wheel_receptances(params, freqs, wheel_model, profile, tread_offset)
    return alpha_wheel, _wheel_transfer(params, modal, vib, freqs, tread_offset)


def clear_chain_caches() -> None:
    """Empty the chain's caches of this process (the chains by position, the parts they share and the lateral
    track's): for a test or a benchmark that changes a module's numerics or wants a fresh chain."""
    from wheelrail.core.noise.rail_lateral import clear_lateral_cache

    for cached in (_track_noise_model, _wheel_part, _track_part):
        cached.cache_clear()
    clear_lateral_cache()


@functools.lru_cache(maxsize=8)
def _track_noise_model(
    params: ModelParameters, numerics: NoiseNumerics, wheel_model: str, profile, components: tuple, position
) -> TrackNoiseModel:
    from wheelrail.core.noise.components import chain_components

    components = chain_components(components, wheel_model)  # the wheel of the wheel model
    contact = params.contact
    freqs = band_frequencies(numerics.points_per_band)
    driven = tuple(entry for entry in components if entry.track_part)
    vib = _track_part(params.track, contact, numerics, driven)  # the same for every wheel and position
    tread = position.wheel_offset if wheel_model == "modal" else 0.0  # the directive's wheel has no position
    alpha_wheel, wheel = _wheel_part(params, numerics, wheel_model, profile, tread, driven)
    alpha_sq = np.abs(alpha_wheel[..., None] + vib["alpha_track"]) ** 2  # |alpha_W + alpha_R + alpha_C|^2
    sigma_rail = rail_radiation_efficiency(freqs)
    sigma_sleeper = piston_radiation_efficiency(freqs, numerics.sleeper_area)
    decay_correction = 10 * np.log10(np.mean(vib["rail_radiated"], axis=(1, 2)) / np.mean(
        sigma_rail[..., None] * vib["rail"], axis=(1, 2)))  # fmt: skip
    force_per_r_sq = 1.0 / alpha_sq  # (N/m)^2
    decay, free_decay = _decay_rates(vib)
    chain = NoiseChain(params=params, numerics=numerics, frequencies=freqs, wheel=wheel, contact_position=position)
    power_per_force, transfer_db = _component_transfers(components, chain, vib["responses"], force_per_r_sq)
    track_parts = tuple(entry.name for entry in components if entry.track_part)
    track_power = sum(10 ** (transfer_db[name] / 10) for name in track_parts)
    configuration = {
        "method": "twins",
        "track_bays": numerics.track_bays,
        "elements_per_bay": numerics.elements_per_bay,
        "points_per_band": numerics.points_per_band,
        "sleeper_area_m2": numerics.sleeper_area,
        "excitation": "mean of above a sleeper and midspan",
        "preload_n": contact.preload,
        "contact_stiffness_n_per_m": vib["contact_stiffness"],  # dF/d delta at the preload (eq. 12)
        "rail_section": rail_section(),
        "band_range_hz": list(NOISE_BAND_RANGE),
        "wheel_model": wheel_model,
        "wheel": wheel["source"],
        "contact_position": position.to_dict(),
    }
    um2 = 1e-12  # (1 um)^2 in m^2
    return TrackNoiseModel(
        frequency_hz=noise_bands(),
        power_per_force=power_per_force,
        force_per_roughness_db=10 * np.log10(np.mean(force_per_r_sq, axis=(1, 2)) * um2),
        effective_roughness_per_force_db=10 * np.log10(np.mean(alpha_sq, axis=(1, 2)) / um2),
        track_transfer_db=10 * np.log10(track_power),
        transfer_db=transfer_db,
        decay_rate_db_per_m=decay,
        free_wave_decay_db_per_m=free_decay,
        rail_radiation_efficiency=np.mean(sigma_rail, axis=1),
        rail_decay_correction_db=decay_correction,
        sleeper_radiation_efficiency=np.mean(sigma_sleeper, axis=1),
        wheel_diameter_mm=nearest_table_diameter_mm(contact.radius_along),
        configuration=configuration,
        wheel_model=wheel_model,
        wheel_power_per_force=wheel["power_per_force"],
        wheel_source=wheel["source"],
        track_parts=track_parts,
    )


def _component_transfers(components: tuple, chain: NoiseChain, responses: dict, force_per_r_sq: np.ndarray):
    """Each component's band means (:mod:`wheelrail.core.noise.components`): for a part of the track its sound
    power per unit mean-square force T (W/N^2, the mean of radiation x response) and 10 lg(2 <T |F / r|^2>
    (1 um)^2 / 1 pW); for one driven by the force through its own receptance its ``power_per_force`` and
    ``transfer``; for one driven by the roughness its ``transfer``. Returns (power per force, transfer dB)."""
    um2 = 1e-12  # (1 um)^2 in m^2; also 1 pW: the two 1e-12 cancel
    power_per_force, transfer_db = {}, {}
    for entry in components:
        if entry.driven_by == "force" and not entry.track_part:
            power_per_force[entry.name] = np.asarray(entry.power_per_force(chain), dtype=float)
            transfer_db[entry.name] = np.asarray(entry.transfer(chain), dtype=float)
        elif entry.driven_by == "force":
            power = entry.radiation(chain) * responses[entry.name]  # W/N^2 (rms force, rms velocity), (b, p, 2)
            power_per_force[entry.name] = np.mean(power, axis=(1, 2))
            with np.errstate(divide="ignore"):  # a part that does not radiate (the centred contact's lateral rail)
                transfer_db[entry.name] = 10 * np.log10(2 * np.mean(power * force_per_r_sq, axis=(1, 2)) * um2 / 1e-12)
        else:
            transfer_db[entry.name] = np.asarray(entry.transfer(chain), dtype=float)
    return power_per_force, transfer_db


def with_modal_wheel(track, params, wheel_profile=None, numerics=None, contact_position=None):
    """``track`` (a :class:`wheelrail.core.noise.twins.TrackNoiseModel` of the 2-DOF wheel, as the force of a run
    with the 2-DOF wheel was computed) with the modal wheel's L_H,veh-equivalent in the place of the directive's,
    driven by the roughness: a given force (a 2-DOF run's, the ``noise`` study's) becomes the effective roughness
    that causes it in its own linear model (the 2-DOF wheel's alpha_W), and that roughness excites the modal
    wheel's chain (its own coupled contact force), as L_H,veh does in the directive's place. Radiating that force
    directly with the modal wheel's W / F^2 would put the 2-DOF wheel's force into the modal wheel's undamped
    resonances, a force the modal wheel's own receptance cuts there; a run with the modal wheel has that force,
    and its noise takes the modal chain itself (:func:`wheelrail.core.noise.run_noise.run_noise`). The rail and
    sleeper transfer functions and the effective roughness stay the 2-DOF chain's. ``contact_position``: the
    modal wheel's chain's (step 7; give ``track``'s own)."""
    import dataclasses

    modal = track_noise_model(params, numerics, "modal", wheel_profile, contact_position)
    source = f"{modal.wheel_source}; on the effective roughness of the 2-DOF wheel's force"
    wheels = {name: levels for name, levels in modal.transfer_db.items() if name not in track.power_per_force}
    return dataclasses.replace(
        track,
        wheel_model="modal",
        transfer_db={**track.transfer_db, **wheels},  # the components driven by the roughness: the wheel's
        wheel_source=source,
        configuration={**track.configuration, "wheel_model": "modal", "wheel": source},
    )
