"""
A wheel flat through the four treatments (Pieringer, Kropp & Nielsen, Wear 2014)
================================================================================

A 50 mm rounded wheel flat (depth L^2 / (16 R) = 0.40 mm) meets a smooth rail at a midspan at 100 km/h, with
the paper's track, wheel and 65 kN preload. Four ways to see it:

* ``hertz`` on the raw profile: the Hertz spring pressed by the flat's profile itself
  (``RunParameters(irregularity_input="raw")``), which a real wheel cannot follow into the dip;
* ``hertz`` on the wheel-centre trajectory (the default): the envelope of a rigid wheel rolling over the flat;
* ``2d`` and ``3d``: the flat as it is, in the contact window.

The force traces are drawn on one plot, the preload dashed; the impact summary
(:func:`wheelrail.core.engine.impact_summary`) of each gives its peak and its time without contact. The runs are
kept short (0.6 m, the flat 0.35 m in) so that the gallery builds quickly; ``validation/impact_models.py`` runs the
same case over two sleeper bays, and ``wheelrail study impact`` sweeps the flat's length and the speed.
"""

import matplotlib.pyplot as plt

from wheelrail.core.drawing.palette import model_colour
from wheelrail.core.engine import impact_summary, simulate
from wheelrail.core.irregularities import WheelFlat
from wheelrail.core.models import model_names
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters
from wheelrail.core.roughness import RoughnessSet

# a smooth rail: 41 lines 1 mm apart (the 3D window's width), 0.7 m long
smooth = RoughnessSet.smooth(0.7, lines=41)
bay = ModelParameters().track.support.sleeper_spacing
flat = WheelFlat(length=0.05, position=0.35)

cases = (("hertz", "raw"), ("hertz", "trajectory"), ("2d", "trajectory"), ("3d", "trajectory"))
fig, ax = plt.subplots(figsize=(8, 4.2))
for model, choice in cases:
    run = RunParameters(speed=100 * KMH, irregularities=(flat,), irregularity_input=choice)
    result = simulate(smooth, model=model, params=ModelParameters(run=run), length=0.6)
    summary = impact_summary(result)
    label = f"{model} on the {'raw profile' if choice == 'raw' else 'trajectory' if model == 'hertz' else 'surface'}"
    ax.plot(
        result.x * 1e3,
        result.force / 1e3,
        color=model_colour(model, model_names()),  # the project's colour of each model; the raw profile dashed
        ls="--" if choice == "raw" else "-",
        lw=2.2 if model == "3d" else 1.1,
        label=f"{label}: peak {summary.peak / 1e3:.0f} kN, {summary.time_without_contact * 1e3:.2f} ms in the air",
    )
    print(f"{label:28s} peak {summary.peak / 1e3:6.1f} kN, without contact {summary.time_without_contact * 1e3:.3f} ms")
ax.axhline(65.0, color="0.5", ls="--", lw=0.8, label="preload 65 kN")
ax.set(xlim=(300, 500), xlabel="wheel position x (mm)", ylabel="contact force (kN)")
ax.set_title("50 mm rounded flat, 100 km/h, smooth rail, the paper's track", fontsize=10)
ax.grid(True, alpha=0.3)
ax.legend(fontsize=7)
fig.tight_layout()
plt.show()
