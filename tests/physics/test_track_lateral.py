"""The lateral track (``wheelrail.core.track.lateral``): its receptances' structure, its decay rate's inputs, and the
EN ISO 3095 lateral limit's data file."""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.noise.decay import decay_against_limit, lateral_decay_limit
from wheelrail.core.parameters import TrackParameters
from wheelrail.core.track.lateral import LateralNumerics, lateral_decay_rate, lateral_receptances

SHORT = LateralNumerics(track_bays=40)  # 26 m of track: enough for the structure of the receptances


def test_the_lateral_limit_is_figure_3_curve_b():
    limit = lateral_decay_limit()
    assert limit.frequency_hz.tolist() == [250, 315, 400, 500, 630, 800, 1000, 1250, 1600, 2000, 2500, 3150, 4000, 5000]
    assert limit.limit_db_per_m.tolist() == [
        2.04,
        1.38,
        0.94,
        0.64,
        0.43,
        0.29,
        0.2,
        0.2,
        0.32,
        0.5,
        0.5,
        0.5,
        0.5,
        0.5,
    ]
    assert "curve B (lateral)" in limit.source and "jmrplens/phonometry" in limit.source
    verdict = decay_against_limit([1000.0, 2000.0], [0.25, 0.4], "lateral")
    assert verdict["below_limit_hz"] == [2000.0] and verdict["limit_dB_per_m"] == [0.2, 0.5]
    assert "curve B" in verdict["limit_source"]


def test_the_vertical_force_drives_the_head_through_its_offset_alone():
    f = [0.0, 300.0, 1500.0]
    centred = lateral_receptances(TrackParameters(), f, numerics=SHORT)
    assert np.all(centred.vertical_to_lateral == 0)  # no torque on the centreline
    one = lateral_receptances(TrackParameters(), f, contact_offset=0.01, numerics=SHORT)
    two = lateral_receptances(TrackParameters(), f, contact_offset=-0.02, numerics=SHORT)
    np.testing.assert_allclose(two.vertical_to_lateral, -2 * one.vertical_to_lateral, rtol=1e-12)  # linear in d
    np.testing.assert_allclose(one.lateral_point, centred.lateral_point, rtol=1e-12)
    assert one.vertical_to_lateral[0].real > 0  # a static vertical load towards +y rolls the head towards +y


def test_the_receptances_are_passive_and_reciprocal():
    f = np.geomspace(50, 5000, 9)
    r = lateral_receptances(TrackParameters(), f, contact_offset=0.02, numerics=SHORT)
    # a damped structure's point receptances take power: Im(alpha) <= 0 with x = Re(X e^{iwt})
    assert np.all(r.lateral_point.imag < 0) and np.all(r.torsional_point.imag < 0)
    # reciprocity (a symmetric dynamic stiffness): the transfer from 0.9 to 0.3 of a bay is the one back
    back = lateral_receptances(TrackParameters(), f, x_response=-0.39, numerics=SHORT, excitation=0.9)
    ahead = lateral_receptances(TrackParameters(), f, x_response=0.39, numerics=SHORT, excitation=0.3)
    np.testing.assert_allclose(ahead.lateral_point, back.lateral_point, rtol=1e-9)
    np.testing.assert_allclose(ahead.torsional_point, back.torsional_point, rtol=1e-9)


def test_bad_inputs_are_one_line_errors():
    with pytest.raises(WheelrailError, match="off the railhead"):
        lateral_receptances(TrackParameters(), [100.0], contact_offset=0.05, numerics=SHORT)
    with pytest.raises(WheelrailError, match="finite and >= 0"):
        lateral_receptances(TrackParameters(), [-1.0], numerics=SHORT)
    with pytest.raises(WheelrailError, match="outside the lateral track"):
        lateral_receptances(TrackParameters(), [100.0], x_response=100.0, numerics=SHORT)
    with pytest.raises(WheelrailError, match="bands 50 Hz-10 kHz"):
        lateral_decay_rate(TrackParameters(), [20.0], numerics=SHORT)
    with pytest.raises(WheelrailError, match="pad_lateral_stiffness|LateralParameters"):
        from wheelrail.core.lateral_parameters import LateralParameters

        LateralParameters(pad_lateral_stiffness=-1.0)


def test_stiffer_lateral_pads_make_the_lateral_decay_faster_above_their_resonance():
    from dataclasses import replace

    numerics = LateralNumerics(track_bays=80, points_per_band=3)
    soft = TrackParameters()
    stiff = replace(soft, lateral=replace(soft.lateral, pad_lateral_stiffness=120e6))
    f = [500.0, 1000.0]  # above the rail-on-pad lateral resonance (about 100-400 Hz, with the pads)
    assert np.all(lateral_decay_rate(stiff, f, numerics=numerics) > lateral_decay_rate(soft, f, numerics=numerics))
