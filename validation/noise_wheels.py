"""The two wheels of the noise chain (``--wheel-model directive|modal``) side by side.

1. The 920 mm freight wheel's L_H,veh-equivalent (the modal wheel, the chain's default numerics) against
   CNOSSOS-EU Table G-3b's 920 mm column, per band 500 Hz-5 kHz and on average.
2. A `hertz` run on the cast-iron wheel set (line 0, 100 km/h, the paper's wheel R = 390 mm: the modal wheel is the
   840 mm named wheel at 780 mm) with each wheel: the wheel's and the total L_WA per wheel and the pass-by level; the
   2-DOF run with either wheel's sound power, and a run with the modal wheel, its wheel driven by its own force.
3. The rail's power radiated in the wavenumber domain against the 2D ratio on the whole field, 50-250 Hz.

    WHEELRAIL_CACHE_DIR=/tmp/cache python3 validation/noise_wheels.py
"""

from __future__ import annotations

import time

import numpy as np

from wheelrail.core.engine import simulate
from wheelrail.core.inputs.declared import model_parameters
from wheelrail.core.modal_wheel import wheel_profile_for
from wheelrail.core.noise.cnossos import vehicle_transfer
from wheelrail.core.noise.run_noise import run_noise
from wheelrail.core.noise.tables import NOMINAL_FREQUENCIES_HZ
from wheelrail.core.noise.twins import track_noise_model


def main() -> None:
    f = np.asarray(NOMINAL_FREQUENCIES_HZ)
    start = time.perf_counter()
    modal = track_noise_model(model_parameters({"wheel_radius": 0.46}), wheel_model="modal")
    print(
        "1. 920 mm wheel, L_H,veh-equivalent (modal) - CNOSSOS-EU 920 mm column, dB "
        f"({time.perf_counter() - start:.0f} s)"
    )
    table = vehicle_transfer(920)
    bands = (f >= 500) & (f <= 5000)
    for fi, m, c in zip(f[bands], modal.transfer_db["wheel"][bands], table[bands], strict=True):
        print(f"  {fi:6g} Hz  modal {m:6.1f}  directive {c:6.1f}  difference {m - c:+5.1f}")
    diff = modal.transfer_db["wheel"][bands] - table[bands]
    print(f"  mean {np.mean(diff):+.2f} dB, largest {diff[np.argmax(np.abs(diff))]:+.1f} dB; bands beyond 6 dB: "
          f"{', '.join(f'{x:g}' for x in f[bands][np.abs(diff) > 6])} Hz")  # fmt: skip
    print("\n2. hertz run, cast-iron-wheel line 0, 100 km/h: L_WA per wheel, dB(A)")
    result = simulate("cast-iron-wheel", model="hertz", line=0)
    radius = result.header.params.contact.radius_along
    modal_run = simulate("cast-iron-wheel", model="hertz", line=0, wheel_system=wheel_profile_for(radius))
    for run, wheel_model in ((result, "directive"), (result, "modal"), (modal_run, "modal")):
        noise = run_noise(run, wheel_model=wheel_model)
        dba = noise.sound_power_dba
        print(f"  {run.header.wheel_model} run, {wheel_model:9s}: wheel {dba['wheel']:.1f}, rail {dba['rail']:.1f}, "
              f"sleeper {dba['sleeper']:.1f}, total {dba['total']:.1f}; "
              f"pass-by {noise.pass_by_laeq_dba:.1f} dB(A)")  # fmt: skip
        print(f"             {noise.configuration['wheel']}")
    print("\n3. rail: wavenumber-domain radiation against the 2D ratio on the whole field, dB")
    print(
        "  " + ", ".join(f"{fi:g} Hz {c:+.2f}" for fi, c in zip(f[:8], modal.rail_decay_correction_db[:8], strict=True))
    )


if __name__ == "__main__":
    main()
