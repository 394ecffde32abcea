"""
Wheel and rail roughness together
=================================

A rough wheel on a rough rail: the corrugated rail with the sinter wheel 1 on it. The wheel set is one
circumference (2.900 m), so the wheel's rolling radius is set to match it (461.5 mm); its lines are paired
with the rail's by lateral position and repeat along the track. For roughness this small the force
spectrum of the combined run is close to the energy sum of the two runs with one surface rough.
"""

import matplotlib.pyplot as plt
import numpy as np

from wheelrail.core.engine import simulate
from wheelrail.core.parameters import ContactParameters, ModelParameters
from wheelrail.core.spectra.force import force_spectrum

params = ModelParameters(contact=ContactParameters(wheel_radius=0.4615))  # m: the wheel set's circumference
runs = {
    "rail rough": simulate("corrugated-rail", model="2d", length=2.0, params=params),
    "wheel rough": simulate("sinter-wheel-1", model="2d", length=2.0, params=params),
    "both": simulate("corrugated-rail", wheel_roughness="sinter-wheel-1", model="2d", length=2.0, params=params),
}
levels = {name: force_spectrum(result) for name, result in runs.items()}
centres = levels["both"][0]
energy_sum = 10 * np.log10(10 ** (levels["rail rough"][1] / 10) + 10 ** (levels["wheel rough"][1] / 10))

fig, ax = plt.subplots(figsize=(6.5, 3.6))
for name, (_, level) in levels.items():
    ax.semilogx(centres, level, label=name)
ax.semilogx(centres, energy_sum, "k:", label="energy sum of the two")
ax.set(xlabel="frequency (Hz)", ylabel="L_F (dB re 1 N)", title="2d model, line 0, 100 km/h")
ax.legend(fontsize=8)
fig.tight_layout()
