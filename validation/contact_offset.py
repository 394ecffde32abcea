"""The contact's lateral position in the noise chain: a bundled run's component powers with the contact centred and
10 mm off, and the modal wheel's sound power per band with the contact 0 and +-10 mm along its tread.

A `hertz` run on the bundled `corrugated-rail` set (line 0, 100 km/h, 1.5 m) with the modal wheel (the 840 mm
wheel's shape at the paper's R = 390 mm), its noise with the modal wheel (``run_noise(..., wheel_model="modal")``)
for the contact at (railhead, tread) offsets (0, 0), (10, 0), (0, +10), (0, -10) and (10, +10) mm, on the noise
chain's default numerics (240 bays, 16 elements per bay, 20 points per band). Prints, per band, the force level and
each component's sound power (dB re 1 pW, one wheel on one rail) for each position, and the A-weighted totals.

Run: ``python3 validation/contact_offset.py`` (about 1.5 minutes on two shared cores: the positions share the
chain's parts, the track's vertical vibration once, the rail's lateral track once for the off-centre railhead
contacts, the modal wheel once per tread offset; 43, 21, 6, 6 and 0 s for the five positions at load 3-4).
"""

from __future__ import annotations

import time

import numpy as np

from wheelrail.core.engine import simulate
from wheelrail.core.inputs.contact_position import ContactPosition
from wheelrail.core.modal_wheel import wheel_profile_for
from wheelrail.core.noise.run_noise import run_noise
from wheelrail.core.parameters import ModelParameters
from wheelrail.core.spectra.bands import nominal_band_label

POSITIONS_MM = ((0.0, 0.0), (10.0, 0.0), (0.0, 10.0), (0.0, -10.0), (10.0, 10.0))


def modal_run():
    """The bundled run with the modal wheel (its header says so: the noise reads the wheel from it)."""
    profile = wheel_profile_for(ModelParameters().contact.radius)
    return simulate("corrugated-rail", model="hertz", line=0, length=1.5, wheel_system=profile)


def main() -> None:
    start = time.perf_counter()
    result = modal_run()
    print(f"run: {result.header.wheel_words()}, {result.n_steps} steps ({time.perf_counter() - start:.0f} s)")
    noises = {}
    for rail_mm, wheel_mm in POSITIONS_MM:
        position = ContactPosition(rail_offset=rail_mm * 1e-3, wheel_offset=wheel_mm * 1e-3)
        began = time.perf_counter()
        noises[rail_mm, wheel_mm] = run_noise(result, wheel_model="modal", contact_position=position)
        print(f"  {position.words()}: {time.perf_counter() - began:.0f} s", flush=True)
    first = noises[POSITIONS_MM[0]]
    names = [name for name in first.sound_power_db if name != "total"]
    print("\nsound power of one wheel on one rail, dB re 1 pW, per (railhead, tread) offset in mm")
    for name in (*names, "total"):
        print(f"\n{name}")
        print("  band Hz  force dB " + " ".join(f"{f'({r:g}, {w:g})':>11}" for r, w in POSITIONS_MM))
        for i, f in enumerate(first.frequency_hz):
            cells = " ".join(f"{noises[p].sound_power_db[name][i]:11.1f}" for p in POSITIONS_MM)
            print(f"  {nominal_band_label(f):>7} {first.force_db[i]:8.1f} {cells}")
    print("\nA-weighted, dB(A) re 1 pW per wheel")
    for position in POSITIONS_MM:
        dba = noises[position].sound_power_dba
        print(f"  {position}: " + ", ".join(f"{k} {v:.1f}" for k, v in dba.items()))
    wheel = {p: noises[p].sound_power_db["wheel"] for p in POSITIONS_MM}
    change = {p: wheel[p] - wheel[0.0, 0.0] for p in POSITIONS_MM}
    for p in ((0.0, 10.0), (0.0, -10.0)):
        finite = np.isfinite(change[p])
        print(f"  the wheel at tread offset {p[1]:+g} mm, per band against 0: {change[p][finite].min():+.1f} to "
              f"{change[p][finite].max():+.1f} dB")  # fmt: skip


if __name__ == "__main__":
    main()
