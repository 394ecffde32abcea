"""The wheel's sound power in the TWINS-like chain: the directive's table or the modal wheel's own radiation.

Two wheel models (:data:`WHEEL_MODELS`; the command line's ``--wheel-model``, declared in
:data:`wheelrail.core.inputs.declared.CHOICES`):

- ``directive`` (the default): CNOSSOS-EU's vehicle transfer function L_H,veh (Table G-3b) for the tabulated
  diameter nearest the model's 2 R; the paper's 2-DOF wheel has no radiating modes.
- ``modal``: the wheel's own vibration and radiation (Thompson, *Railway Noise and Vibration*, 2009, ch. 5, the
  TWINS wheel). Per unit RMS radial contact force, at every frequency of the chain's band sampling:

  1. the axisymmetric FE wheel's modes (:func:`wheelrail.core.modal_wheel.wheel_modes`, bore clamped, n = 0..10,
     up to 10 kHz) give the spatially averaged mean-square normal velocity <v_d,n^2> of its axially and radially
     facing surfaces (areas S_d) per number of nodal diameters n
     (:func:`wheelrail.core.modal_wheel.mean_square_velocity`);
  2. W / F^2 = rho c sum_d S_d sum_n sigma_d,n(f) <v_d,n^2> with the radiation efficiency of each family
     (:mod:`wheelrail.core.modal_wheel.radiation`, eq. 1);
  3. the force per unit roughness |F / r| = 1 / |alpha_W + alpha_R + alpha_C| as for the rail
     (:mod:`wheelrail.core.noise.twins`, step 1), with alpha_W the modal wheel's radial point receptance at the
     contact plus the rigid unsprung mass's -1 / (M_W w^2) (the FE wheel is clamped at its bore: the axle's and
     wheel's rigid motion is the paper's unsprung mass M_W; the primary suspension, a few Hz, is left out);
  4. the L_H,veh-equivalent (the same definition as ``twins.wheel_transfer_dB``): sound power of the two wheels
     of an axle for 0 dB re 1 um effective roughness, 10 lg(2 <W / F^2 |F / r|^2> (1 um)^2 / 1 pW);
  5. driven by a force (a run's, with this wheel): a band's mean-square force <F^2> gives the sound power
     <F^2> <W / F^2 |F / r|^2> / <|F / r|^2>. Within a band the force follows |F / r|^2 of the coupled wheel, track
     and contact (the roughness taken as flat across the band): it falls to nothing at each of the wheel's
     resonances, where the receptance alpha_W, and so W / F^2, peaks (loss factors of 1e-4: peaks 1e-4 f wide,
     far narrower than a run's spectrum resolves). The plain band mean <W / F^2> is held by those peaks and would
     put a force the wheel does not get into them (on the corrugated rail's modal-wheel run, 12.7 dB(A) more).

  6. the contact off the nominal rolling circle (``tread_offset``, the chain's ``contact_offset_wheel``,
     :mod:`wheelrail.core.inputs.contact_position`): the radial force acts at that point of the tread, so each
     mode is driven (and its receptance at the contact read) through its radial displacement there
     (:func:`wheelrail.core.modal_wheel.receptance.tread_shapes`): the axial modes, which dominate a wheel's
     noise, are driven in proportion to the offset.

  The wheel's profile is given (``wheel_profile``), or the named wheel nearest the model's R, at R
  (:func:`modal_wheel_profile`; :data:`wheelrail.core.modal_wheel.NAMED_WHEELS`: 920, 840, 640 mm). Only radial
  (vertical) excitation is modelled, as for the track: the lateral (creep) force, the wheel's rotation and the
  rigid wheelset's own radiation are left out.
"""

from __future__ import annotations

import contextlib
import contextvars
import functools
from collections.abc import Callable, Iterator

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.declared import choice
from wheelrail.core.noise.radiation import AIR_DENSITY, SOUND_SPEED

WHEEL_MODELS = choice("noise_wheel_model").values  # ("directive", "modal")
DEFAULT_WHEEL_MODEL = choice("noise_wheel_model").default
MAX_HARMONIC = 10  # n = 0..10 nodal diameters: every wheel mode of the 640-920 mm wheels below 10 kHz
MAX_FREQUENCY = 12.5e3  # Hz: modes up to the top band's upper edge (11.2 kHz) and some above
SIGMA_TABLE_HZ = (35.0, 12500.0, 77)  # radiation efficiency table: 30 points per decade, interpolated in lg f
# Frequencies per band of the wheel's band means: its modes have loss factors of 1e-4 (n >= 2; 1e-3 for n = 0, 1),
# half-power widths of 1e-4 f, far below the track's 20 points per band; the L_H,veh-equivalent of the 920 mm
# wheel moves by <= 0.6 dB per band 500 Hz-5 kHz from 1 000 to 4 000 points (tests/physics/test_modal_wheel_noise.py)
WHEEL_POINTS_PER_BAND = 1000
RADIATION_PHASE = "the radiation efficiencies of its surfaces, once per radius, tyre width and bore"
_PROGRESS: contextvars.ContextVar[Callable[[str, int, int], None] | None] = contextvars.ContextVar(
    "wheelrail_radiation_progress", default=None
)


@contextlib.contextmanager
def radiation_progress(callback: Callable[[str, int, int], None] | None) -> Iterator[None]:
    """Report the progress of any radiation table computed in this block (this thread) to ``callback``, as
    ``callback(RADIATION_PHASE, done, total)`` before the first and after each harmonic and direction."""
    token = _PROGRESS.set(callback)
    try:
        yield
    finally:
        _PROGRESS.reset(token)


def checked_wheel_model(wheel_model) -> str:
    """``wheel_model`` if it is one of :data:`WHEEL_MODELS`, else one WheelrailError naming them."""
    return choice("noise_wheel_model").check(wheel_model)


def modal_wheel_profile(wheel_radius: float):
    """The modal wheel's cross-section for a running radius (m): the wheel helper's rule
    (:func:`wheelrail.core.modal_wheel.profile.wheel_profile_for`): the named wheel nearest in radius, at that
    radius, its other dimensions kept (a named wheel itself at its own radius)."""
    from wheelrail.core.modal_wheel.profile import wheel_profile_for

    return wheel_profile_for(float(wheel_radius))


def profile_name(profile) -> str:
    """The named wheel's name ("freight_920"), "<name>'s shape" for a named wheel at another radius, else
    "parametric" or "outline"."""
    import dataclasses

    from wheelrail.core.modal_wheel import NAMED_WHEELS, WheelProfile

    if not isinstance(profile, WheelProfile):
        return "outline"
    for name, named in NAMED_WHEELS.items():
        if named == profile:
            return name
        if dataclasses.replace(named, wheel_radius=profile.wheel_radius) == profile:
            return f"{name}'s shape"
    return "parametric"


@functools.lru_cache(maxsize=16)
def radiation_table(profile) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(f on :data:`SIGMA_TABLE_HZ`, sigma_axial (f, n), sigma_radial (f, n)) for n = 0..MAX_HARMONIC, disk-cached
    by the geometry the radiation uses (its radius, tyre width and bore); up to a minute to build, its progress
    reported to the callable of :func:`radiation_progress`."""
    from wheelrail.core.files.cache import cache_key, load_entry, save_entry
    from wheelrail.core.modal_wheel.radiation import wheel_radiation_efficiency

    geometry = {"radius": profile.wheel_radius, "tyre_width": profile.tyre_width, "hub": profile.bore_radius}
    f = np.geomspace(*SIGMA_TABLE_HZ)
    key = cache_key("wheel-radiation", {**geometry, "grid": list(SIGMA_TABLE_HZ), "n": MAX_HARMONIC, "version": 1})
    entry = load_entry("wheel-radiation", key, ("axial", "radial"))
    if entry is not None:
        return f, entry["axial"], entry["radial"]
    progress = _PROGRESS.get() or (lambda phase, done, total: None)
    jobs = [(d, n) for d in ("axial", "radial") for n in range(MAX_HARMONIC + 1)]
    progress(RADIATION_PHASE, 0, len(jobs))
    columns = {}
    for done, (d, n) in enumerate(jobs, start=1):
        columns[d, n] = wheel_radiation_efficiency(
            f, n, d, radius=geometry["radius"], tyre_width=geometry["tyre_width"], hub_radius=geometry["hub"]
        )
        progress(RADIATION_PHASE, done, len(jobs))
    tables = {d: np.stack([columns[d, n] for n in range(MAX_HARMONIC + 1)], axis=1) for d in ("axial", "radial")}
    save_entry("wheel-radiation", key, tables)
    return f, tables["axial"], tables["radial"]


def _on(frequencies: np.ndarray, f_table: np.ndarray, table: np.ndarray) -> np.ndarray:
    """A sigma table (f, n) interpolated in lg f (lg sigma) onto ``frequencies`` (held at the table's ends)."""
    lf, lt = np.log10(frequencies), np.log10(f_table)
    with np.errstate(divide="ignore"):
        log_sigma = np.log10(np.maximum(table, 1e-300))
    return 10 ** np.stack([np.interp(lf, lt, log_sigma[:, n]) for n in range(table.shape[1])], axis=1)


def modal_wheel_response(profile, frequencies, unsprung_mass: float, tread_offset: float = 0.0) -> dict:
    """The modal wheel at ``frequencies`` (Hz, any shape): ``receptance`` alpha_W (m/N, steps 3 of the module
    docstring), ``power_per_force`` W / F^2 (W/N^2, step 2) and its ``axial`` and ``radial`` parts, for a radial
    force at the contact ``tread_offset`` m along the tread from the rolling circle (step 6)."""
    from wheelrail.core.modal_wheel import contact_receptance, mean_square_velocity, wheel_modes

    f = np.asarray(frequencies, dtype=float)
    if not (np.all(np.isfinite(f)) and np.all(f > 0)):
        raise WheelrailError("modal_wheel_response: frequencies must be positive and finite (Hz)")
    modes = wheel_modes(profile, max_frequency=MAX_FREQUENCY, max_harmonic=MAX_HARMONIC)
    flat = f.ravel()
    alpha = contact_receptance(modes, flat, tread_offset=tread_offset).radial - 1.0 / (
        unsprung_mass * (2 * np.pi * flat) ** 2
    )
    velocity = mean_square_velocity(modes, flat, force_radial=1.0, tread_offset=tread_offset)
    f_table, axial, radial = radiation_table(profile)
    harmonics = np.asarray(velocity.harmonic)
    parts = {
        "axial": velocity.area_axial * np.sum(_on(flat, f_table, axial)[:, harmonics] * velocity.axial, axis=1),
        "radial": velocity.area_radial * np.sum(_on(flat, f_table, radial)[:, harmonics] * velocity.radial, axis=1),
    }
    rho_c = AIR_DENSITY * SOUND_SPEED
    return {
        "receptance": alpha.reshape(f.shape),
        "power_per_force": (rho_c * (parts["axial"] + parts["radial"])).reshape(f.shape),
        "axial": (rho_c * parts["axial"]).reshape(f.shape),
        "radial": (rho_c * parts["radial"]).reshape(f.shape),
        "modes": modes,
    }


def modal_wheel_band_means(profile, unsprung_mass: float, alpha_track, freqs, tread_offset: float = 0.0):
    """Band means (over axis 1 of ``freqs``, (bands, points) Hz: :data:`WHEEL_POINTS_PER_BAND` per band evenly in
    lg f, ``twins.band_frequencies``) of the modal wheel's W / F^2 (W/N^2) and of W / F^2 |F / r|^2 (W/m^2) with
    |F / r| = 1 / |alpha_W + alpha_T| for each excitation position. ``alpha_track(f)`` gives alpha_R + alpha_C
    (m/N) at frequencies f (n,) as (n, positions): the track's receptance, smooth beside the wheel's modes,
    interpolated by the caller between its own points.

    Returns ``power_per_force`` (24,), ``power_per_roughness`` (24,) (the mean over positions too), ``force_sq``
    (24,) the band means of |F / r|^2 (N^2/m^2; over positions too), ``power_per_force_weighted`` (24,) W / F^2
    weighted by the coupled force's shape within the band, <W / F^2 |F / r|^2> / <|F / r|^2> (W/N^2: a band's
    mean-square force times it is the wheel's sound power; module docstring, step 5), and ``modes``; the radial
    force at the contact ``tread_offset`` m along the tread from the rolling circle (step 6)."""
    power, per_roughness, force_mean = np.empty(freqs.shape[0]), np.empty(freqs.shape[0]), np.empty(freqs.shape[0])
    modes = None
    for b, f in enumerate(freqs):  # a band at a time: the modal sums hold (points, modes, surface points)
        response = modal_wheel_response(profile, f, unsprung_mass, tread_offset)
        modes = response["modes"]
        force_sq = 1.0 / np.abs(response["receptance"][:, None] + alpha_track(f)) ** 2
        power[b] = np.mean(response["power_per_force"])
        per_roughness[b] = np.mean(response["power_per_force"][:, None] * force_sq)
        force_mean[b] = np.mean(force_sq)
    return {
        "power_per_force": power,
        "power_per_roughness": per_roughness,
        "force_sq": force_mean,
        "power_per_force_weighted": per_roughness / force_mean,
        "modes": modes,
    }
