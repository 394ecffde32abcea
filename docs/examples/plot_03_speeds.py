"""
The force spectrum at four speeds (paper Fig. 11)
=================================================

The 2D model on line 0 of the corrugated rail at 75, 100, 140 and 200 km/h. The sleeper-passing peak moves
with v / L_S (L_S = 0.65 m: 43 Hz at 100 km/h); the roughness-excited part moves with v / lambda.
"""

import matplotlib.pyplot as plt

from wheelrail.core.engine import simulate
from wheelrail.core.parameters import ModelParameters, RunParameters
from wheelrail.core.spectra.force import force_spectrum

fig, ax = plt.subplots(figsize=(6, 3.6))
for kmh in (75, 100, 140, 200):
    params = ModelParameters(run=RunParameters(speed=kmh / 3.6))  # SI inside: m/s
    result = simulate("corrugated-rail", model="2d", line=0, length=2.0, params=params)
    centres, level = force_spectrum(result)
    ax.semilogx(centres, level, label=f"{kmh} km/h")
ax.set(xlabel="frequency (Hz)", ylabel="L_F (dB re 1 N)", title="2d model, corrugated rail, line 0")
ax.legend()
fig.tight_layout()
