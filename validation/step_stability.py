"""The coupled step's period-two stability margin k_H (1/k_H + H(-1)) over the accepted speeds, for the paper's
track and the corners of the accepted track ranges (history.check_step_stability refuses a run where it is not
positive). Each new track costs its Green's functions once (13-60 s). Prints the worst margin and its speed.

    python3 validation/step_stability.py
"""

from __future__ import annotations

import numpy as np

from wheelrail.core.engine.history import check_step_stability
from wheelrail.core.inputs.declared import model_parameters
from wheelrail.core.parameters import KMH, MAX_SPEED_KMH, MIN_SPEED_KMH
from wheelrail.core.track import moving_weights
from wheelrail.core.wheel import wheel_discrete_system

TRACKS = {
    "paper's track": {},
    "soft pads 10 MN/m": {"pad_stiffness": 10e6},
    "stiff pads 3000 MN/m": {"pad_stiffness": 3000e6},
    "stiff pads and ballast, light sleepers": {"pad_stiffness": 3000e6, "sleeper_mass": 20.0, "ballast_stiffness": 3e9},
    "soft, heavy, least damped": {
        "pad_stiffness": 10e6,
        "sleeper_mass": 300.0,
        "ballast_stiffness": 10e6,
        "pad_damping": 5e3,
        "ballast_damping": 20e3,
    },
}


def main() -> None:
    speeds = np.geomspace(MIN_SPEED_KMH, MAX_SPEED_KMH, 40)
    for name, values in TRACKS.items():
        worst = (np.inf, None)
        for kmh in speeds:
            params = model_parameters({**values, "speed": kmh * KMH})
            dt = params.run.time_step
            weights = moving_weights(params.run.speed, dt, params.track)
            margin = check_step_stability(params, weights, wheel_discrete_system(params.wheel, dt))
            worst = min(worst, (margin, kmh))
        print(f"{name:42s} worst margin {worst[0]:.3f} at {worst[1]:.1f} km/h", flush=True)


if __name__ == "__main__":
    main()
