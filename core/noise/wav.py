"""The pass-by WAV written block by block: memory bounded by a block, not by the pass-by's length.

The pass-by pressure is synthesised at the run's own rate (v / dx: a few MB however long the train, at most
(train length + 2 v lead) / dx samples), then resampled to 48 kHz (``scipy.signal.resample_poly``) one block of
:data:`BLOCK_SAMPLES` output samples at a time, each from the stretch of the record it needs (the filter's
half-length either side), so the blocks join into what one call on the whole record gives. Two passes: the
first finds the peak and the A-weighted energy over T_p (``spectra.levels.a_weighted_energy`` per block of at most
:data:`BLOCK_SAMPLES`; a T_p of one block is weighted whole, exactly as ``laeq_of_pressure``), which set the
calibration (``RunNoise.calibrated_pass_by``, to ``RunNoise.wav_level_dba``); the second scales each block to 16-bit
PCM and writes it.

A wheel with a flat is heard once per revolution: its record is made one revolution (2 pi R / v) long before
the wheels' stretches are cut from it (``run_noise.wheel_record``): a run shorter than a revolution is padded with
its mean force (the rest of the revolution holds no dynamic force), a longer one is cut to whole revolutions; the
WAV is then calibrated to the impacts' pass-by level (``RunNoise.wav_level_dba``, ``RunNoise.wav_fill``).

A WAV lasts at most :data:`MAX_WAV_S` (:func:`check_wav_duration`): a 5 km train at 5 km/h is an hour (346 MB
at 48 kHz), written in minutes, for a pass-by level that needs no WAV at all. Its synthesis adds one stretch of the
record per wheel over the whole pass-by at the run's rate, :data:`SYNTHESIS_NS` a sample, so it sums at most
:data:`MAX_WHEEL_SAMPLES` (:func:`check_wav_work`): 2 000 axles past a 5 km train at 100 km/h would be 2e10 samples,
tens of minutes of synthesis before the first word.
"""

from __future__ import annotations

import math
import struct
from collections.abc import Iterator
from fractions import Fraction

import numpy as np

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.spectra.levels import PRESSURE_REFERENCE, a_weighted_energy

__all__ = [
    "BLOCK_SAMPLES",
    "MAX_WAV_S",
    "MAX_WHEEL_SAMPLES",
    "SYNTHESIS_NS",
    "check_wav_duration",
    "check_wav_work",
    "wav_duration",
    "write_wav",
]

BLOCK_SAMPLES = 1 << 21  # output samples per block: 44 s at 48 kHz, about 120 MB of working arrays
MAX_WAV_S = 600.0  # s: the longest pass-by written as a WAV (57.6 MB at 48 kHz, 16 bit)
_BYTES_PER_SAMPLE = 2  # 16-bit PCM, one channel
SYNTHESIS_NS = 64.0  # ns per sample per wheel of the synthesis's sum, measured on a 2-core development machine
MAX_WHEEL_SAMPLES = 2e9  # samples summed over the wheels: about 2 min at SYNTHESIS_NS


def wav_duration(train_length: float, speed: float, lead: float) -> float:
    """Seconds of a pass-by WAV: T_p = ``train_length`` / ``speed`` and ``lead`` s before and after."""
    return train_length / speed + 2.0 * lead


def check_wav_duration(train_length: float, speed: float, lead: float, rate: float) -> float:
    """The pass-by's duration (s), or one WheelrailError when it is over :data:`MAX_WAV_S`, saying how long it
    would be, how large, and the longest train at this speed that fits."""
    duration = wav_duration(train_length, speed, lead)
    if duration > MAX_WAV_S:
        longest = (MAX_WAV_S - 2.0 * lead) * speed
        raise WheelrailError(
            f"a WAV of this pass-by would last {duration:.0f} s ({train_length:g} m at {speed * 3.6:g} km/h and "
            f"{lead:g} s before and after; {duration * rate * _BYTES_PER_SAMPLE / 1e6:.0f} MB): at most "
            f"{MAX_WAV_S:g} s are written; give a train of at most {math.floor(longest):g} m at this speed for the "
            "WAV (the pass-by level itself needs no WAV)",
            Blame("train_length", train_length, unit="m"),
        )
    return duration


def check_wav_work(axles: int, train_length: float, speed: float, time_step: float, lead: float) -> float:
    """The samples the pass-by's synthesis sums (two wheels an axle, each over the pass-by at the run's step
    ``time_step``), or one WheelrailError over :data:`MAX_WHEEL_SAMPLES`, saying the estimated time and the most
    axles that fit."""
    samples = wav_duration(train_length, speed, lead) / time_step
    work = 2 * axles * samples
    if work > MAX_WHEEL_SAMPLES:
        most = max(1, math.floor(MAX_WHEEL_SAMPLES / (2 * samples)))
        raise WheelrailError(
            f"a WAV of this pass-by sums {2 * axles} wheels' records of {samples / 1e6:.2g} million samples each "
            f"({work:.2g} samples, about {work * SYNTHESIS_NS * 1e-9 / 60:.0f} min): at most {MAX_WHEEL_SAMPLES:.0e} "
            f"are summed; give at most {most} axles or a shorter train for the WAV (the pass-by level itself needs "
            "no WAV)",
            Blame("train_axles", axles),
        )
    return work


def _resampled(pressure: np.ndarray, up: int, down: int, block: int) -> Iterator[tuple[int, np.ndarray]]:
    """(first output index, samples) of ``resample_poly(pressure, up, down)``, ``block`` samples at a time, each
    from the stretch of ``pressure`` it needs (block starts at multiples of ``down`` input samples, so the
    output grid is the whole call's)."""
    from scipy.signal import resample_poly

    total = -(-len(pressure) * up // down)
    pad = -(-10 * max(up, down) // up) + 2  # the default filter's half-length, in input samples
    step = max(1, block // up) * down  # input samples per block: a multiple of down
    for start in range(0, len(pressure), step):
        low = max(0, start - pad)
        low -= low % down
        stretch = resample_poly(pressure[low : min(len(pressure), start + step + pad)], up, down)
        first = start * up // down
        skip = (start - low) * up // down
        yield first, stretch[skip : skip + min(step * up // down, total - first)]


def _calibration(noise, pressure, ratio, span, rate) -> tuple[float, float]:
    """(peak Pa, correction dB) of the resampled pass-by: the correction sets its L_pAeq over T_p (``span``,
    the 48 kHz samples) to the pass-by level, as ``RunNoise.calibrated_pass_by`` does."""
    first, last = span
    peak, energy, segment_length = 0.0, 0.0, 0
    pending, buffered = [], 0  # T_p's samples not yet weighted: at most two blocks
    for start, samples in _resampled(pressure, ratio.numerator, ratio.denominator, BLOCK_SAMPLES):
        peak = max(peak, float(np.max(np.abs(samples)))) if samples.size else peak
        inside = samples[max(0, first - start) : max(0, last - start)]
        pending.append(inside)
        buffered += inside.size
        while buffered > BLOCK_SAMPLES:  # a T_p of one block is weighted whole, below
            joined = np.concatenate(pending)
            energy += a_weighted_energy(joined[:BLOCK_SAMPLES], rate)
            pending, buffered, segment_length = (
                [joined[BLOCK_SAMPLES:]],
                buffered - BLOCK_SAMPLES,
                segment_length + BLOCK_SAMPLES,
            )
    if buffered:
        energy += a_weighted_energy(np.concatenate(pending), rate)
        segment_length += buffered
    correction = 0.0
    if math.isfinite(noise.wav_level_dba) and segment_length > 1 and energy > 0:
        level = 10 * math.log10(energy / segment_length / PRESSURE_REFERENCE**2)
        correction = noise.wav_level_dba - level
    return peak, correction


def write_wav(noise, handle, *, lead: float = 1.0, seed: int = 0, rate: int = 48_000) -> float:
    """Write the pass-by of ``noise`` (a ``RunNoise``) to ``handle`` as a 16-bit PCM WAV at ``rate`` Hz, block
    by block (module docstring); returns its calibration, Pa at full scale (peak at half of full scale)."""
    cfg = noise.configuration
    check_wav_duration(cfg["train_length_m"], cfg["run"]["speed_m_s"], lead, rate)
    check_wav_work(cfg["train_axles"], cfg["train_length_m"], cfg["run"]["speed_m_s"], noise._time_step, lead)
    pressure, own_rate, (first, last) = noise.pass_by_pressure(lead=lead, seed=seed)
    ratio = Fraction(rate / own_rate).limit_denominator(2000)
    total = -(-len(pressure) * ratio.numerator // ratio.denominator)
    span = (int(round(first * ratio)), min(total, int(round(last * ratio))))
    peak, correction = _calibration(noise, pressure, ratio, span, float(rate))
    full_scale = 2.0 * peak * 10 ** (correction / 20)
    size = total * _BYTES_PER_SAMPLE
    handle.write(b"RIFF" + struct.pack("<I", 36 + size) + b"WAVE")
    handle.write(b"fmt " + struct.pack("<IHHIIHH", 16, 1, 1, rate, rate * _BYTES_PER_SAMPLE, _BYTES_PER_SAMPLE, 16))
    handle.write(b"data" + struct.pack("<I", size))
    scale = 10 ** (correction / 20) / full_scale * 32767 if full_scale > 0 else 0.0
    for _, samples in _resampled(pressure, ratio.numerator, ratio.denominator, BLOCK_SAMPLES):
        handle.write(np.round(samples * scale).astype("<i2").tobytes())
    return full_scale
