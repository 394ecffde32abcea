"""The four ways the models meet a wheel flat, and the Hertz model's convergence in the step.

A 50 mm rounded flat (D = L^2 / (16 R)) at a midspan on a smooth rail, 65 kN, the paper's track and 2-DOF wheel,
through ``wheelrail run``'s engine: ``3d`` and ``2d`` on the surface, ``hertz`` on the wheel-centre trajectory
and ``hertz`` on the raw profile (``RunParameters.irregularity_input``). Printed per speed: each model's peak
force, minimum force and time without contact (``engine.impact_summary``), and for ``hertz`` on the trajectory
the change of the peak and of the time without contact when the element (the step) is halved, 1 to 0.5 mm; the
independent reference's figures (``validation/impact_reference.py``) beside them. Pieringer, Kropp & Nielsen
(Wear 2014) found Hertz on the raw profile far off, Hertz on the trajectory slightly above 3D and 2D slightly
below it.

Run: ``python3 validation/impact_models.py [km/h ...]`` (default 100; the 3D runs take about a minute each).
"""

from __future__ import annotations

import sys
import time

from wheelrail.core.engine import impact_summary, simulate
from wheelrail.core.irregularities import WheelFlat
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters
from wheelrail.core.roughness import RoughnessSet

REFERENCE = {30.0: (97.6, 0.0), 60.0: (116.2, 0.0), 100.0: (155.1, 0.25)}  # kN, ms (impact_reference.py)
CASES = (("3d", "trajectory"), ("hertz", "trajectory"), ("2d", "trajectory"), ("hertz", "raw"))
BAY = ModelParameters().track.support.sleeper_spacing


def flat_run(model: str, speed_kmh: float, irregularity_input: str = "trajectory", element_size: float = 1e-3):
    """A run of two bays with the flat's first meeting at the midspan in between; its impact summary."""
    smooth = RoughnessSet.smooth(3 * BAY + 0.1, lines=41)  # 40 mm across: the 3D window's rows at 2.4 P
    flat = WheelFlat(length=0.05, position=1.5 * BAY)
    run = RunParameters(speed=speed_kmh * KMH, element_size=element_size, irregularities=(flat,),
                        irregularity_input=irregularity_input)  # fmt: skip
    length = round(2 * BAY / element_size) * element_size
    return impact_summary(simulate(smooth, model=model, params=ModelParameters(run=run), length=length))


def main(argv: list[str]) -> None:
    speeds = [float(v) for v in argv] or [100.0]
    for speed in speeds:
        reference = REFERENCE.get(speed)
        words = f" (reference {reference[0]} kN, {reference[1]} ms)" if reference else ""
        print(f"50 mm rounded flat at {speed:g} km/h{words}:")
        for model, choice in CASES:
            start = time.process_time()
            summary = flat_run(model, speed, choice)
            print(
                f"  {model:5s} on the {choice:10s}: peak {summary.peak / 1e3:6.1f} kN ({summary.peak / 65e3:.2f} P), "
                f"minimum {summary.minimum / 1e3:5.1f} kN, without contact {summary.time_without_contact * 1e3:.3f} "
                f"ms ({time.process_time() - start:.0f} s CPU)"
            )
        coarse, fine = flat_run("hertz", speed), flat_run("hertz", speed, element_size=5e-4)
        lost = (
            f"{(fine.time_without_contact / coarse.time_without_contact - 1) * 100:+.2f} %"
            if coarse.time_without_contact
            else "none either way"
        )
        print(f"  hertz on the trajectory, element halved: peak {(fine.peak / coarse.peak - 1) * 100:+.2f} %, "
              f"time without contact {lost}")  # fmt: skip


if __name__ == "__main__":
    main(sys.argv[1:])
