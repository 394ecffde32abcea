"""
Force spectra and contact filters of the five models (paper Fig. 10)
====================================================================

Each contact model runs on line 0 of the bundled corrugated rail at 100 km/h. The contact filter of a model
is its third-octave force level minus that of ``hertz``, the Hertz spring on the unfiltered roughness
(section 3.3). The paper's Fig. 10 averages the one-line models over lines -3..3 of an 8 m record; this run
is 1.5 m of one line, so its levels scatter more (``wheelrail study filters`` draws the full figure).
"""

import matplotlib.pyplot as plt

from wheelrail.core.engine import simulate
from wheelrail.core.models import model_names
from wheelrail.core.spectra.force import force_spectrum
from wheelrail.core.spectra.levels import contact_filter

levels = {}
for model in model_names():
    result = simulate("corrugated-rail", model=model, line=0, length=1.5)
    centres, levels[model] = force_spectrum(result)  # band centres (Hz), dB re 1 N

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 3.6))
for model, level in levels.items():
    left.semilogx(centres, level, label=model)
    right.semilogx(centres, contact_filter(level, levels["hertz"]), label=model)
left.set(xlabel="frequency (Hz)", ylabel="L_F (dB re 1 N)", title="force spectra, corrugated rail, line 0")
right.set(xlabel="frequency (Hz)", ylabel="L - L_hertz (dB)", title="contact filters")
left.legend(fontsize=8)
fig.tight_layout()
