"""Print how the 3d model's contact filter on the bundled sets compares with the reference filters.

For each bundled set: ``3d`` and ``hertz`` on line 0, whole set, paper defaults (65 kN, R = 0.39 m,
100 km/h); contact filter L_3d - L_hertz (``wheelrail.core.study.contact_filter``) minus each reference
filter of ``wheelrail.core.reference_filters.reference_filters`` per frequency band, dB. Run:
``python3 validation/reference_filters_3d.py`` (a few minutes on a 2-core VM with a cold cache).
"""

from __future__ import annotations

import numpy as np

from wheelrail.core.engine import simulate
from wheelrail.core.parameters import ContactParameters, RunParameters
from wheelrail.core.reference_filters import REFERENCE_FILTERS, reference_filters
from wheelrail.core.roughness import bundled_names, load_roughness
from wheelrail.core.spectra.force import force_spectrum
from wheelrail.core.study import contact_filter


def main() -> None:
    contact, run = ContactParameters(), RunParameters()
    refs = reference_filters(contact.preload, contact.radius, run.speed)
    centres = refs.frequency_bands.centres
    labels = refs.frequency_bands.labels()
    for name in bundled_names():
        rough = load_roughness(name)
        centres_run, hertz = force_spectrum(simulate(rough, model="hertz"))
        _, three_d = force_spectrum(simulate(rough, model="3d"))
        np.testing.assert_allclose(centres_run, centres)
        measured = contact_filter(three_d, hertz)
        print(f"\n{name}: 3d contact filter (dB) and 3d minus each reference filter (dB)")
        print(f"{'band Hz':>8} {'3d':>7}" + "".join(f" {n:>17}" for n in REFERENCE_FILTERS))
        for i, label in enumerate(labels):
            cells = "".join(f" {measured[i] - refs.by_frequency[n][i]:>17.1f}" for n in REFERENCE_FILTERS)
            print(f"{label:>8} {measured[i]:>7.1f}{cells}")


if __name__ == "__main__":
    main()
