"""
Soft against stiff rail pads: force and noise
=============================================

The pad stiffness is the main lever of rolling-noise design. A soft pad decouples the rail from the sleepers:
the rail's vibration decays slowly along the track and the rail radiates more; a stiff pad ties the rail to the
sleepers, whose own radiation then grows. Here the same rough rail (the bundled corrugated rail, line 0, the
``hertz`` model at 100 km/h) runs on the paper's track with 60 MN/m and with 1000 MN/m pads; every other input is
the paper's. Each track is an input like the speed (``wheelrail.core.inputs.declared``); each new one costs its Green's
functions once (13-60 s, then cached). The run is 2 m long to keep the gallery quick: the bands below 100 Hz
are not resolved.
"""

import matplotlib.pyplot as plt
import numpy as np

from wheelrail.core.engine import simulate
from wheelrail.core.inputs.declared import model_parameters
from wheelrail.core.noise.decay import track_decay
from wheelrail.core.noise.run_noise import run_noise
from wheelrail.core.spectra.force import force_spectrum

pads_mn_m = (60, 1000)
runs, noise, decay = {}, {}, {}
for pad in pads_mn_m:
    params = model_parameters({"pad_stiffness": pad * 1e6})  # SI: N/m
    runs[pad] = simulate("corrugated-rail", model="hertz", line=0, length=2.0, params=params)
    noise[pad] = run_noise(runs[pad])  # the TWINS-like chain on this track: rail, sleeper, wheel
    decay[pad] = track_decay(params.track)  # EN 15461 on the noise model's track

fig, axes = plt.subplots(1, 3, figsize=(11, 3.4))
for pad in pads_mn_m:
    centres, levels = force_spectrum(runs[pad])
    axes[0].semilogx(centres, levels, label=f"{pad} MN/m")
    f = noise[pad].frequency_hz
    axes[1].semilogx(f, noise[pad].sound_power_db["rail"], label=f"rail, {pad} MN/m")
    axes[1].semilogx(f, noise[pad].sound_power_db["sleeper"], "--", label=f"sleeper, {pad} MN/m")
    axes[2].semilogx(decay[pad]["frequency_hz"], decay[pad]["decay_rate_dB_per_m"], label=f"{pad} MN/m")
limit = np.array([np.nan if v is None else v for v in decay[pads_mn_m[0]]["limit_dB_per_m"]])
axes[2].semilogx(decay[pads_mn_m[0]]["frequency_hz"], limit, "k:", label="EN ISO 3095 limit")
axes[0].set(xlabel="frequency (Hz)", ylabel="L_F (dB re 1 N)", title="contact force")
axes[1].set(xlabel="frequency (Hz)", ylabel="L_W (dB re 1 pW)", title="sound power of one wheel's rail and sleepers")
axes[2].set(xlabel="frequency (Hz)", ylabel="dB/m", title="vertical decay rate", yscale="log")
for ax in axes:
    ax.legend(fontsize=7)
fig.tight_layout()

for pad in pads_mn_m:
    dba = noise[pad].sound_power_dba
    print(
        f"{pad:5d} MN/m pads: L_WA rail {dba['rail']:.1f}, sleeper {dba['sleeper']:.1f}, wheel {dba['wheel']:.1f} "
        f"dB(A) per wheel; per axle {noise[pad].axle_dba:.1f} dB(A); pass-by {noise[pad].pass_by_laeq_dba:.1f} dB(A)"
    )
