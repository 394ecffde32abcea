"""Pads of a finite width: the rail on a Winkler layer k_P / w over the pad, exact integrals, the point support
as its limit, the same track in both time and frequency domains."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import SupportParameters, TrackParameters
from wheelrail.core.track.fe import assemble_track, pad_couplings, track_receptance


def _track(width: float, n_bays: int = 8) -> TrackParameters:
    return TrackParameters(support=SupportParameters(pad_width=width), n_bays=n_bays)


@pytest.mark.parametrize("per_bay", [16, 64])
def test_pad_layer_integrals_are_exact(per_bay):
    # Known answers for a rail moving as a rigid body over the pad (the Timoshenko interpolation represents
    # w = a + b (x - x_S), theta = b exactly): the pad's force is k_P a (the layer's k_P / w over its width w)
    # and its moment k_P w^2 / 12 b, whether or not the pad's edges are nodes (0.15 m over 16 or 64 elements of
    # a 0.65 m bay: they are not). Round-off tolerance.
    width = 0.15
    track = _track(width)
    model = assemble_track(track, per_bay)
    node = 4 * per_bay  # a support node inside the track
    xs = model.node_x[node]
    k = track.support.pad_stiffness
    force = moment = total = 0.0
    for dofs, (P, p, covered), _ in pad_couplings(track, model.node_x, model.w_dof, model.theta_dof, node):
        nodes = np.searchsorted(model.w_dof, dofs[::2])
        translation = np.ravel(np.column_stack([np.ones(2), np.zeros(2)]))
        rotation = np.ravel(np.column_stack([model.node_x[nodes] - xs, np.ones(2)]))
        force += translation @ P @ translation
        moment += rotation @ P @ rotation
        total += covered
        assert p @ translation == pytest.approx(translation @ P @ translation)  # the sleeper takes the same force
    assert force == pytest.approx(k, rel=1e-12)
    assert moment == pytest.approx(k * width**2 / 12, rel=1e-12)
    assert total == pytest.approx(k, rel=1e-12)


def test_narrow_pad_tends_to_the_point_support():
    # The receptances above a sleeper and at midspan (load above the sleeper) of a pad w wide tend to the point
    # support's as w -> 0, at first order in w: under a load above the sleeper the Timoshenko rail's slope jumps
    # (w' = theta + Q / kGA, Q jumps by the load), so the pad's layer sees a deflection |x| F / (2 kGA) across
    # it. Measured at 100 Hz-3 kHz: 0.15 % at 1 mm, 0.015 % at 0.1 mm. Asserted: below 0.3 % at 1 mm, and the
    # difference halving (within 10 %) with w; a 150 mm pad visibly differs (> 5 %).
    f = np.array([100.0, 300.0, 940.0, 3000.0])
    x = np.array([4 * 0.65, 4.5 * 0.65])

    def receptance(width):
        return track_receptance(assemble_track(_track(width), 16), f, x[0], x)

    point = receptance(0.0)
    errors = [np.max(np.abs(receptance(w) - point) / np.abs(point)) for w in (0.002, 0.001)]
    assert errors[1] < 3e-3
    assert errors[0] / errors[1] == pytest.approx(2.0, rel=0.1)
    assert np.max(np.abs(receptance(0.15) / point - 1)) > 0.05


def test_pad_width_keeps_the_matrices_symmetric_and_banded_and_is_checked():
    model = assemble_track(_track(0.15), 64)
    for matrix in (model.K, model.C, model.M):
        assert abs(matrix - matrix.T).max() <= 1e-9 * abs(matrix).max()
    coo = model.K.tocoo()
    assert np.max(np.abs(coo.row - coo.col)) == model.half_bandwidth > 4  # the band is as wide as needed
    assert assemble_track(_track(0.0), 64).half_bandwidth == 4
    with pytest.raises(WheelrailError, match="pad_width"):
        SupportParameters(pad_width=-0.01)
    with pytest.raises(WheelrailError, match="pad_width"):
        SupportParameters(pad_width=0.3, sleeper_spacing=0.5)  # over half the spacing: it would reach the next pad


def test_a_sub_nanometre_pad_is_the_point_support():
    # --pad-width-mm 1e-308 (accepted: 0 to 300 mm) vanished around the sleepers (or overflowed
    # k_P / w) and left a singular track. A pad narrower than 1 nm is the point support.
    point = assemble_track(_track(0.0, n_bays=70))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        tiny = assemble_track(_track(1e-311, n_bays=70))
    for name in ("K", "M", "C"):
        assert (getattr(tiny, name) != getattr(point, name)).nnz == 0, name
