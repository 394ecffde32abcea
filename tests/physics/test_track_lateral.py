"""The lateral track (``wheelrail.core.track.lateral``): its receptances' structure, its decay rate's inputs, and the
EN ISO 3095 lateral limit's data file."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.noise.decay import decay_against_limit, lateral_decay_limit
from wheelrail.core.parameters import RailParameters, TrackParameters
from wheelrail.core.track.lateral import (
    LOG10_E,
    LateralNumerics,
    lateral_band_frequencies,
    lateral_decay_rate,
    lateral_receptances,
)

SHORT = LateralNumerics(track_bays=40, absorbing_bays=8)  # 26 m of track: enough for the receptances' structure


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
    numerics = LateralNumerics(track_bays=80, points_per_band=3)
    soft = TrackParameters()
    stiff = replace(soft, lateral=replace(soft.lateral, pad_lateral_stiffness=120e6))
    f = [500.0, 1000.0]  # above the rail-on-pad lateral resonance (about 100-400 Hz, with the pads)
    assert np.all(lateral_decay_rate(stiff, f, numerics=numerics) > lateral_decay_rate(soft, f, numerics=numerics))


# --------------------------------------------------------------------------------------------------------------
# Against an independent model: the infinite periodic rail solved exactly in each bay (lateral_oracle.py)
# --------------------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("loss_factor", [0.0, 0.02])
def test_the_receptances_match_the_infinite_periodic_rail(loss_factor):
    from lateral_oracle import PeriodicLateralRail

    track = TrackParameters(rail=RailParameters(loss_factor=loss_factor))
    spacing = track.support.sleeper_spacing
    f = np.array([100.0, 315.0, 630.0, 1000.0, 2000.0, 4000.0])
    mid = lateral_receptances(track, f, x_response=np.array([0.0, 0.325, 1.3]), contact_offset=0.02)
    above = lateral_receptances(track, f, excitation=0.0)
    for i, fi in enumerate(f):
        exact = PeriodicLateralRail(track, fi)
        at = 0.5 * spacing
        reference = exact.railhead(at, [at - 1e-12, spacing, at + 1.3])
        level = 20 * np.log10(np.abs(mid.lateral_point[i]) / np.abs(reference))
        # the point and the next sleeper within 0.2 dB, 1.3 m on within 0.3 dB: 16 elements per bay are within
        # 0.1 dB to 5 kHz (against 32) and the absorbing ends return what reaches them 30 dB down or more
        assert np.all(np.abs(level[:2]) < 0.2), (fi, level)
        assert abs(level[2]) < 0.3, (fi, level)
        rolled = -0.02 * exact.railhead(at, [at - 1e-12], lateral=0.0, torque=1.0)[0]  # the torque -F d
        assert abs(20 * np.log10(abs(mid.vertical_to_lateral[i, 0]) / abs(rolled))) < 0.2, fi
        twist = exact.twist(at, [at - 1e-12])[0]
        assert abs(20 * np.log10(abs(mid.torsional_point[i, 0]) / abs(twist))) < 0.2, fi
        sleeper = exact.railhead(1e-9, [2e-9])[0]  # a load on a support: just after it (v, phi continuous)
        assert abs(20 * np.log10(abs(above.lateral_point[i]) / abs(sleeper))) < 0.2, fi


def test_the_decay_rate_matches_the_infinite_periodic_rail():
    from lateral_oracle import PeriodicLateralRail

    track = TrackParameters()
    spacing = track.support.sleeper_spacing
    numerics = LateralNumerics(points_per_band=3)
    bands = [250.0, 400.0, 630.0, 1000.0, 1600.0, 2500.0, 4000.0]
    model = lateral_decay_rate(track, bands, numerics=numerics)
    frequencies = lateral_band_frequencies(3)
    step = spacing / numerics.elements_per_bay
    count = int(numerics.decay_length / step) + 1
    for band, rate in zip(bands, model, strict=True):
        power = 0.0
        for f in frequencies[int(round(10 * np.log10(band / 50.0)))]:
            power = power + np.abs(PeriodicLateralRail(track, f).railhead_ahead(0.5 * spacing, step, count)) ** 2
        ratio = power / power[0]
        exact = LOG10_E / (step * (np.sum(ratio) - 0.5 * (ratio[0] + ratio[-1])))
        # EN 15461's sum on the same grid: within 5 % (the FE's wavenumbers at 16 elements per bay: -3 % at 5 kHz)
        assert abs(rate - exact) < 0.05 * exact, (band, rate, exact)


def test_the_lateral_fe_converges_in_elements_and_bays():
    """A sparse version of ``validation/lateral_convergence.py``: doubling the elements per bay or lengthening the
    track moves the decay rate by a few per cent and the point receptance by a few tenths of a dB."""
    track = TrackParameters()
    bands = [500.0, 1000.0, 2000.0, 4000.0]
    base = LateralNumerics(points_per_band=3)
    rate = lateral_decay_rate(track, bands, numerics=base)
    finer = lateral_decay_rate(track, bands, numerics=replace(base, elements_per_bay=32))
    longer = lateral_decay_rate(track, bands, numerics=replace(base, track_bays=360, absorbing_bays=30))
    assert np.all(np.abs(finer / rate - 1) < 0.05), finer / rate  # 2.4 % at most (4 kHz)
    assert np.all(np.abs(longer / rate - 1) < 0.02), longer / rate
    f = np.array(bands)
    point = lateral_receptances(track, f).lateral_point
    fine_point = lateral_receptances(track, f, numerics=replace(base, elements_per_bay=32)).lateral_point
    assert np.all(np.abs(20 * np.log10(np.abs(fine_point / point))) < 0.3)


def test_a_narrow_pad_is_the_point_support_and_a_wide_one_spreads_the_same_stiffness():
    from wheelrail.core.parameters import SupportParameters

    f = np.array([100.0, 630.0, 2000.0])
    point = lateral_receptances(TrackParameters(), f, numerics=SHORT).lateral_point
    narrow = TrackParameters(support=SupportParameters(pad_width=0.002))
    close = lateral_receptances(narrow, f, numerics=SHORT).lateral_point
    assert np.all(np.abs(20 * np.log10(np.abs(close / point))) < 0.02)  # (w / h)^2-small: the same support
    # static: a rigid-enough rail sees the pads' total stiffness whatever their width (0 Hz, 0.15 m pads)
    wide = TrackParameters(support=SupportParameters(pad_width=0.15))
    static = [lateral_receptances(t, [0.0], numerics=SHORT).lateral_point[0] for t in (TrackParameters(), wide)]
    assert abs(static[1] / static[0] - 1) < 0.02
