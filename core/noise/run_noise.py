"""A finished run (any contact model) to sound power, dB(A), pass-by level and a pass-by you can hear.

One wheel on one rail (what a run simulates), band by band (24 bands 50 Hz .. 10 kHz), for every component of
the chain (:mod:`wheelrail.core.noise.components`: the rail (vertical; lateral through the contact's offset on the
railhead, ``contact_position``), the sleepers and the wheel, and any registered):

- contact-force level L_F (dB re 1 N) of the run's dynamic force (:func:`wheelrail.core.spectra.force.force_spectrum`);
- a component driven by the force (rail, rail lateral, sleepers; the modal wheel): L_W = L_F + 10 lg(T / 1 pW),
  T its sound power per unit mean-square force through its own receptance
  (:func:`wheelrail.core.noise.twins.track_noise_model`,
  the same wheel, track and contact as the run): for ``wheel_model`` "modal" on a run with the modal wheel, the
  wheel's T is the modal wheel's W / F^2 weighted by the coupled force's shape within the band (the run's own
  wheel, :mod:`wheelrail.core.noise.wheel_power`, step 5);
- a component driven by the roughness: the effective roughness that causes L_F in the linear model,
  L_r = L_F + 10 lg <|alpha_W + alpha_R + alpha_C|^2> (dB re 1 um), plus its transfer per axle (two wheels: minus
  3 dB). The wheel for ``wheel_model`` "directive" (the default) is CNOSSOS-EU's L_H,veh for the nearest
  tabulated diameter (it has no receptance, :mod:`wheelrail.core.noise.twins`); for "modal" on a run whose force
  came from another wheel (the 2-DOF wheel), the modal wheel's L_H,veh-equivalent on that run's effective
  roughness (:func:`wheelrail.core.noise.twins.with_modal_wheel`: the 2-DOF wheel's force lacks the modal wheel's
  resonances, which its own receptance would have cut);
- total and L_WA per wheel; per axle +3 dB (two wheels on two rails, incoherent).

**Pass-by level** at the ISO 3095 position (7.5 m from the track centre, 1.2 m above the rail head): every axle a
point source of the axle's sound power W radiating into the half space above a rigid ground (p^2 = rho c W /
(2 pi r^2)), moving at speed v past the microphone at distance d = sqrt(7.5^2 + 1.2^2) m; one axle's sound
exposure within T_p = l / v (from the first axle at the microphone to the last, axles at s_k evenly from 0 to l
behind the first) is rho c W / (2 pi d v) [atan(s_k / d) + atan((l - s_k) / d)] (rho c W / (2 d v) for a whole
passage), so L_pAeq,Tp = L_WA,axle + 10 lg(sum_k [atan(s_k / d) + atan((l - s_k) / d)] / (2 pi d l))
+ 10 lg(rho c 1 pW / (20 uPa)^2) (derived here; N / (2 d l) for a train much longer than d: the 40-axle, 200 m
default train is 0.53 dB below that, a 16-axle 80 m one 1.1 dB).

**Pass-by WAV**: the run's dynamic force (sampled at v / dx, 27.8 kHz at 100 km/h) is filtered by the pressure
per unit force at the closest distance, |p / F|^2 = rho c sum_c T_c / (2 pi d^2) over the components, a zero-phase
FIR interpolated in lg f between the band values; each wheel of each axle gets its own stretch of the force record
(cyclically shifted at random, so the wheels are incoherent; a record shorter than the pass-by repeats; on a run
with a wheel flat the record is first made one revolution, or whole revolutions, long: :func:`wheel_record`), is
weighted by the distance law d / r(t) of its own position, and all are summed. Doppler shift is not applied.
The pressure is resampled to 48 kHz and scaled so that its own L_pAeq over T_p is the pass-by level above (the
random stretches alone move it by -0.6 to +0.8 dB between seeds). Calibration: the samples are pressure in Pa
divided by the ``full_scale_pa`` written in the summary (16-bit PCM, peak at half of full scale); the level
computed from the WAV's samples is the pass-by level within 0.05 dB for any seed (``tests/unit/test_wav.py``).
"""

from __future__ import annotations

import dataclasses
import io
import math
from dataclasses import dataclass, field

import numpy as np

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.noise.components import TOTAL
from wheelrail.core.noise.pass_by import (
    DEFAULT_TRAIN_AXLES,
    DEFAULT_TRAIN_LENGTH,
    ISO3095_DISTANCE,
    ISO3095_HEIGHT,
    pass_by_level,
    receiver_distance,
)
from wheelrail.core.noise.radiation import AIR_DENSITY, SOUND_SPEED
from wheelrail.core.spectra.bands import NOISE_BAND_RANGE, noise_bands
from wheelrail.core.spectra.levels import (
    PRESSURE_REFERENCE,
    a_weighted_energy,
    a_weighted_total,
    energy_sum,
    power_level,
)

WAV_RATE = 48_000  # Hz: the pass-by WAV's sample rate (a standard one; the run's own is v / dx)
# Closest accepted even axle spacing of a train, m: no bogie has axles closer than about 1.4 m (tram and
# light-rail bogies; wheels of 0.6 to 1 m diameter); 40 axles in a 2.5 m train (one every 6 cm) is a typo
MIN_AXLE_SPACING = 1.0
AXLE_DB = 10 * math.log10(2)  # an axle: two wheels on two rails, incoherent (a run is one wheel on one rail)


@dataclass(frozen=True, kw_only=True, eq=False)
class RunNoise:
    """Sound power of one run, per component and band, and its pass-by (module docstring).

    Attributes
    ----------
    frequency_hz : numpy.ndarray
        Exact band centres, Hz (24 bands 50 Hz .. 10 kHz).
    force_db : numpy.ndarray
        Dynamic contact-force level, dB re 1 N (NaN above the run's Nyquist frequency).
    effective_roughness_db : numpy.ndarray
        Effective roughness that causes the force in the linear model, dB re 1 um.
    sound_power_db : dict
        Per component (``rail``, ``sleeper``, ``wheel`` and any registered,
        :func:`wheelrail.core.noise.components.component_names`), then ``total``: dB re 1 pW for one wheel on one
        rail.
    sound_power_dba : dict
        Their A-weighted totals.
    axle_dba : float
        L_WA of an axle (two wheels), dB(A) re 1 pW.
    pass_by_laeq_dba : float
        L_pAeq,Tp at 7.5 m / 1.2 m for ``train_axles`` axles in ``train_length`` m.
    configuration : dict
        What produced it (the run's header, the train, the wheel transfer's source).
    cnossos : CnossosResult or None
        The CNOSSOS-EU source of one axle beside it, on the run's own roughness
        (:func:`wheelrail.core.noise.cnossos_run.cnossos_beside_run`).
    impact : ImpactNoise or None
        For a run with discrete irregularities: the exposure level per impact, its repetition rate and the
        pass-by level from them (:mod:`wheelrail.core.noise.impact_noise`); None without.
    """

    frequency_hz: np.ndarray
    force_db: np.ndarray
    effective_roughness_db: np.ndarray
    sound_power_db: dict
    sound_power_dba: dict
    axle_dba: float
    pass_by_laeq_dba: float
    configuration: dict = field(default_factory=dict)
    cnossos: object = None
    impact: object = None
    _force: np.ndarray | None = None
    _time_step: float = 0.0
    _pressure_per_force_sq: np.ndarray | None = None
    _revolution_steps: int = 0  # steps of one wheel revolution (2 pi R / dx) on a run with a flat, else 0

    @property
    def wav_level_dba(self) -> float:
        """The L_pAeq,Tp the WAV is calibrated to: on a run with a wheel flat the pass-by of the record made one
        revolution (or whole revolutions) long, which is the impacts' (``impact.pass_by_laeq_dba["flat"]``: the
        record's energy at once per revolution); else :attr:`pass_by_laeq_dba`."""
        if self._revolution_steps and self.impact is not None and "flat" in self.impact.pass_by_laeq_dba:
            return self.impact.pass_by_laeq_dba["flat"]
        return self.pass_by_laeq_dba

    @property
    def wav_fill(self) -> str:
        """How the WAV's wheels fill the pass-by from the run's record, in words."""
        if not self._revolution_steps:
            return "each wheel a randomly shifted stretch of the record, repeated where the pass-by is longer"
        return (
            "a flat: the record made one revolution (2 pi R / v) long, the wheel's flat heard once per revolution: "
            "a record shorter than a revolution is filled with the mean force (no dynamic force: between impacts "
            "the WAV holds nothing of the run), a longer one cut to whole revolutions; each wheel at a random phase"
        )

    def to_dict(self) -> dict:
        """The JSON layout of ``wheelrail noise --run F.npz --json``."""
        from wheelrail.core.spectra.bands import band_labels

        return {
            "band_labels": band_labels(self.frequency_hz),
            "frequency_hz": self.frequency_hz,
            "force_dB_re_1N": self.force_db,
            "effective_roughness_dB_re_1um": self.effective_roughness_db,
            "sound_power_dB": self.sound_power_db,
            "sound_power_dBA": self.sound_power_dba,
            "axle_dBA": self.axle_dba,
            "total_dBA": self.sound_power_dba["total"],
            "pass_by_LpAeq_dBA": self.pass_by_laeq_dba,
            "configuration": self.configuration,
            **({} if self.cnossos is None else {"cnossos": self.cnossos_summary()}),
            **({} if self.impact is None else {"impact": self.impact.to_dict()}),
        }

    def csv_text(self, comment: str = "") -> str:
        """The sound power per band as CSV: ``comment`` (``#`` lines naming the run, e.g.
        :meth:`wheelrail.core.engine.results.RunHeader.csv_comment`), a line with the train and the totals, then
        ``band, centre_hz``, the force level and the sound power of each component (``<name>_dB``) and their total
        (``total_dB``) of one wheel on one rail (dB re 1 pW; empty where a band is above the run's Nyquist
        frequency)."""
        from wheelrail.core.spectra.bands import band_labels

        axles, length = self.train
        lines = [
            comment.rstrip("\n"),
            f"# sound power of one wheel on one rail, dB re 1 pW; L_WA per wheel {self.sound_power_dba['total']:.2f}"
            f" dB(A), per axle {self.axle_dba:.2f} dB(A); pass-by L_pAeq,Tp {self.pass_by_laeq_dba:.2f} dB(A) at "
            f"{ISO3095_DISTANCE:g} m / {ISO3095_HEIGHT:g} m for {axles} axles in {length:g} m",
            *([] if self.impact is None else ["#" + line.lstrip() for line in self.impact.lines()]),
            "band,centre_hz,force_dB_re_1N," + ",".join(f"{name}_dB" for name in self.sound_power_db),
        ]
        columns = [self.force_db, *self.sound_power_db.values()]
        for i, (label, centre) in enumerate(zip(band_labels(self.frequency_hz), self.frequency_hz, strict=True)):
            cells = ["" if not np.isfinite(column[i]) else f"{column[i]:.3f}" for column in columns]
            lines.append(",".join([label, f"{centre:.6g}", *cells]))
        return "\n".join(line for line in lines if line) + "\n"

    @property
    def train(self) -> tuple[int, float]:
        """Axles and length (m) of the train of the pass-by level and WAV."""
        return self.configuration["train_axles"], self.configuration["train_length_m"]

    def cnossos_pass_by_dba(self) -> float:
        """L_pAeq,Tp of the CNOSSOS-EU source beside it, by the same pass-by formula and train (NaN without)."""
        if self.cnossos is None:
            return math.nan
        return pass_by_level(self.cnossos.total_dba, *self.train)

    def cnossos_summary(self) -> dict:
        """The CNOSSOS-EU source beside the run (``cnossos`` of :meth:`to_dict`): per axle, with its pass-by level."""
        return {**self.cnossos.to_dict(), "pass_by_LpAeq_dBA": self.cnossos_pass_by_dba(), "per": "axle"}

    def with_train(self, train_axles: int, train_length: float) -> RunNoise:
        """The same sound power for another train: its pass-by level and WAV."""
        axles, length = checked_train(train_axles, train_length)
        configuration = {**self.configuration, "train_axles": axles, "train_length_m": length}
        impact = None if self.impact is None else self.impact.with_train(axles, length)
        return dataclasses.replace(
            self,
            pass_by_laeq_dba=pass_by_level(self.axle_dba, axles, length),
            configuration=configuration,
            impact=impact,
        )

    def pass_by_pressure(self, *, lead: float = 1.0, seed: int = 0) -> tuple[np.ndarray, float, tuple[int, int]]:
        """The synthesised pass-by pressure (Pa), its sample rate (Hz) and the sample range of T_p.

        ``lead``: seconds before the first axle reaches the microphone and after the last has passed.
        """
        return _synthesise(self, lead=lead, seed=seed)

    def calibrated_pass_by(self, *, lead: float = 1.0, seed: int = 0, rate: int = WAV_RATE):
        """The pass-by pressure (Pa) at ``rate`` Hz, scaled so that its own L_pAeq over T_p is the pass-by
        level; returns (pressure, rate, (first, last) samples of T_p, the correction applied in dB).

        The synthesis (module docstring) gives the spectrum's shape; its level moves with the random
        stretches of the record each wheel gets (-0.6 to +0.8 dB between seeds on a 2 m run) and with the
        gain interpolated between bands (+0.1 dB), so the level is set here: the correction is what it
        took. The run's rate (v / dx, e.g. 27 778 Hz) is resampled (``scipy.signal.resample_poly``, the ratio
        to within 1e-6) to ``rate``, one every player handles.
        """
        from fractions import Fraction

        from scipy.signal import resample_poly

        pressure, own_rate, (first, last) = self.pass_by_pressure(lead=lead, seed=seed)
        ratio = Fraction(rate / own_rate).limit_denominator(2000)
        pressure = resample_poly(pressure, ratio.numerator, ratio.denominator)
        first, last = int(round(first * ratio)), min(len(pressure), int(round(last * ratio)))
        correction = 0.0
        if math.isfinite(self.wav_level_dba) and last - first > 1 and np.any(pressure[first:last]):
            correction = self.wav_level_dba - laeq_of_pressure(pressure[first:last], float(rate))
            pressure = pressure * 10 ** (correction / 20)
        return pressure, float(rate), (first, last), correction

    def wav_bytes(self, *, lead: float = 1.0, seed: int = 0, rate: int = WAV_RATE) -> tuple[bytes, float]:
        """The pass-by as a 16-bit PCM WAV file's bytes at ``rate`` Hz and its calibration (Pa at full scale):
        its own L_pAeq over T_p is the pass-by level (:meth:`calibrated_pass_by`). :meth:`write_wav` writes the
        same to a file without holding it."""
        buffer = io.BytesIO()
        full_scale = self.write_wav(buffer, lead=lead, seed=seed, rate=rate)
        return buffer.getvalue(), full_scale

    def write_wav(self, handle, *, lead: float = 1.0, seed: int = 0, rate: int = WAV_RATE) -> float:
        """Write the pass-by to the binary file ``handle`` as a 16-bit PCM WAV at ``rate`` Hz, block by block
        (:func:`wheelrail.core.noise.wav.write_wav`: memory bounded, at most ``MAX_WAV_S`` long, else one
        WheelrailError); returns its calibration, Pa at full scale."""
        from wheelrail.core.noise.wav import write_wav

        return write_wav(self, handle, lead=lead, seed=seed, rate=rate)


def _band_values_on(frequencies: np.ndarray, band_db: np.ndarray) -> np.ndarray:
    """Band levels (dB on the 24 exact centres) interpolated in lg f onto ``frequencies`` (held at the ends)."""
    centres = noise_bands()
    return np.interp(np.log10(np.maximum(frequencies, 1e-3)), np.log10(centres), band_db)


def sound_power_from_force(force_db, track) -> dict:
    """Sound power of one wheel on one rail from its contact-force levels (24 bands, dB re 1 N; NaN: unresolved).

    ``track`` is the :class:`wheelrail.core.noise.twins.TrackNoiseModel` of the run's wheel, track and contact;
    its components (``track.transfer_db``) are the parts. Returns ``db`` (each component's and the ``total``
    sound power, dB re 1 pW per band), ``dba`` (their A-weighted totals, NaN bands left out), ``axle_dba`` (two
    wheels) and ``roughness_db`` (the effective roughness, dB re 1 um).
    """
    force_db = np.asarray(force_db, dtype=float)
    if force_db.shape != track.frequency_hz.shape:
        raise WheelrailError(f"force levels: {force_db.size} values for the {track.frequency_hz.size} noise bands")
    mean_sq_force = 10 ** (force_db / 10)
    roughness = force_db + track.effective_roughness_per_force_db
    powers = {}
    for name, transfer in track.transfer_db.items():
        if name in track.power_per_force:  # driven by the force: its sound power per unit mean-square force
            powers[name] = power_level(track.power_per_force[name] * mean_sq_force)
        else:  # driven by the roughness: its transfer per axle (L_H,veh or the modal wheel's), one wheel of two
            powers[name] = roughness + transfer - AXLE_DB
    powers[TOTAL] = energy_sum(*powers.values())
    dba = {name: a_weighted_total(np.where(np.isfinite(levels), levels, -np.inf)) for name, levels in powers.items()}
    return {"db": powers, "dba": dba, "axle_dba": dba["total"] + AXLE_DB, "roughness_db": roughness}


def run_noise(
    result,
    *,
    train_axles: int = DEFAULT_TRAIN_AXLES,
    train_length: float = DEFAULT_TRAIN_LENGTH,
    numerics=None,
    wheel_model: str = "directive",
    wheel_profile=None,
    contact_position=None,
) -> RunNoise:
    """Sound power, dB(A) and pass-by level of a finished run (:class:`wheelrail.core.engine.results.RunResult`).

    Parameters
    ----------
    result : RunResult
        A run of any contact model (``simulate`` or ``RunResult.load_npz``).
    train_axles : int
        Axles of the train for the pass-by level.
    train_length : float
        Train length, m.
    numerics : NoiseNumerics, optional
        How the track's transfer functions are computed (default :class:`wheelrail.core.noise.twins.NoiseNumerics`
        with the run's own elements per bay: its track numerics' frequency-domain fields,
        :func:`wheelrail.core.inputs.numerics.frequency_domain_fields`).
    wheel_model : str
        "directive" (CNOSSOS-EU's L_H,veh on the effective roughness) or "modal" (the modal wheel: on a run with
        the modal wheel of the same cross-section, driven by the run's force through its W / F^2; on another run,
        its L_H,veh-equivalent on the effective roughness): :mod:`wheelrail.core.noise.wheel_power`.
    wheel_profile : WheelProfile, optional
        The modal wheel's cross-section (default: the run's own, ``RunHeader.wheel_profile``, for a run with the
        modal wheel; else the named wheel nearest the run's R, at R).
    contact_position : ContactPosition, optional
        The contact's lateral position on the railhead (drives the ``rail_lateral`` component) and on the wheel's
        tread (the modal wheel's axial modes): :class:`wheelrail.core.inputs.contact_position.ContactPosition`,
        default centred (no lateral rail vibration; the wheel driven at its rolling circle). The run's force is
        the same: the interaction is vertical.

    Returns
    -------
    RunNoise
        The sound power of one wheel on one rail per band (dB re 1 pW) of each component of the chain
        (:func:`wheelrail.core.noise.components.component_names`) and their total, their A-weighted totals, the
        axle's L_WA, the pass-by level of the train, the CNOSSOS-EU source beside it on the run's roughness and
        what produced them (``configuration``); :meth:`RunNoise.to_dict` and :meth:`RunNoise.csv_text` give the
        JSON and CSV of ``wheelrail noise --run``, :meth:`RunNoise.write_wav` the pass-by.

    Raises
    ------
    WheelrailError
        If ``result`` is not a finished run, is too short for a force spectrum or has no fluctuating force, or
        an input is out of its range.

    Examples
    --------
    0.6 m of the bundled corrugated rail under the Hertz spring at 100 km/h, its noise on a coarse track (40 bays,
    one frequency per band: the default numerics resolve the bands):

    >>> from wheelrail.core.engine import simulate
    >>> from wheelrail.core.noise.components import sound_power_parts
    >>> from wheelrail.core.noise.run_noise import run_noise
    >>> from wheelrail.core.noise.twins import NoiseNumerics
    >>> result = simulate("corrugated-rail", model="hertz", line=0, length=0.6)
    >>> noise = run_noise(result, numerics=NoiseNumerics(track_bays=40, elements_per_bay=4, points_per_band=1))
    >>> tuple(noise.sound_power_db) == sound_power_parts()   # the rail's, sleepers', wheel's and their total
    True
    >>> noise.sound_power_db["wheel"].shape               # dB re 1 pW in the 24 bands, one wheel on one rail
    (24,)
    >>> round(noise.axle_dba - noise.sound_power_dba["total"], 2)   # dB(A): an axle is two wheels on two rails
    3.01
    >>> noise.train                                       # the pass-by's train: axles, m
    (40, 200.0)
    >>> noise.pass_by_laeq_dba < noise.axle_dba           # L_pAeq,Tp at 7.5 m, dB(A)
    True
    """
    from wheelrail.core.engine.results import result_of_run
    from wheelrail.core.files.run_file import check_fluctuating
    from wheelrail.core.noise.cnossos_run import cnossos_beside_run
    from wheelrail.core.noise.impact_noise import impact_noise, power_per_force
    from wheelrail.core.noise.twins import track_noise_model, with_modal_wheel
    from wheelrail.core.noise.wheel_power import checked_wheel_model
    from wheelrail.core.spectra.force import force_spectrum, spectrum_record

    result = result_of_run("run_noise: result", result)
    train_axles, train_length = checked_train(train_axles, train_length)
    _check_run_length(result)  # before the track's transfer functions (the costly part on a cold cache)
    check_fluctuating(result.force, spectrum_record(result).skipped_steps, f"the {result.model} run")  # else silence
    params = result.header.params
    numerics = _run_numerics(result) if numerics is None else numerics
    if checked_wheel_model(wheel_model) == "modal" and _own_modal_wheel(result, wheel_profile):
        from wheelrail.core.modal_wheel import profile_from_description

        # one wheel, track and contact: the run's force drives the modal wheel through its own W / F^2
        profile = profile_from_description(result.header.wheel_profile)
        track = track_noise_model(params, numerics, "modal", profile, contact_position)
    elif wheel_model == "modal":  # the force of another wheel: the modal wheel on its effective roughness
        track = track_noise_model(params, numerics, contact_position=contact_position)
        track = with_modal_wheel(track, params, wheel_profile, numerics, contact_position)
    else:
        track = track_noise_model(params, numerics, contact_position=contact_position)
    _, force_db = force_spectrum(result, band_range=NOISE_BAND_RANGE)
    force_db = np.asarray(force_db, dtype=float)
    power = sound_power_from_force(force_db, track)
    powers, powers_dba, axle_dba, roughness = power["db"], power["dba"], power["axle_dba"], power["roughness_db"]
    # |p/F|^2 at the closest distance, per band: rho c sum_c T_c / (2 pi d^2), T_c each component's W/N^2
    t_total = sum(power_per_force(track).values())
    d = receiver_distance()
    undefined = [float(f) for f, value in zip(noise_bands(), powers["total"], strict=True) if not np.isfinite(value)]
    configuration = _configuration(result, track, train_axles, train_length, undefined)
    return RunNoise(
        frequency_hz=noise_bands(),
        force_db=force_db,
        effective_roughness_db=roughness,
        sound_power_db=powers,
        sound_power_dba=powers_dba,
        axle_dba=axle_dba,
        pass_by_laeq_dba=pass_by_level(axle_dba, int(train_axles), float(train_length)),
        configuration=configuration,
        cnossos=cnossos_beside_run(result),
        impact=impact_noise(result, track, int(train_axles), float(train_length)),
        _force=np.asarray(result.force, dtype=float),
        _time_step=result.time_step,
        _pressure_per_force_sq=AIR_DENSITY * SOUND_SPEED * t_total / (2 * np.pi * d**2),
        _revolution_steps=_revolution_steps(result),
    )


def _run_numerics(result):
    """The noise chain's numerics of a run: the default's, with the elements per bay of the run's own track
    numerics (one track for the force and the transfer functions)."""
    from wheelrail.core.inputs.numerics import numerics_from_changes
    from wheelrail.core.noise.twins import chain_numerics

    return chain_numerics(numerics_from_changes(result.header.track_numerics))


def _revolution_steps(result) -> int:
    """Steps of one revolution of the wheel, 2 pi R / dx, on a run with a wheel flat; 0 without."""
    from wheelrail.core.irregularities.shapes import WheelFlat

    if not any(isinstance(item, WheelFlat) for item in result.header.params.run.irregularities):
        return 0
    return int(round(2 * math.pi * result.header.params.contact.radius_along / result.element_size))


def wheel_record(force: np.ndarray, revolution_steps: int) -> np.ndarray:
    """The dynamic force record each wheel of the pass-by plays, repeated: ``force`` as it is (0 steps: no flat),
    or, for a wheel with a flat, one revolution of it: a shorter record padded with zeros (no dynamic force) to
    ``revolution_steps``, a longer one cut to whole revolutions, so that the flat comes once per revolution."""
    if not revolution_steps:
        return force
    if len(force) < revolution_steps:
        return np.concatenate((force, np.zeros(revolution_steps - len(force))))
    return force[: (len(force) // revolution_steps) * revolution_steps]


def _own_modal_wheel(result, wheel_profile) -> bool:
    """Whether the run's force came from the modal wheel ``wheel_profile`` names (None: the run's own)."""
    from wheelrail.core.modal_wheel import profile_from_description

    own = result.header.wheel_profile
    if result.header.wheel_model != "modal" or own is None:
        return False
    return wheel_profile is None or wheel_profile == profile_from_description(own)


def _configuration(result, track, train_axles, train_length, undefined) -> dict:
    """What produced a run's noise (``RunNoise.configuration``)."""
    return {
        "run": {
            "model": result.model,
            "roughness": result.roughness_name,
            "line": result.line,
            "wheel_roughness": result.wheel_roughness_name,
            "wheel_model": result.header.wheel_model,  # the interaction's wheel ("2dof", "modal"), its force's
            **({"wheel_profile": result.header.wheel_profile} if result.header.wheel_profile is not None else {}),
            "speed_m_s": result.speed,
            "element_size_m": result.element_size,
            "track_numerics": dict(result.header.track_numerics),  # those that differ from the default
            **_irregularities(result),
        },
        "parameters": result.parameters,
        "train_axles": int(train_axles),
        "train_length_m": float(train_length),
        "receiver": {"distance_m": ISO3095_DISTANCE, "height_m": ISO3095_HEIGHT},
        "wheel_model": track.wheel_model,
        "wheel": track.configuration["wheel"],
        "contact_position": track.configuration["contact_position"],  # m: on the railhead, on the wheel's tread
        "track": {k: v for k, v in track.configuration.items() if k != "rail_section"},
        "sound_power_per": "one wheel on one rail (axle: +3 dB)",
        # bands the run's force spectrum does not resolve (narrower than 1 / T, or above v / (2 dx)): null, left out
        "undefined_bands_hz": undefined,
    }


def _irregularities(result) -> dict:
    """The run's discrete irregularities (records, SI) and what the Hertz models saw of them, or {} without."""
    run = result.header.params.run
    if not run.irregularities:
        return {}
    from wheelrail.core.irregularities.shapes import as_record

    return {
        "irregularities": [as_record(item) for item in run.irregularities],
        "irregularity_input": run.irregularity_input,
    }


def _check_run_length(result) -> None:
    """The run holds a force spectrum (:func:`wheelrail.core.spectra.force.shortest_spectrum_run`), else one
    WheelrailError that names no option (the noise has no length or skip of its own)."""
    from wheelrail.core.spectra.force import FORCE_MIN_STEPS, FORCE_SKIP, shortest_spectrum_run

    shortest = shortest_spectrum_run(result.speed, result.element_size)
    length = result.n_steps * result.element_size
    if length < shortest - 1e-9 * result.element_size:
        raise WheelrailError(
            f"the run is {length:.4g} m long ({result.n_steps} steps): too short for its sound power at "
            f"{result.speed * 3.6:.4g} km/h, whose force spectrum leaves out the first {FORCE_SKIP * 1e3:g} ms "
            f"(start-up) and needs {FORCE_MIN_STEPS} steps after them, at least {shortest:.4g} m; make a longer run"
        )


def checked_train(train_axles, train_length) -> tuple[int, float]:
    """(axles, length in m) of a train, or one WheelrailError: each within its accepted range
    (``ranges.ACCEPTED``: 1 to 2 000 axles, 2 m to 5 km) and the axles, evenly along the train, at least
    :data:`MIN_AXLE_SPACING` apart."""
    from wheelrail.core.inputs.ranges import ACCEPTED

    if isinstance(train_axles, bool) or not isinstance(train_axles, int | np.integer) or train_axles < 1:
        raise WheelrailError("not a whole number of at least 1", Blame("train_axles", train_axles))
    if isinstance(train_length, bool) or not (
        isinstance(train_length, int | float | np.floating) and math.isfinite(train_length) and train_length > 0
    ):
        raise WheelrailError("not a positive length", Blame("train_length", train_length, unit="m"))
    axles = int(ACCEPTED["train_axles"].check(int(train_axles)))
    length = ACCEPTED["train_length"].check(float(train_length))
    most = 1 + math.floor(length / MIN_AXLE_SPACING + 1e-9)
    if axles > most:
        raise WheelrailError(
            f"too many for a {length:g} m train",
            Blame(
                "train_axles",
                axles,
                maximum=most,
                reason=f"axles evenly along the train, at least {MIN_AXLE_SPACING:g} m apart",
            ),
        )
    return axles, length


def _synthesise(noise: RunNoise, *, lead: float, seed: int):
    """The pass-by pressure (module docstring)."""
    from scipy.signal import fftconvolve

    from wheelrail.core.spectra.force import FORCE_SKIP

    dt = noise._time_step
    rate = 1.0 / dt
    force = noise._force[int(round(FORCE_SKIP / dt)) :]
    force = force - force.mean()
    if len(force) < 64:
        raise WheelrailError("the run is too short to synthesise a pass-by (at least 64 steps after the start-up)")
    force = wheel_record(force, noise._revolution_steps)
    # zero-phase FIR: |H(f)| from the band values, 4096 taps (or the record's length), Hann-windowed
    taps = int(min(4096, 2 ** math.floor(math.log2(len(force)))))
    freqs = np.fft.rfftfreq(taps, dt)
    gain_db = _band_values_on(freqs, 10 * np.log10(noise._pressure_per_force_sq))
    gain = 10 ** (gain_db / 20)
    gain[freqs < noise.frequency_hz[0] / 2 ** (1 / 6)] = 0.0  # below the 50 Hz band: not modelled
    kernel = np.fft.fftshift(np.fft.irfft(gain, taps)) * np.hanning(taps)
    pressure_at_d = fftconvolve(force, kernel, mode="same")  # Pa at the closest distance, per axle
    cfg = noise.configuration
    speed = cfg["run"]["speed_m_s"]
    axles, length = cfg["train_axles"], cfg["train_length_m"]
    tp = length / speed
    n = int(round((tp + 2 * lead) / dt))
    t = np.arange(n) * dt - lead  # 0: the first axle at the microphone
    axle_offsets = np.linspace(0.0, length, axles)  # m behind the first axle
    d = receiver_distance()
    rng = np.random.default_rng(seed)
    out = np.zeros(n)
    record = len(pressure_at_d)
    for offset in axle_offsets:
        along = speed * t - offset  # m past the microphone
        for _wheel in range(2):  # the axle's two wheels on their two rails: independent stretches of the record
            start = int(rng.integers(record))
            idx = (start + np.arange(n)) % record
            out += pressure_at_d[idx] * d / np.hypot(d, along)
    first, last = int(round(lead / dt)), int(round((lead + tp) / dt))
    return out, rate, (first, last)


def laeq_of_pressure(pressure: np.ndarray, rate: float) -> float:
    """L_Aeq (dB(A) re 20 uPa) of a pressure signal (Pa): A-weighting applied in the frequency domain
    (:func:`~wheelrail.core.spectra.levels.a_weighted_energy`)."""
    return float(10 * np.log10(a_weighted_energy(pressure, rate) / len(pressure) / PRESSURE_REFERENCE**2))
