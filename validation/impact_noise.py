"""The impact noise of a wheel flat against speed: its slope in dB per doubling of speed (Wu & Thompson 2002:
impact noise grows about 20 lg v, 6 dB per doubling, against 30 lg v, 9 dB, for rolling noise).

A 50 mm rounded flat (D = L^2 / (16 R)) met once at a midspan on a smooth rail, 65 kN, the paper's track and 2-DOF
wheel, ``hertz`` on the wheel-centre trajectory, at 50 and 100 km/h (element 1 mm); its noise on the default track
numerics (:func:`wheelrail.core.noise.run_noise.run_noise`, the impact's part
:mod:`wheelrail.core.noise.impact_noise`). Printed per speed: the exposure level per impact L_WAE, the rate
v / (2 pi R) and the pass-by level of the impacts alone (40 axles, 200 m); then the slopes between the speeds.

Run: ``python3 validation/impact_noise.py [km/h ...]`` (default 50 100).
"""

from __future__ import annotations

import math
import sys

from wheelrail.core.engine import simulate
from wheelrail.core.irregularities import WheelFlat
from wheelrail.core.noise.run_noise import run_noise
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters
from wheelrail.core.roughness import RoughnessSet

BAY = ModelParameters().track.support.sleeper_spacing


def flat_noise(speed_kmh: float, model: str = "hertz", numerics=None):
    """The noise of a run of two bays with the flat's first meeting at the midspan in between."""
    smooth = RoughnessSet.smooth(3 * BAY + 0.1, lines=41)
    flat = WheelFlat(length=0.05, position=1.5 * BAY)
    params = ModelParameters(run=RunParameters(speed=speed_kmh * KMH, element_size=1e-3, irregularities=(flat,)))
    result = simulate(smooth, model=model, params=params, length=round(2 * BAY / 1e-3) * 1e-3)
    return run_noise(result, numerics=numerics).impact


def main(argv: list[str]) -> None:
    speeds = [float(v) for v in argv] or [50.0, 100.0]
    rows = []
    for speed in speeds:
        impact = flat_noise(speed)
        rows.append((speed, impact.exposure_dba, impact.pass_by_laeq_dba["flat"]))
        print(
            f"{speed:5g} km/h: L_WAE {impact.exposure_dba:.1f} dB(A) re 1 pJ per impact, rate "
            f"{impact.flat_rate_hz:.2f} /s, pass-by of the impacts {impact.pass_by_laeq_dba['flat']:.1f} dB(A)"
        )
    for (v1, e1, p1), (v2, e2, p2) in zip(rows, rows[1:], strict=False):
        doublings = math.log2(v2 / v1)
        print(
            f"{v1:g} -> {v2:g} km/h: per impact {(e2 - e1) / doublings:+.1f} dB per doubling "
            f"({(e2 - e1) / math.log10(v2 / v1):.1f} lg v), pass-by {(p2 - p1) / doublings:+.1f} dB per doubling "
            f"({(p2 - p1) / math.log10(v2 / v1):.1f} lg v)"
        )


if __name__ == "__main__":
    main(sys.argv[1:])
