"""
Moving Green's functions of the track (paper Fig. 4)
====================================================

The rail's response to a unit impulse travelling with the wheel, g_R,v(t) of the paper's eq. (2), for a load
above a sleeper and at midspan and three speeds. The stationary impulse responses are computed once (a few
seconds, then cached on disk) and each speed is read off them in milliseconds.
"""

import matplotlib.pyplot as plt

from wheelrail.core.track import moving_from_stationary, stationary_track_response

response = stationary_track_response()  # the paper's track; cached after the first call
positions = response.excitation_positions  # excitation points across the central bay, m

fig, axes = plt.subplots(1, 2, figsize=(9, 3.4), sharey=True)
for ax, index, where in ((axes[0], 0, "above a sleeper"), (axes[1], len(positions) // 2, "at midspan")):
    for kmh, style in ((50, "--"), (100, "-."), (150, "-")):
        green = moving_from_stationary(response, kmh / 3.6)  # speed in m/s
        keep = green.time <= 0.02
        ax.plot(green.time[keep] * 1e3, green.values[index, keep], style, label=f"{kmh} km/h")
    ax.set(xlabel="time (ms)", title=f"excitation {where} (x0 = {positions[index] * 1e3:.0f} mm)")
axes[0].set_ylabel("g (m/(N s))")
axes[0].legend()
fig.tight_layout()
