"""A wide pad lowers the sleeper-passing harmonics of the force as the first-order estimate says.

On a smooth rail the force varies with the wheel's place in the bay at the harmonics k v / L_S. To first order in the
support's coupling a pad of width b smooths the rail's receptance along the bay with its box, so the k-th harmonic is
the point support's times |sinc(k b / L_S)| (``validation/pad_harmonics.py``; a static FE track with 130 elements per
bay meets it within 5 % at k = 1-20). Small track numerics (16 positions, 32 refined elements per bay, a 10 us step)
keep the test fast; the default numerics meet the estimate more closely (docs/validation.md).
"""

import numpy as np
import pytest

from wheelrail.core.engine import simulate
from wheelrail.core.inputs.numerics import parse_track_numerics
from wheelrail.core.parameters import ModelParameters, SupportParameters, TrackParameters
from wheelrail.core.roughness import RoughnessSet

SMALL = parse_track_numerics("elements_per_bay=16,refined_elements_per_bay=32,positions_per_bay=16,time_step_us=10")
SPACING = 0.65  # m, the paper's sleeper spacing
ORDERS = np.arange(1, 13)


def _harmonics(pad_width: float) -> np.ndarray:
    """Force amplitudes (N) at k v / L_S, k = 1-12, of a hertz run on a smooth rail over one bay (the run starts in
    the moving load's steady state, so one bay is the periodic force)."""
    params = ModelParameters(track=TrackParameters(support=SupportParameters(pad_width=pad_width)))
    smooth = RoughnessSet.smooth(2.0)
    result = simulate(smooth, model="hertz", params=params, length=SPACING, track_numerics=SMALL, keep_pressure=False)
    force = result.force - result.force.mean()
    x = np.arange(len(force)) * result.element_size
    return np.array([2 * abs(np.mean(force * np.exp(-2j * np.pi * k * x / SPACING))) for k in ORDERS])


@pytest.fixture(scope="module")
def harmonics():
    return {width: _harmonics(width) for width in (0.0, 0.15)}


def test_a_wide_pad_lowers_the_harmonics_as_the_first_order_estimate(harmonics):
    point, pad = harmonics[0.0], harmonics[0.15]
    estimate = point * np.abs(np.sinc(ORDERS * 0.15 / SPACING))
    # k = 1-3 (86-128 Hz at 100 km/h): the pad within 12 % of the estimate (5-10 % at these small numerics)
    np.testing.assert_allclose(pad[:3], estimate[:3], rtol=0.12)
    # k = 8-12, where the estimate is 0.1-0.3 % of the point support's: within twice it and 0.5 N (the floor of
    # these numerics). With the first excitation position at the refined mesh's edge they were 5-8 N.
    high = slice(7, 12)
    assert np.all(pad[high] <= 2 * estimate[high] + 0.5), (pad[high], estimate[high])
    assert pad[high].sum() < 0.15 * point[high].sum()
