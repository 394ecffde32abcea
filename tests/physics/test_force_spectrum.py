"""Force spectrum (dB re 1 N, third-octave bands 50 Hz-8 kHz) against signals of known band power."""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.spectra.bands import third_octave_bands
from wheelrail.core.spectra.force import FORCE_SKIP, force_spectrum, resolved_force_bands, spectrum_record

DT = 1e-3 / (100 / 3.6)  # s: one 1 mm element at 100 km/h, the paper's step (36 µs)


@pytest.mark.parametrize("frequency", [63.0958, 501.187, 5011.87])  # exact centres of the 63, 500, 5k bands
def test_sine_lands_in_its_band_at_its_rms_level(frequency):
    amplitude = 1500.0  # N
    n = 16384  # 0.59 s: df = 1.7 Hz, >= 8 bins in the narrowest band (50 Hz: 11.5 Hz wide)
    t = np.arange(n) * DT
    force = 65e3 + amplitude * np.sin(2 * np.pi * frequency * t + 0.3)  # a tone on the 65 kN preload
    centres, levels = force_spectrum(force, DT)

    band = int(np.argmin(np.abs(centres - frequency)))
    expected = 20 * np.log10(amplitude / np.sqrt(2))  # the band holds the tone's mean square A²/2
    # 0.5 dB: the Hann main lobe (±2 bins = ±3.4 Hz) lies well inside the band and the sidelobes outside it
    # carry < 0.1 % of the power, and the power-conserving correction is exact for a tone over many
    # periods, so the real error is < 0.05 dB; 0.5 dB leaves room for the 63 Hz band's edge bins.
    assert levels[band] == pytest.approx(expected, abs=0.5)
    # The other bands hold only leakage: the Hann window's sidelobes (-31 dB, falling 18 dB/octave) put
    # them more than 20 dB down (measured: > 60 dB).
    others = np.delete(levels, band)
    assert np.all(others < expected - 20.0)


def test_start_up_transient_is_skipped():
    n = 4096  # 0.15 s: short enough that a transient in the first 20 ms is not hidden by the Hann window
    t = np.arange(n) * DT
    force = 65e3 + 1500.0 * np.sin(2 * np.pi * 1000.0 * t)
    start = t < FORCE_SKIP
    force[start] += 20e3 * np.exp(-t[start] / 5e-3) * np.cos(2 * np.pi * 90.0 * t[start])  # 90 Hz ring-down
    centres, skipped = force_spectrum(force, DT)
    _, kept = force_spectrum(force, DT, skip=0.0)
    low = centres < 400.0
    tone = 20 * np.log10(1500.0 / np.sqrt(2))
    # Measured: with the transient kept the 63-125 Hz bands reach 20-27 dB re 1 N; skipped, all bands below
    # 400 Hz stay below -35 dB (Hann leakage of the tone). The 40 dB margins are far from both.
    assert np.max(kept[low]) > tone - 40.0
    assert np.max(skipped[low]) < tone - 80.0
    assert skipped[np.argmin(np.abs(centres - 1000.0))] == pytest.approx(tone, abs=0.5)  # as the sine test


def test_white_noise_rises_one_db_per_band():
    rng = np.random.default_rng(7)
    sigma = 100.0  # N
    n = 2**18  # 9.4 s
    force = 65e3 + rng.normal(0.0, sigma, n)
    centres, levels = force_spectrum(force, DT, skip=0.0)
    _, lower, upper = third_octave_bands(50.0, 8000.0)

    # White noise: one-sided PSD 2 sigma² dt, so a band holds 2 sigma² dt (upper - lower), proportional
    # to its centre: +1 dB per third-octave band, 10 dB per decade.
    slope = np.polyfit(np.arange(len(levels)), levels, 1)[0]
    # 0.05 dB/band: each band level scatters by ~sqrt(1.5/bins) (Hann-correlated bins), i.e. 0.5 dB in
    # the 50 Hz band (100 bins) down to 0.04 dB at 8 kHz; over 23 bands the fitted slope errs < 0.02.
    assert slope == pytest.approx(1.0, abs=0.05)
    expected = 10 * np.log10(2 * sigma**2 * DT * (upper - lower))
    # 4 standard deviations of each band's estimate (see above), from the number of bins per band.
    bins = (upper - lower) * n * DT
    tolerance = 4 * 10 * np.log10(1 + np.sqrt(1.5 / bins))
    assert np.all(np.abs(levels - expected) < tolerance)


def test_run_result_and_array_give_the_same_spectrum():
    class Run:  # the attributes of RunResult that force_spectrum uses
        time_step = DT
        force = 65e3 + 500 * np.sin(2 * np.pi * 1000 * np.arange(4000) * DT)

    np.testing.assert_array_equal(force_spectrum(Run())[1], force_spectrum(Run.force, DT)[1])


@pytest.mark.parametrize("kmh", [5.0, 100.0, 400.0])
def test_the_shortest_run_with_a_spectrum_is_force_spectrums_own_rule(kmh):
    # spectra.force.shortest_spectrum_run (what the explorer offers, the studies and `wheelrail run` check) against
    # force_spectrum itself: a run of that length has a spectrum, one element less has none
    from wheelrail.core.spectra.force import check_spectrum_length, shortest_spectrum_run

    speed, dx = kmh / 3.6, 1e-3
    steps = round(shortest_spectrum_run(speed, dx) / dx)
    force_spectrum(np.ones(steps), dx / speed)
    with pytest.raises(WheelrailError):
        force_spectrum(np.ones(steps - 1), dx / speed)
    check_spectrum_length(steps * dx, speed, dx)
    with pytest.raises(WheelrailError, match="too short for a force spectrum") as info:
        check_spectrum_length((steps - 1) * dx, speed, dx)
    assert info.value.parameter == "length" and info.value.minimum == pytest.approx(steps * dx)


def test_too_short_run_and_bad_input_are_clear_errors():
    with pytest.raises(WheelrailError, match="leaves 0 steps after the skip, and a spectrum needs 16") as info:
        force_spectrum(np.ones(300), DT)  # 300 steps = 10.8 ms < 20 ms
    assert info.value.parameter == "skip" and info.value.maximum == pytest.approx((300 - 16) * DT)
    with pytest.raises(WheelrailError, match="time_step"):
        force_spectrum(np.ones(3000))
    with pytest.raises(WheelrailError, match="NaN"):
        force_spectrum(np.full(3000, np.nan), DT)
    with pytest.raises(WheelrailError, match="skip"):
        force_spectrum(np.ones(3000), DT, skip=-1.0)


@pytest.mark.parametrize(
    ("n_steps", "time_step"),
    [(572, DT), (600, DT), (1000, DT), (4096, DT), (30000, DT), (2000, 1e-4), (5000, 2e-4), (800, 5e-5)],
)
def test_resolved_bands_are_exactly_where_the_spectrum_has_a_level(n_steps, time_step):
    # resolved_force_bands predicts force_spectrum's NaN bands (narrower than 1 / T, or above Nyquist)
    # from the record's size alone; run files are checked against it, so it must agree band for band
    force = 65e3 + np.random.default_rng(n_steps).normal(0.0, 100.0, n_steps)
    centres, levels = force_spectrum(force, time_step)
    expected_centres, resolved = resolved_force_bands(n_steps, time_step)
    np.testing.assert_array_equal(centres, expected_centres)
    np.testing.assert_array_equal(np.isfinite(levels), resolved)
    assert resolved.any()


@pytest.mark.parametrize(
    ("n_steps", "time_step"),
    [(1000, DT), (572, DT), (1300, DT), (2000, DT), (4096, DT), (2000, 1e-4), (800, 5e-5), (700, 2e-4)],
)
def test_a_band_is_resolved_by_its_width_against_the_analysed_record(n_steps, time_step):
    # one rule: a band has a level when it is at least 1 / T wide, T the record left after the 20 ms skip,
    # and lies below the Nyquist frequency; so the resolved bands are contiguous (no n/a between two levels).
    # 1000 steps at 100 km/h is `run --model 3d --length-m 1`: 444 steps (16 ms) analysed, 1 / T = 62.5 Hz
    force = 65e3 + np.random.default_rng(n_steps).normal(0.0, 100.0, n_steps)
    centres, levels = force_spectrum(force, time_step)
    _, lower, upper = third_octave_bands(50.0, 8000.0)
    duration = (n_steps - int(np.ceil(FORCE_SKIP / time_step - 1e-9))) * time_step
    expected = (upper - lower >= 1.0 / duration * (1 - 1e-9)) & (upper <= 0.5 / time_step)
    np.testing.assert_array_equal(np.isfinite(levels), expected)
    finite = np.flatnonzero(np.isfinite(levels))
    assert finite.size and np.all(np.diff(finite) == 1)


def test_the_spectrum_record_says_what_was_skipped_and_analysed():
    force = 65e3 + np.random.default_rng(1).normal(0.0, 100.0, 1000)  # 1 m at 100 km/h
    record = spectrum_record(force, DT)
    assert record.skipped_steps == 556 and record.skip == pytest.approx(556 * DT)
    assert record.duration == pytest.approx(444 * DT) and record.resolution == pytest.approx(1 / (444 * DT))
    centres, levels = force_spectrum(force, DT)
    np.testing.assert_array_equal(record.resolved, np.isfinite(levels))
    assert record.band_labels[record.lowest_resolved()] == "315"
    summary = record.to_dict()
    assert summary["lowest_resolved_band_label"] == "315" and summary["analysed_duration_s"] == pytest.approx(444 * DT)
    assert summary["skip_s"] == pytest.approx(556 * DT)
    words = record.words()
    assert "20.02 ms" in words and "15.98 ms" in words and "315-8000 Hz" in words
    assert spectrum_record(force, DT, skip=0.0).skipped_steps == 0


def test_a_skip_beyond_any_record_is_refused_in_one_line_not_an_overflow():
    with pytest.raises(WheelrailError, match="skip"):
        force_spectrum(np.ones(3000), DT, skip=1e308)
    record = spectrum_record(np.ones(3000), DT, skip=1e308)
    assert record.analysed_steps == 0 and not record.resolved.any() and "no band resolved" in record.words()
