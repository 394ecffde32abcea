"""The track's Newmark integration (``core/track/newmark.py``: the displacement recurrence, profile Cholesky
factor, row-stored matrices) against the three-vector form with band matrices it replaced
(``newmark_reference.py``), and the profile factor against LAPACK's band factor."""

from __future__ import annotations

import numpy as np
import pytest
from newmark_reference import reference_responses
from scipy.linalg import cholesky_banded

from wheelrail.core.parameters import RailParameters, SupportParameters, TrackParameters
from wheelrail.core.track.fe import assemble_track, to_upper_band
from wheelrail.core.track.newmark import profile_cholesky
from wheelrail.core.track.stationary import integrate_responses


def _model(pad_width: float = 0.0, loss_factor: float = 0.0):
    track = TrackParameters(
        support=SupportParameters(pad_width=pad_width), rail=RailParameters(loss_factor=loss_factor), n_bays=8
    )
    return assemble_track(track, 8, refined=(4, 2, 32))


@pytest.mark.parametrize(
    ("pad_width", "loss_factor", "impulse"),
    [(0.0, 0.0, True), (0.0, 0.0, False), (0.15, 0.0, True), (0.0, 0.02, True), (0.15, 0.05, False)],
)
def test_recurrence_reproduces_the_three_vector_newmark_scheme(pad_width, loss_factor, impulse):
    # Known answer: the same sequence u_k in exact arithmetic (module docstring of core/track/newmark.py); in
    # floating point within 1e-9 of the largest response (measured: ~1e-13), over 600 steps of 5 us (3 ms: the
    # pad's and the sleeper's motion under way) for loads above a sleeper, at midspan and near the next sleeper.
    model = _model(pad_width, loss_factor)
    L = model.params.support.sleeper_spacing
    x_e = 4 * L + np.array([0.0, 0.5, 0.9]) * L
    dt, n_steps = 5e-6, 600
    loads = np.stack([model.load_vector(x) for x in x_e], axis=1)
    expected = reference_responses(model, loads, dt, n_steps, impulse=impulse)
    nodes = np.arange(len(model.node_x))
    n_nodes = len(nodes)
    counts = np.full((len(x_e), n_steps), n_nodes, dtype=np.int64)
    offsets = (np.arange(len(x_e) * n_steps, dtype=np.int64) * n_nodes).reshape(len(x_e), n_steps)
    out = integrate_responses(
        model, x_e, dt, n_steps, 1, np.tile(nodes, (len(x_e), 1)), counts, offsets, impulse=impulse
    )
    got = out.reshape(len(x_e), n_steps, n_nodes, 2)
    want = np.stack([expected[:, model.w_dof, :], expected[:, model.theta_dof, :]], axis=-1).transpose(2, 0, 1, 3)
    for part in range(2):
        scale = np.max(np.abs(want[..., part]))
        assert scale > 0
        assert np.max(np.abs(got[..., part] - want[..., part])) <= 1e-9 * scale


@pytest.mark.parametrize("pad_width", [0.0, 0.15])
def test_profile_factor_is_lapacks_band_factor(pad_width):
    # Known answer: the Cholesky factor is unique, so the profile factor's entries are LAPACK's band factor's
    # (round-off), and its profile is no longer than the band: the rail's columns stay short with a wide pad.
    model = _model(pad_width)
    keff = model.K + 8e5 * model.C + 1.6e11 * model.M
    u = model.half_bandwidth
    band = cholesky_banded(to_upper_band(keff, u))
    factor = profile_cholesky(keff)
    n = model.n_dof
    dense = np.zeros((n, n))
    for j in range(n):
        rows = np.arange(factor.first[j], j)
        dense[rows, j] = factor.off[factor.start[j] : factor.start[j] + len(rows)]
        dense[j, j] = 1.0 / factor.inverse_diagonal[j]
    from_band = np.zeros((n, n))
    for d in range(u + 1):
        j = np.arange(d, n)
        from_band[j - d, j] = band[u - d, d:]
    np.testing.assert_allclose(dense, from_band, rtol=0, atol=1e-12 * np.max(np.abs(from_band)))
    profile = len(factor.off) + n
    assert profile <= (u + 1) * n
    if pad_width > 0:
        assert profile < 0.6 * (u + 1) * n
    x = np.random.default_rng(1).standard_normal((n, 3))
    np.testing.assert_allclose(keff @ factor.solve(x), x, rtol=0, atol=1e-9 * np.max(np.abs(x)))
