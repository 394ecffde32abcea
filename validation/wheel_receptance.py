"""The modal wheel's receptance at the contact converged: band levels against a mesh twice as fine and twice the
harmonics, and what the static residual the receptance leaves out (the contact zone's local flexibility) does.

1. Per harmonic n, the static flexibility at the contact node G_n, the share of it the modes below the maximum
   frequency carry, and the rest (the residual), radial, for 12 and 6 mm elements: the residual is the same in
   every harmonic and grows as the mesh is refined (the local field of a point load), the modes' share does not.
2. The radial receptance at 100 Hz with and without that residual, for 12, 6 and 3 mm elements and 10, 20 and 40
   harmonics.
3. The band means of |alpha|^2 (``receptance.band_mean_square``, each resonance resolved) for the radial point,
   axial point and cross receptances, the noise chain's bands 50 Hz-10 kHz and maximum frequency (12.5 kHz),
   against half the element size and twice the harmonics, in dB re 1 m^2/N^2.

Wheels: the 920 mm freight wheel and the noise chain's default (the 840 mm wheel at the paper's R = 390 mm).
``--fine`` adds the 3 mm mesh to part 3 (minutes).

    python3 validation/wheel_receptance.py [--fine]
"""

from __future__ import annotations

import sys
import time

import numpy as np

from wheelrail.core.modal_wheel import contact_receptance, named_profile, wheel_modes, wheel_profile_for
from wheelrail.core.modal_wheel.receptance import band_mean_square, static_residual
from wheelrail.core.spectra.bands import BAND_HALF_WIDTH, noise_bands

MAX_FREQUENCY = 12.5e3  # Hz: the noise chain's (wheel_power.MAX_FREQUENCY)
HARMONICS = 20  # every harmonic with a mode below 12.5 kHz (n <= 16 for the 920 mm wheel) and some above
WHEELS = {"freight_920": named_profile("freight_920"), "840 mm at R = 390 mm": wheel_profile_for(0.39)}


def _modes(profile, size, harmonics):
    return wheel_modes(profile, max_frequency=MAX_FREQUENCY, max_harmonic=harmonics, element_size=size)


def per_harmonic(profile) -> None:
    print("1. per harmonic, radial, m/N: G_n (static at the contact node), the modes' share, the residual")
    coarse, fine = _modes(profile, 0.012, HARMONICS), _modes(profile, 0.006, HARMONICS)
    print("   n   G_n 12 mm   modes 12 mm  residual 12 mm | modes 6 mm  residual 6 mm")
    for n in range(HARMONICS + 1):
        row = []
        for modes in (coarse, fine):
            mine = (modes.harmonic == n) & (modes.frequency > 1.0)
            share = np.sum(modes.contact_shapes()[mine, 0] ** 2 / (2 * np.pi * modes.frequency[mine]) ** 2)
            row.append((modes.static[n, 0, 0], share, modes.static[n, 0, 0] - share))
        (g, s, r), (_, s6, r6) = row
        print(f"  {n:2d}  {g:10.3e}  {s:10.3e}  {r:10.3e}     | {s6:10.3e}  {r6:10.3e}")


def at_100_hz(profile) -> None:
    print("2. radial receptance at 100 Hz, m/N: with the residual (as before) and without (the receptance now)")
    for size in (0.012, 0.006, 0.003):
        for harmonics in (10, 20, 40):
            if size == 0.003 and harmonics > 10:
                continue  # beyond the work limit
            modes = _modes(profile, size, harmonics)
            alpha = contact_receptance(modes, [100.0]).radial[0]
            with_residual = alpha + static_residual(modes)[0, 0]
            print(
                f"   {size * 1e3:4.0f} mm, n <= {harmonics:2d}: with {abs(with_residual):.3e}  without {abs(alpha):.3e}"
            )


def bands(profile, fine: bool) -> None:
    centres = noise_bands()
    lower, upper = centres / BAND_HALF_WIDTH, centres * BAND_HALF_WIDTH
    settings = {"12 mm, n <= 20": (0.012, HARMONICS), "6 mm": (0.006, HARMONICS), "n <= 40": (0.012, 2 * HARMONICS)}
    if fine:
        settings["3 mm"] = (0.003, HARMONICS)
    levels = {}
    for name, (size, harmonics) in settings.items():
        start = time.perf_counter()
        means = band_mean_square(_modes(profile, size, harmonics), lower, upper)
        levels[name] = {d: 10 * np.log10(getattr(means, d)) for d in ("radial", "axial", "cross")}
        print(f"   ({name}: {time.perf_counter() - start:.0f} s)")
    names = list(settings)
    print("3. band means of |alpha|^2, dB re 1 m^2/N^2 (12 mm, n <= 20), and the change with each other setting")
    print("   band Hz | " + " | ".join(f"{d:^{8 + 7 * (len(names) - 1)}s}" for d in ("radial", "axial", "cross")))
    for b, centre in enumerate(centres):
        cells = []
        for d in ("radial", "axial", "cross"):
            base = levels[names[0]][d][b]
            cells.append(f"{base:7.1f} " + " ".join(f"{levels[n][d][b] - base:+6.2f}" for n in names[1:]))
        print(f"   {centre:7.0f} | " + " | ".join(cells))
    for n in names[1:]:
        worst = {d: np.max(np.abs(levels[n][d] - levels[names[0]][d])) for d in ("radial", "axial", "cross")}
        print(f"   largest change, {n}: " + ", ".join(f"{d} {w:.2f} dB" for d, w in worst.items()))


def main() -> None:
    fine = "--fine" in sys.argv[1:]
    for name, profile in WHEELS.items():
        print(f"== {name}")
        if name == "freight_920":
            per_harmonic(profile)
            at_100_hz(profile)
        bands(profile, fine)


if __name__ == "__main__":
    main()
