"""The noise of an impact: an exposure level per impact, its repetition rate and the pass-by level from them.

A discrete irregularity (a wheel flat, a rail joint, a dipped weld, a squat) gives a transient force, not a
stationary one, so its noise is counted in energy per event and events per second:

- **force exposure** per band (N^2 s): the energy of the run's dynamic force F - mean(F) in each of the 24 bands,
  over the record after start-up (:data:`wheelrail.core.spectra.force.FORCE_SKIP`), from its Fourier transform
  (2 |X(f)|^2 integrated over the band's edges, X = dt FFT(F), zero-padded to a frequency step of at most
  :data:`FREQUENCY_STEP`), divided by the impacts the record holds (the flats' meetings with the rail and the
  rail irregularities within it; on a rough rail the rolling noise between them is counted with them);
- **sound energy** per impact of one wheel on one rail, per component and band: that force exposure times the
  component's sound power per unit mean-square force (W / N^2, the run's noise chain,
  :func:`power_per_force`); its A-weighted total is the **exposure level per impact** L_WAE (dB re 1 pJ), and one
  impact at the closest point to the ISO 3095 microphone gives the sound exposure level
  L_AE = L_WAE + 10 lg(rho c 1 pJ / (2 pi d^2 p0^2 1 s)) (dB re (20 uPa)^2 s; half-space spreading, as the
  pass-by);
- **repetition rate**: a flat meets the rail once per revolution, n = v / (2 pi R) per wheel (per flat); a rail
  irregularity is met once by every wheel that passes it;
- **pass-by level** L_pAeq,Tp of a train of N axles of length l from the impacts alone: flats, every wheel a
  source of mean power W = E n, so L_WA,axle = L_WAE + 10 lg(n / 1 Hz) + 3 dB and the pass-by formula of
  :func:`wheelrail.core.noise.pass_by.pass_by_level`; a rail irregularity opposite the microphone, 2 N wheel
  passings of exposure rho c E / (2 pi d^2) within T_p = l / v:
  L_pAeq,Tp = L_WAE + 10 lg(2 N / (T_p / 1 s)) + 10 lg(rho c 1 pJ / (2 pi d^2 p0^2 1 s)).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from wheelrail.core.errors import WheelrailError
from wheelrail.core.noise.components import TOTAL
from wheelrail.core.noise.pass_by import pass_by_level, receiver_distance
from wheelrail.core.noise.radiation import AIR_DENSITY, SOUND_SPEED
from wheelrail.core.spectra.bands import BAND_HALF_WIDTH, noise_bands
from wheelrail.core.spectra.levels import PRESSURE_REFERENCE, a_weighted_total, energy_sum

__all__ = [
    "FREQUENCY_STEP",
    "ImpactNoise",
    "force_band_exposure",
    "impact_events",
    "impact_noise",
    "power_per_force",
    "single_event_level",
]

FREQUENCY_STEP = 0.25  # Hz: the finest frequency step of the force exposure's transform (zero-padded to it)
ENERGY_REFERENCE = 1e-12  # J: sound energy levels in dB re 1 pJ
AXLE_DB = 10 * math.log10(2)  # two wheels on two rails, incoherent


def force_band_exposure(force, time_step: float, centres=None) -> np.ndarray:
    """The energy of ``force`` (N, sampled every ``time_step`` s) in each third-octave band, N^2 s.

    Its Fourier transform X = dt FFT(F) (zero-padded to a frequency step of at most :data:`FREQUENCY_STEP`),
    the one-sided density 2 |X(f)|^2 integrated (trapezoids) between each band's edges (``centres``: default the
    24 noise bands). The force is taken as given (subtract a mean first for its dynamic part); by Parseval the
    bands together hold at most sum F^2 dt.
    """
    force = np.asarray(force, dtype=float)
    centres = noise_bands() if centres is None else np.asarray(centres, dtype=float)
    n = max(force.size, 2 ** math.ceil(math.log2(1.0 / (time_step * FREQUENCY_STEP))))
    spectrum = time_step * np.fft.rfft(force, n)
    f = np.fft.rfftfreq(n, time_step)
    density = 2.0 * np.abs(spectrum) ** 2
    cumulative = np.concatenate(([0.0], np.cumsum(0.5 * (density[1:] + density[:-1]) * np.diff(f))))
    upper = np.interp(centres * BAND_HALF_WIDTH, f, cumulative, right=np.nan)
    lower = np.interp(centres / BAND_HALF_WIDTH, f, cumulative, right=np.nan)
    return upper - lower


def power_per_force(track) -> dict:
    """Each component's sound power per unit mean-square contact force of one wheel on one rail, W / N^2 per
    band (``track``: a :class:`wheelrail.core.noise.twins.TrackNoiseModel`): its own for a component driven by the
    force, else its transfer per axle on the effective roughness per unit force, one wheel of two."""
    out = {}
    for name, transfer in track.transfer_db.items():
        if name in track.power_per_force:
            out[name] = np.asarray(track.power_per_force[name], dtype=float)
        else:
            out[name] = 10 ** ((transfer - AXLE_DB + track.effective_roughness_per_force_db) / 10) * 1e-12
    return out


def single_event_level(distance: float) -> float:
    """10 lg(rho c 1 pJ / (2 pi d^2 p0^2 1 s)): a sound energy level (dB re 1 pJ) to the sound exposure level
    (dB re (20 uPa)^2 s) of the event at ``distance`` m, half-space spreading."""
    return 10 * math.log10(
        AIR_DENSITY * SOUND_SPEED * ENERGY_REFERENCE / (2 * math.pi * distance**2 * PRESSURE_REFERENCE**2)
    )


def impact_events(irregularities, wheel_radius: float, start: float, end: float) -> dict:
    """The impacts between positions ``start`` and ``end`` (m) of a run: ``{"flat": k, "rail": m}``, the flats'
    meetings with the rail (:func:`wheelrail.core.irregularities.shapes.flat_meetings`) and the rail
    irregularities (joints, welds, squats) whose position lies within."""
    from wheelrail.core.irregularities.shapes import WheelFlat, flat_meetings

    flats = rail = 0
    for item in irregularities:
        if isinstance(item, WheelFlat):
            flats += sum(start <= x <= end for x in flat_meetings(item, wheel_radius, end))
        elif start <= item.position <= end:
            rail += 1
    return {"flat": flats, "rail": rail}


@dataclass(frozen=True, kw_only=True)
class ImpactNoise:
    """The noise of a run's impacts (module docstring), one wheel on one rail.

    Attributes
    ----------
    events : dict
        Impacts in the record: ``flat`` (meetings of the flats) and ``rail`` (rail irregularities).
    force_exposure_db : numpy.ndarray
        Force exposure per impact per band, dB re 1 N^2 s.
    energy_db : dict
        Sound energy per impact per component and ``total`` per band, dB re 1 pJ.
    exposure_dba : float
        L_WAE: A-weighted sound energy level of one impact, dB(A) re 1 pJ.
    sel_dba : float
        L_AE of one impact at the closest point to the ISO 3095 microphone, dB(A) re (20 uPa)^2 s.
    flat_rate_hz : float or None
        Impacts per second per wheel of each flat, v / (2 pi R) (None without a flat).
    flats : int
        Flats on the wheel (each meets the rail at ``flat_rate_hz``).
    speed : float
        The run's speed, m/s.
    train : tuple
        Axles and length (m) of the train of ``pass_by_laeq_dba``.
    """

    events: dict
    force_exposure_db: np.ndarray
    energy_db: dict
    exposure_dba: float
    sel_dba: float
    flat_rate_hz: float | None
    flats: int
    speed: float
    train: tuple[int, float]

    @property
    def pass_by_laeq_dba(self) -> dict:
        """L_pAeq,Tp (dB(A)) of the train from the impacts alone (module docstring): ``flat`` (the wheels' flats
        at their rate) and ``rail`` (a rail irregularity opposite the microphone), each where the run has one."""
        axles, length = self.train
        passes = {}
        if self.flat_rate_hz is not None:
            axle = self.exposure_dba + 10 * math.log10(self.flat_rate_hz * self.flats) + AXLE_DB
            passes["flat"] = pass_by_level(axle, axles, length)
        if self.events["rail"]:
            tp = length / self.speed
            passes["rail"] = (
                self.exposure_dba + 10 * math.log10(2 * axles / tp) + single_event_level(receiver_distance())
            )
        return passes

    def with_train(self, axles: int, length: float) -> ImpactNoise:
        """The same impacts in a train of ``axles`` axles and ``length`` m."""
        return dataclasses.replace(self, train=(int(axles), float(length)))

    def to_dict(self) -> dict:
        """JSON-ready view (``impact`` of ``wheelrail noise --run --json``)."""
        return {
            "events_in_record": self.events,
            "force_exposure_dB_re_1N2s": self.force_exposure_db,
            "sound_energy_dB_re_1pJ": self.energy_db,
            "exposure_level_dBA_re_1pJ": self.exposure_dba,
            "sound_exposure_level_dBA": self.sel_dba,
            "flat_rate_per_s": self.flat_rate_hz,
            "rail_rate": "once per wheel passing" if self.events["rail"] else None,
            "pass_by_LpAeq_dBA": self.pass_by_laeq_dba,
            "per": "impact, one wheel on one rail",
        }

    def lines(self) -> list[str]:
        """What ``wheelrail noise --run`` prints for the impacts."""
        rates = []
        if self.flat_rate_hz is not None:
            rates.append(f"a flat {self.flat_rate_hz:.3g} per s per wheel (once per revolution, v / 2 pi R)")
        if self.events["rail"]:
            rates.append("a rail irregularity once per wheel passing")
        passes = ", ".join(f"{kind} {value:.1f}" for kind, value in self.pass_by_laeq_dba.items())
        return [
            f"  impact ({self.events['flat']} flat meeting(s), {self.events['rail']} rail irregularity(ies) in the "
            f"record): exposure level L_WAE {self.exposure_dba:.1f} dB(A) re 1 pJ per impact, one wheel; "
            f"L_AE {self.sel_dba:.1f} dB(A) at 7.5 m / 1.2 m",
            f"  impact rate: {'; '.join(rates)}; pass-by L_pAeq,Tp of the impacts alone: {passes} dB(A)",
        ]


def impact_noise(result, track, train_axles: int, train_length: float) -> ImpactNoise | None:
    """The noise of the impacts of ``result`` (a RunResult) through the components of ``track`` (its
    TrackNoiseModel), for a train of ``train_axles`` axles in ``train_length`` m (module docstring); None for a
    run whose record holds no irregularity."""
    from wheelrail.core.irregularities.shapes import WheelFlat
    from wheelrail.core.spectra.force import FORCE_SKIP

    run = result.header.params.run
    if not run.irregularities:
        return None
    dt, x = result.time_step, np.asarray(result.x, dtype=float)
    skip = int(round(FORCE_SKIP / dt))
    radius = result.header.params.contact.radius_along
    events = impact_events(run.irregularities, radius, float(x[skip]), float(x[-1]))
    count = events["flat"] + events["rail"]
    if count == 0:
        return None
    force = np.asarray(result.force, dtype=float)[skip:]
    exposure = force_band_exposure(force - force.mean(), dt) / count
    if not np.any(exposure > 0):
        raise WheelrailError("the run's force has no energy in the noise bands: no impact noise")
    with np.errstate(divide="ignore"):
        energy = {name: 10 * np.log10(t * exposure / ENERGY_REFERENCE) for name, t in power_per_force(track).items()}
    energy[TOTAL] = energy_sum(*energy.values())
    exposure_dba = a_weighted_total(np.where(np.isfinite(energy[TOTAL]), energy[TOTAL], -np.inf))
    flats = sum(isinstance(item, WheelFlat) for item in run.irregularities)
    with np.errstate(divide="ignore"):
        force_db = 10 * np.log10(exposure)
    return ImpactNoise(
        events=events,
        force_exposure_db=force_db,
        energy_db=energy,
        exposure_dba=float(exposure_dba),
        sel_dba=float(exposure_dba + single_event_level(receiver_distance())),
        flat_rate_hz=result.speed / (2 * math.pi * radius) if flats else None,
        flats=flats,
        speed=result.speed,
        train=(int(train_axles), float(train_length)),
    )
