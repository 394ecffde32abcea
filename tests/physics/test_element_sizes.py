"""Every model runs at both ends of the accepted element size (``--element-mm`` 0.5 and 2: ``ranges.ACCEPTED``), on
a rail set (1 mm samples and lines) and a wheel set (0.5 mm samples, lines 2 mm apart), and at the fastest and
slowest accepted speeds: the steps are the element apart in space and element / speed in time, the force stays
around the preload, and the ``3d`` pressure integrates to the force over elements of the size run.

What the element size changes in each model (the grid of the ``3d`` window, the ``2d`` bedding's elements, the
``hertz-average`` and ``hertz-winkler`` equivalent roughness sampled on it, the run-in in whole elements, the
track's convolution weights at dt = element / speed) is read from ``params.run.element_size`` everywhere; these runs
check that none of them assumes 1 mm. The force spectra's convergence in it is validation/element_convergence.py.
"""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.engine import simulate
from wheelrail.core.inputs.ranges import ACCEPTED, MAX_SPEED_KMH, MIN_SPEED_KMH
from wheelrail.core.models import model_names
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters

SIZES = (ACCEPTED["element_size"].minimum, ACCEPTED["element_size"].maximum)  # 0.5 and 2 mm


def _run(set_name, model, element_size, speed_kmh=100.0, length=0.04):
    params = ModelParameters(run=RunParameters(speed=speed_kmh * KMH, element_size=element_size))
    return simulate(set_name, model=model, line=0, params=params, length=length)


@pytest.mark.parametrize("element_size", SIZES)
@pytest.mark.parametrize("set_name", ["corrugated-rail", "sinter-wheel-1"])
@pytest.mark.parametrize("model", [m for m in model_names() if m in ("3d", "2d", "hertz", "hertz-winkler",
                                                                       "hertz-average")])  # fmt: skip
def test_every_model_runs_at_both_ends_of_the_element_range(model, set_name, element_size):
    result = _run(set_name, model, element_size)
    n = int(round(0.04 / element_size))
    assert result.n_steps == n and result.element_size == element_size
    assert np.allclose(np.diff(result.x), element_size, rtol=1e-9)
    assert np.allclose(np.diff(result.time), element_size / (100 * KMH), rtol=1e-9)
    preload = result.header.params.contact.preload
    assert np.all(np.isfinite(result.force)) and abs(result.force.mean() / preload - 1) < 0.2
    if model == "3d":
        assert np.allclose(result.pressure.sum(axis=(1, 2)) * element_size**2, result.force, rtol=1e-5)


@pytest.mark.parametrize(("speed_kmh", "element_size"), [(MIN_SPEED_KMH, SIZES[1]), (MAX_SPEED_KMH, SIZES[0])])
def test_the_longest_and_shortest_steps_run_and_stay_smooth(speed_kmh, element_size):
    # 2 mm at 5 km/h is the longest step an edge accepts (1.44 ms), 0.5 mm at 400 km/h the shortest (4.5 us); on a
    # smooth rail the force stays at the preload (no period-two chatter: the second difference stays small)
    from wheelrail.core.roughness import RoughnessSet

    smooth = RoughnessSet.smooth(1.0, dx=0.5e-3)
    result = _run(smooth, "hertz", element_size, speed_kmh, length=0.1)
    assert result.time_step == pytest.approx(element_size / (speed_kmh * KMH))
    assert np.all(np.isfinite(result.force)) and np.max(np.abs(np.diff(result.force, 2))) < 500.0


@pytest.mark.slow
def test_the_memory_estimate_bounds_a_half_millimetre_3d_run():
    # the 3d window at 0.5 mm is 49 x 49 elements (four times the maps of 1 mm per step, twice the steps per metre):
    # the estimate (core/engine/memory.py, from the element size) must bound the traced growth, within a factor two
    import json
    import subprocess
    import sys
    from pathlib import Path

    from wheelrail.core.engine import memory
    from wheelrail.core.models import model_entry

    params = ModelParameters(run=RunParameters(element_size=SIZES[0]))
    script = Path(__file__).parents[1] / "traced_peaks.py"  # in a fresh interpreter: the script says why
    done = subprocess.run(
        [sys.executable, str(script), "3d", str(SIZES[0]), "0.5", "1.0"], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    short, long = json.loads(done.stdout.splitlines()[-1])
    measured = long - short
    estimate = [memory.check_run_memory(model_entry("3d"), params, length, 0.1, True) for length in (0.5, 1.0)]
    assert measured <= estimate[1] - estimate[0] <= 2 * measured
