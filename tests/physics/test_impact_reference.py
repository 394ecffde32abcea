"""The independent impact simulation (validation/impact_reference.py): a 50 mm rounded flat at 100 km/h lifts
the wheel off the rail and peaks at 2-3 times the preload; the full reference's figures (docs/validation.md)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "validation" / "impact_reference.py"


@pytest.fixture(scope="module")
def reference():
    spec = importlib.util.spec_from_file_location("validation_impact_reference", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclass looks its module up there
    try:
        spec.loader.exec_module(module)
        yield module
    finally:
        del sys.modules[spec.name]


def test_a_flat_at_100_kmh_lifts_the_wheel_and_peaks_at_two_to_three_preloads(reference):
    # a short track (12 bays) and a coarse step (8 elements a bay, 20 us): 4096 steps, within 0.3 % of the full
    # reference's peak (70 bays, 16 elements, 10 us: 155.1 kN) and its 0.25 ms without contact
    run = reference.simulate_impact(100 / 3.6, n_bays=12, elements_per_bay=8, time_step=20e-6)
    assert run.force[0] == run.preload
    assert 2.0 * run.preload < run.peak < 3.0 * run.preload
    assert run.peak == pytest.approx(155.1e3, rel=3e-3)
    assert run.minimum == 0.0
    assert 0.2e-3 <= run.time_without_contact <= 0.3e-3
    assert np.all(run.force >= 0.0)  # the spring never pulls


@pytest.mark.slow
def test_a_gentle_dip_at_walking_speed_follows_the_static_solution(reference):
    # a long gentle dip (3 mm over 1.8 m): the wheel follows it, and beyond the static solution (the same springs
    # in series at each x) the suspension's damper adds c_S v z' (up to 0.1 kN at 5 km/h), the wheel's inertia
    # M_W v^2 z'' (~20 N) and the track rings under the moving load: 0.26 kN at most (validation/impact_reference.py
    # --walking), 0.4 % of P
    run = reference.simulate_impact(5 / 3.6, n_bays=12, elements_per_bay=8, time_step=200e-6, kind="weld")
    sample = slice(None, None, 200)
    static = reference.static_force(run.position[sample], kind="weld", n_bays=12, elements_per_bay=8)
    assert np.ptp(static) > 3e3  # the dip changes the static force by ~k_S D (the suspension lets the wheel follow)
    np.testing.assert_allclose(run.force[sample], static, rtol=0, atol=0.005 * run.preload)


@pytest.mark.slow
def test_the_full_reference_figures(reference):
    # the figures of docs/validation.md ("Impact of a wheel flat: the independent reference")
    for speed_kmh, peak, minimum in ((30, 97.6e3, 28.4e3), (60, 116.2e3, 9.7e3), (100, 155.1e3, 0.0)):
        run = reference.simulate_impact(speed_kmh / 3.6)
        assert run.peak == pytest.approx(peak, abs=60.0)
        assert run.minimum == pytest.approx(minimum, abs=60.0)
