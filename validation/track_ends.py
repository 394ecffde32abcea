"""End reflections of the interaction's finite track: its point receptance against a 4x longer track.

The interaction's track (``TrackParameters.n_bays``: 70 bays, free ends) must behave as an infinite one where
the wheel is: waves reflected at its ends must come back attenuated by the track's own decay. This prints, for
the paper's track, soft (60 MN/m) and stiff (1000 MN/m, the lowest decay above the pinned-pinned frequency)
pads and the ends of the accepted range (10 and 3000 MN/m), undamped or with a rail loss factor of 0.02, the
band-mean point receptance level (20 frequencies per one-third octave band, 100 Hz-5 kHz) above the central
sleeper and at midspan of the 70-bay track minus that of a 280-bay track, the largest difference, and the
20-bay track's for scale. Frequency domain, the same FE mesh as the Green's functions outside their refined
bays (16 elements per bay).

Run: ``python3 validation/track_ends.py``.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from wheelrail.core.noise.twins import band_frequencies
from wheelrail.core.parameters import RailParameters, SupportParameters, TrackParameters
from wheelrail.core.track import assemble_track, track_receptance

TRACKS = {
    "paper (120 MN/m)": TrackParameters(),
    "soft pads 60 MN/m": TrackParameters(support=SupportParameters(pad_stiffness=60e6)),
    "stiff pads 1000 MN/m": TrackParameters(support=SupportParameters(pad_stiffness=1000e6)),
    "stiff pads 1000 MN/m, eta 0.02": TrackParameters(
        rail=RailParameters(loss_factor=0.02), support=SupportParameters(pad_stiffness=1000e6)
    ),
    # the ends of the accepted range (wheelrail.core.inputs.ranges.ACCEPTED["pad_stiffness"])
    "softest accepted pads 10 MN/m": TrackParameters(support=SupportParameters(pad_stiffness=10e6)),
    "stiffest accepted pads 3000 MN/m": TrackParameters(support=SupportParameters(pad_stiffness=3000e6)),
}


def band_levels(track: TrackParameters, n_bays: int) -> np.ndarray:
    """10 lg of the band-mean |alpha|^2 above the central sleeper and at midspan, (bands, 2)."""
    track = replace(track, n_bays=n_bays)
    model = assemble_track(track, 16)
    spacing = track.support.sleeper_spacing
    x = (n_bays // 2) * spacing
    freqs = band_frequencies(20)
    centres = freqs[:, 10]
    keep = (centres > 90) & (centres < 5100)
    out = []
    for row in freqs[keep]:
        above = track_receptance(model, row, x)
        mid = track_receptance(model, row, x + spacing / 2)
        out.append([10 * np.log10(np.mean(np.abs(a) ** 2)) for a in (above, mid)])
    return np.array(out)


def main() -> None:
    centres = band_frequencies(20)
    centres = np.sqrt(centres[:, 0] * centres[:, -1])
    centres = centres[(centres > 90) & (centres < 5100)]
    for name, track in TRACKS.items():
        long = band_levels(track, 280)
        print(f"\n{name}: band level minus the 280-bay track's (dB), above a sleeper / at midspan")
        for bays in (20, 70):
            diff = band_levels(track, bays) - long
            worst = np.unravel_index(np.argmax(np.abs(diff)), diff.shape)
            print(
                f"  {bays:3d} bays: max |d| {np.max(np.abs(diff)):.2f} dB at {centres[worst[0]]:.0f} Hz "
                f"({'above a sleeper' if worst[1] == 0 else 'midspan'})"
            )
            if bays == 70:
                print("   " + " ".join(f"{c:6.0f}" for c in centres))
                print("   " + " ".join(f"{d:+6.2f}" for d in diff[:, 0]))
                print("   " + " ".join(f"{d:+6.2f}" for d in diff[:, 1]))


if __name__ == "__main__":
    main()
