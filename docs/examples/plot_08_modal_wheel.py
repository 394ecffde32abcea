"""
The modal wheel against the paper's 2-DOF wheel
===============================================

The paper's wheel is two masses and springs: it has no modes of its own. The modal wheel
(``wheelrail.core.modal_wheel``) computes a solid wheel's modes from its cross-section (axisymmetric finite
elements, n = 0..10 nodal diameters, to 10 kHz) and, in the interaction, puts its radial receptance at the contact
in series with the paper's wheelset mass and suspension (``wheelrail run --wheel-model modal``). Here the 840 mm
named wheel at the paper's R = 0.39 m: its cross-section and natural frequencies, its radial receptance beside the
2-DOF wheel's, and the contact force on the same rough rail (the bundled corrugated rail, line 0, ``hertz``,
100 km/h, 2 m) with each wheel. The modes take a few seconds once, then come from the cache.
"""

import matplotlib.pyplot as plt
import numpy as np

from wheelrail.core.engine import simulate
from wheelrail.core.modal_wheel import wheel_modes, wheel_profile_for
from wheelrail.core.modal_wheel.time_domain import modal_wheel_receptance, modal_wheel_system
from wheelrail.core.parameters import ModelParameters
from wheelrail.core.spectra.force import force_spectrum
from wheelrail.core.wheel import wheel_receptance

params = ModelParameters()
modes = wheel_modes(wheel_profile_for(params.contact.radius_along))
system = modal_wheel_system(modes, params.wheel, params.run.time_step)
runs = {
    "2-DOF wheel": simulate("corrugated-rail", model="hertz", line=0, length=2.0, params=params),
    "modal wheel": simulate("corrugated-rail", model="hertz", line=0, length=2.0, params=params, wheel_system=system),
}

fig, axes = plt.subplots(1, 4, figsize=(15, 3.6))
nodes, corners = modes.mesh.nodes * 1e3, modes.mesh.triangles[:, :3]
axes[0].triplot(nodes[:, 1], nodes[:, 0], corners, lw=0.3)
axes[0].set(xlabel="z (mm)", ylabel="r (mm)", title="cross-section and mesh", aspect="equal")
for family, marker in (("axial", "o"), ("radial", "s"), ("circumferential", "^")):
    chosen = modes.family == family
    axes[1].plot(modes.harmonic[chosen], modes.frequency[chosen], marker, ls="", label=family)
axes[1].set(xlabel="nodal diameters n", ylabel="frequency (Hz)", title="natural frequencies")
f = np.geomspace(20, 8000, 800)
axes[2].loglog(f, np.abs(wheel_receptance(params.wheel, f)), label="2-DOF wheel")
axes[2].loglog(f, np.abs(modal_wheel_receptance(modes, params.wheel, f)), label="modal wheel")
axes[2].set(xlabel="frequency (Hz)", ylabel="|receptance| (m/N)", title="wheel at the contact")
for label, result in runs.items():
    centres, levels = force_spectrum(result)
    axes[3].semilogx(centres, levels, "o-", ms=3, label=label)
axes[3].set(xlabel="frequency (Hz)", ylabel="L_F (dB re 1 N)", title="contact force, corrugated rail")
for ax in axes[1:]:
    ax.legend(fontsize=7)
fig.tight_layout()

centres, two_dof = force_spectrum(runs["2-DOF wheel"])
_, modal = force_spectrum(runs["modal wheel"])
for centre, a, b in zip(centres, two_dof, modal, strict=True):
    if np.isfinite(a) and np.isfinite(b) and abs(b - a) >= 1.0:
        print(f"{centre:7.0f} Hz: modal wheel {b - a:+.1f} dB against the 2-DOF wheel")
