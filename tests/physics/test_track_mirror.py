"""The track's integration on its mirror symmetry (``stationary.mirror_plan``): on a model that is its own mirror
image about the central bay's middle, the loads past the middle are read from their images' columns."""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.parameters import RailParameters, SupportParameters, TrackNumerics, TrackParameters
from wheelrail.core.track import stationary
from wheelrail.core.track.fe import assemble_track

NUMERICS = TrackNumerics(
    elements_per_bay=8, refined_elements_per_bay=16, positions_per_bay=8, duration=0.0015, max_speed=100 / 3.6
)


def _track(pad_width: float = 0.0, loss_factor: float = 0.0, n_bays: int = 10) -> TrackParameters:
    return TrackParameters(
        support=SupportParameters(pad_width=pad_width), rail=RailParameters(loss_factor=loss_factor), n_bays=n_bays
    )


def _integrated(model, numerics: TrackNumerics, mirror: bool, impulse: bool = True) -> np.ndarray:
    _, x_e, _ = stationary.excitation_nodes(model, numerics)
    t, n_steps = stationary.stored_times(numerics)
    nodes, _, counts, offsets = stationary.stored_nodes(model, numerics, x_e, numerics.max_speed, t)
    dt, stride = numerics.time_step, numerics.store_every
    was = stationary.MIRROR_SYMMETRY
    stationary.MIRROR_SYMMETRY = mirror
    try:
        return stationary.integrate_responses(model, x_e, dt, n_steps, stride, nodes, counts, offsets, impulse=impulse)
    finally:
        stationary.MIRROR_SYMMETRY = was


@pytest.mark.parametrize(
    ("pad_width", "loss_factor", "impulse"),
    [(0.0, 0.0, True), (0.15, 0.0, True), (0.0, 0.02, False), (0.15, 0.05, True)],
)
def test_mirrored_integration_is_the_full_one(pad_width, loss_factor, impulse):
    # Known answer: the model is its own mirror image (one more bay than the 10 asked for: 5 on either side of the
    # central bay), so position k's response behind it is position P - k's ahead, theta negated; in floating point
    # they differ by round-off only (the factor's DOFs are not numbered symmetrically). Positions 0 (a sleeper,
    # whose image is the next bay's) and P / 2 (mid-bay, its own) are integrated; 1 .. P / 2 - 1 give P - k too.
    model = stationary.numerics_model(_track(pad_width, loss_factor), NUMERICS)
    assert stationary.model_bays(model.params) == 11 and model.params.n_bays == 11
    columns, source, sign, _ = stationary.mirror_plan(model, stationary.excitation_nodes(model, NUMERICS)[1])
    assert columns.tolist() == [0, 1, 2, 3, 4]
    assert source.tolist() == [0, 1, 2, 3, 4, 3, 2, 1] and sign.tolist() == [1, 1, 1, 1, 1, -1, -1, -1]
    assert stationary.integrated_positions(_track(pad_width, loss_factor), NUMERICS) == 5
    full = _integrated(model, NUMERICS, mirror=False, impulse=impulse)
    mirrored = _integrated(model, NUMERICS, mirror=True, impulse=impulse)
    for part in range(2):
        scale = np.max(np.abs(full[:, part]))
        assert scale > 0
        assert np.max(np.abs(mirrored[:, part] - full[:, part])) <= 1e-12 * scale


def test_an_asymmetric_model_integrates_every_position():
    # refined bays 2..5 around a central bay 3 of 7: not symmetric, so nothing is mirrored (and the result is the
    # full integration's, bit for bit)
    numerics = TrackNumerics(**{**NUMERICS.__dict__, "refined_bays": 3})
    model = stationary.numerics_model(_track(n_bays=7), numerics)
    x_e = stationary.excitation_nodes(model, numerics)[1]
    columns, source, sign, _ = stationary.mirror_plan(model, x_e)
    assert columns.tolist() == list(range(8)) and np.all(sign == 1)
    assert stationary.integrated_positions(_track(n_bays=7), numerics) == 8
    np.testing.assert_array_equal(_integrated(model, numerics, mirror=True), _integrated(model, numerics, mirror=False))


def test_the_model_has_as_many_bays_on_either_side_of_the_central_bay():
    for n_bays, expected in ((70, 71), (71, 71), (4, 5)):
        model = stationary.numerics_model(_track(n_bays=n_bays), NUMERICS)
        assert model.params.n_bays == expected
        L = model.params.support.sleeper_spacing
        assert (n_bays // 2) * L == pytest.approx((model.node_x[-1] - L) / 2)
        x = model.node_x
        np.testing.assert_allclose(x + x[::-1], x[-1], rtol=0, atol=1e-9)
        assert len(x) == stationary._node_count(_track(n_bays=n_bays), NUMERICS)
    assert assemble_track(_track(n_bays=70)).params.n_bays == 70  # the track's own model (receptances) as given


@pytest.mark.parametrize(
    ("changes", "n_bays", "integrated"),
    [({}, 10, 5), ({"refined_bays": 3}, 7, 8), ({"refined_bays": 3, "refined_elements_per_bay": 8}, 10, 5)],
)
def test_the_precompute_estimate_reads_the_plan_of_the_mesh(changes, n_bays, integrated, monkeypatch):
    # integrated_positions (the work a precompute's estimate scales with) is mirror_plan's plan on numerics_model's
    # mesh, not a second decision from the numerics: refined bays as fine as the others give a uniform mesh, its
    # own mirror image whatever refined_bays says
    numerics = TrackNumerics(**{**NUMERICS.__dict__, **changes})
    model = stationary.numerics_model(_track(n_bays=n_bays), numerics)
    np.testing.assert_array_equal(stationary.numerics_mesh(_track(n_bays=n_bays), numerics), model.node_x)
    columns = stationary.mirror_plan(model, stationary.excitation_nodes(model, numerics)[1])[0]
    assert stationary.integrated_positions(_track(n_bays=n_bays), numerics) == len(columns) == integrated
    monkeypatch.setattr(stationary, "MIRROR_SYMMETRY", False)  # every load integrated: so the estimate says
    assert stationary.integrated_positions(_track(n_bays=n_bays), numerics) == 8
