"""Print the rolling-noise figures of the README section "Rolling noise" and their timings.

1. CNOSSOS-EU: the two wavelength-to-frequency rules compared (max per band, dB(A)) at 50-300 km/h.
2. The model track as a TWINS-like transfer function beside CNOSSOS-EU's L_H,tr (every track type), decay rates
   and the rail's radiation efficiency.
3. Runs: `hertz` and `3d` on a bundled set (line 0, whole set, 100 km/h): sound power per component, L_WA, the
   pass-by level, the WAV's own L_pAeq, CNOSSOS-EU beside them, and 3d - hertz per band (where the contact filter
   acts).
4. Timings (best and range of ``--repeats``; the machine may be shared): the CNOSSOS source, the track noise
   model (a fresh computation, the BEM table cached), run_noise, the WAV synthesis.
5. Convergence of the track noise model (bays, elements, frequencies per band doubled) and of the sigma table.

Run: ``python3 validation/noise.py [--set corrugated-rail] [--repeats 3] [--wav-dir DIR]``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from wheelrail.core.engine import simulate
from wheelrail.core.noise.cnossos import TRACK_TYPES, cnossos_rolling_noise, interpolation_difference, track_transfer
from wheelrail.core.noise.run_noise import laeq_of_pressure, run_noise
from wheelrail.core.noise.tables import NOMINAL_FREQUENCIES_HZ
from wheelrail.core.noise.twins import clear_chain_caches, track_noise_model


def _timed(function, repeats: int) -> tuple[float, float, object]:
    times, value = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        value = function()
        times.append(time.perf_counter() - start)
    return min(times), max(times), value


def cnossos_rules() -> None:
    print(
        "1. CNOSSOS-EU: energy-log-frequency minus proportional (network-average rail, cast-iron wheel, "
        "mono-block-medium, 920 mm, 65 kN)"
    )
    print(f"{'km/h':>6} {'max |band| dB':>14} {'band Hz':>8} {'total dB(A)':>12}")
    for v in (50, 100, 160, 200, 300):
        per_band, total = interpolation_difference(v / 3.6, rail="network-average", wheel="cast-iron", load=65e3)
        i = int(np.nanargmax(np.abs(per_band)))
        print(f"{v:>6} {per_band[i]:>14.2f} {NOMINAL_FREQUENCIES_HZ[i]:>8g} {total:>12.2f}")


def track_model() -> None:
    model = track_noise_model()
    print("\n2. Model track (TWINS-like) vs CNOSSOS-EU L_H,tr, dB re 1 pW per axle for 0 dB re 1 um")
    names = [n for n in TRACK_TYPES if n != "direct-fastening"]
    print(
        f"{'band':>6} {'model':>6} "
        + " ".join(f"{n[:14]:>14}" for n in names)
        + f" {'DR EN15461':>10} {'free wave':>9} {'sigma':>6}"
    )
    for i, f in enumerate(NOMINAL_FREQUENCIES_HZ):
        print(
            f"{f:>6g} {model.track_transfer_db[i]:>6.1f} "
            + " ".join(f"{track_transfer(n)[i]:>14.1f}" for n in names)
            + f" {model.decay_rate_db_per_m[i]:>10.2f} {model.free_wave_decay_db_per_m[i]:>9.2f}"
            + f" {model.rail_radiation_efficiency[i]:>6.2f}"
        )
    for n in names:
        diff = model.track_transfer_db - track_transfer(n)
        print(
            f"  model - {n}: mean {np.mean(diff):+.1f} dB, 500 Hz-5 kHz mean {np.mean(diff[10:21]):+.1f} dB, "
            f"range {np.min(diff):+.1f}..{np.max(diff):+.1f} dB"
        )


def runs(set_name: str, wav_dir: Path | None) -> None:
    print(f"\n3. Runs on {set_name}, line 0, 100 km/h, whole set")
    results = {}
    for model in ("hertz", "3d"):
        noise = run_noise(simulate(set_name, model=model, line=0))
        p, rate, (a, b) = noise.pass_by_pressure()
        wav_level = laeq_of_pressure(p[a:b], rate)
        results[model] = noise
        print(
            f"  {model:>5}: L_WA per wheel "
            + ", ".join(f"{k} {v:.1f}" for k, v in noise.sound_power_dba.items())
            + f" dB(A); pass-by {noise.pass_by_laeq_dba:.1f} dB(A), synthesised WAV {wav_level:.1f} dB(A)"
        )
        if wav_dir is not None:
            data, full_scale = noise.wav_bytes()
            path = wav_dir / f"pass-by-{set_name}-{model}-100kmh.wav"
            path.write_bytes(data)
            print(f"         wrote {path} (full scale {full_scale:.3g} Pa)")
    beside = results["3d"]
    print(
        f"  CNOSSOS-EU beside them (the run's roughness, A3, {beside.cnossos.configuration['track_type']}, "
        f"{beside.cnossos.configuration['wheel_diameter_m'] * 1e3:g} mm): L_WA per axle track "
        f"{beside.cnossos.track_dba:.1f}, vehicle {beside.cnossos.vehicle_dba:.1f}, "
        f"total {beside.cnossos.total_dba:.1f} dB(A) (models per axle: hertz {results['hertz'].axle_dba:.1f}, "
        f"3d {beside.axle_dba:.1f}); pass-by "
        f"{beside.cnossos_pass_by_dba():.1f} dB(A)"
    )
    diff = results["3d"].sound_power_db["total"] - results["hertz"].sound_power_db["total"]
    print(
        "  3d - hertz, total sound power per band (dB): "
        + ", ".join(f"{f:g} {d:+.1f}" for f, d in zip(NOMINAL_FREQUENCIES_HZ, diff, strict=True))
    )


def convergence() -> None:
    """The track noise model's numerics doubled one at a time, and the rail's sigma table against direct BEM."""
    from wheelrail.core.noise.radiation import (
        UIC60_CHIEF_POINTS,
        rail_boundary,
        rail_radiation_efficiency,
        vertical_radiation_efficiency,
    )
    from wheelrail.core.noise.twins import NoiseNumerics, band_frequencies

    print(
        "\n5. Convergence: L_H,tr (dB) with one numerical setting doubled, minus the default (240 bays, 16 elements "
        "per bay, 20 frequencies per band); max |difference| over 50 Hz-10 kHz and over 100 Hz-5 kHz"
    )
    base = track_noise_model()
    for label, numerics in (
        ("480 bays", NoiseNumerics(track_bays=480)),
        ("32 elements per bay", NoiseNumerics(elements_per_bay=32)),
        ("40 frequencies per band", NoiseNumerics(points_per_band=40)),
    ):
        diff = track_noise_model(numerics=numerics).track_transfer_db - base.track_transfer_db
        f = np.asarray(NOMINAL_FREQUENCIES_HZ)
        mid = (f >= 100) & (f <= 5000)
        print(
            f"  {label:>24}: {np.max(np.abs(diff)):.2f} dB, {np.max(np.abs(diff[mid])):.2f} dB "
            f"(worst band {NOMINAL_FREQUENCIES_HZ[int(np.argmax(np.abs(diff)))]:g} Hz)"
        )
    freqs = band_frequencies(10)
    direct = np.array(
        [[vertical_radiation_efficiency(rail_boundary(f), f, UIC60_CHIEF_POINTS)[0] for f in row] for row in freqs]
    )
    table = rail_radiation_efficiency(freqs)
    diff = 10 * np.log10(direct.mean(axis=1) / table.mean(axis=1))
    print(
        f"  rail sigma, band means from the cached table vs direct BEM at 10 frequencies per band: max "
        f"{np.max(np.abs(diff)):.2f} dB (band {NOMINAL_FREQUENCIES_HZ[int(np.argmax(np.abs(diff)))]:g} Hz)"
    )


def timings(repeats: int, set_name: str) -> None:
    print(f"\n4. Timings (s), best and range of {repeats}")
    best, worst, _ = _timed(lambda: cnossos_rolling_noise(100 / 3.6), repeats)
    print(f"  CNOSSOS-EU source, one call: {best:.4f} ({best:.4f}-{worst:.4f})")

    def fresh():
        clear_chain_caches()
        return track_noise_model()

    best, worst, _ = _timed(fresh, repeats)
    print(f"  track noise model (240 bays, 480 frequencies x 2 positions): {best:.2f} ({best:.2f}-{worst:.2f})")
    result = simulate(set_name, model="hertz", line=0)
    best, worst, noise = _timed(lambda: run_noise(result), repeats)
    print(f"  run_noise (track model cached): {best:.3f} ({best:.3f}-{worst:.3f})")
    best, worst, _ = _timed(lambda: noise.wav_bytes(), repeats)
    print(f"  WAV synthesis (40 axles, 200 m at 100 km/h, 9.2 s of sound): {best:.2f} ({best:.2f}-{worst:.2f})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", default="corrugated-rail")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--wav-dir", type=Path, default=None)
    args = parser.parse_args()
    cnossos_rules()
    track_model()
    runs(args.set, args.wav_dir)
    timings(args.repeats, args.set)
    convergence()


if __name__ == "__main__":
    main()
