"""The track's resonances (``core.track.resonances``): named by the infinite periodic track's mode shapes, found at
the finite track's receptance peaks, against the paper's 943 Hz, closed-form estimates and every accepted track."""

import math
import warnings
from dataclasses import replace

import numpy as np
import pytest
import scipy.linalg

from wheelrail.core.inputs.declared import inputs_of
from wheelrail.core.inputs.ranges import ACCEPTED
from wheelrail.core.parameters import RailParameters, SupportParameters, TrackParameters
from wheelrail.core.track import RESONANCE_KINDS, assemble_track, receptance_peaks, track_receptance
from wheelrail.core.track.resonances import named_band_edges

PAPER = TrackParameters()


def _track(key: str, value: float, base: TrackParameters = PAPER) -> TrackParameters:
    """``base`` with one declared track input (``core.inputs.declared``, group "track") set to ``value`` (SI)."""
    (entry,) = [e for e in inputs_of("track") if e.key == key]
    part, field = entry.path.split(".")[1:]
    if part == "rail":
        return replace(base, rail=replace(base.rail, **{field: value}))
    if part == "lateral":  # the lateral rail's supports (track.lateral): the vertical resonances must not mind them
        return replace(base, lateral=replace(base.lateral, **{field: value}))
    return replace(base, support=replace(base.support, **{field: value}))


def _timoshenko_pinned_pinned(rail: RailParameters, span: float) -> float:
    """First natural frequency of a simply supported Rayleigh-Timoshenko span, Hz: the lower root in w^2 of
    EI k^4 - (m' + (EI m' / kGA + rho I) k^2) w^2 + (rho I m' / kGA) w^4 = 0 at k = pi / span."""
    EI, kGA, m, rI = rail.bending_stiffness, rail.shear_stiffness, rail.mass_per_length, rail.rotary_inertia_per_length
    k = math.pi / span
    a, b, c = rI * m / kGA, m + (EI * m / kGA + rI) * k**2, EI * k**4
    return math.sqrt((b - math.sqrt(b * b - 4 * a * c)) / (2 * a)) / (2 * math.pi)


def _locally_reacting(track: TrackParameters) -> tuple[float, float]:
    """The two natural frequencies of the rail (m' per metre) on pads over sleepers on ballast, each smeared
    along the track (per metre: k_P / L, m_S / L, k_B / L), Hz: the continuously supported track's cut-ons."""
    sup, L = track.support, track.support.sleeper_spacing
    kp, kb = sup.pad_stiffness / L, sup.ballast_stiffness / L
    K = np.array([[kp, -kp], [-kp, kp + kb]])
    M = np.diag([track.rail.mass_per_length, sup.sleeper_mass / L])
    return tuple(np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True)) / (2 * math.pi))


def test_paper_pinned_pinned_frequency_943_hz():
    peaks = receptance_peaks(assemble_track(PAPER))
    # Paper section 2.2: "the pinned-pinned resonance ... occurs at 943 Hz for the current parameters". The same
    # track in the same FE model (Nielsen & Igeland's, 16 elements per bay): within 1 % (the finite, 70-bay track
    # and the pads' damping move the peak by a few Hz; measured 941.0 Hz)
    assert peaks["pinned_pinned"].frequency_hz == pytest.approx(943.0, rel=0.01)
    # its band edge, the infinite periodic track's, is the simply supported span's to 0.1 % (the point supports are
    # the mode's nodes: the pads and ballast do not enter)
    assert peaks["pinned_pinned"].band_edge_hz == pytest.approx(_timoshenko_pinned_pinned(PAPER.rail, 0.65), rel=1e-3)
    # the support resonances where the paper's track has them (docs/physics.md: 111 and 285 Hz): each below its
    # undamped band edge (the pads' and the ballast's damping lower a displacement peak)
    assert 100 < peaks["sleeper_on_ballast"].frequency_hz < peaks["sleeper_on_ballast"].band_edge_hz
    assert 270 < peaks["rail_on_pad"].frequency_hz < peaks["rail_on_pad"].band_edge_hz


@pytest.mark.parametrize(
    ("changes", "expected_hz"),
    [
        # A damped rail (loss factor 0.05) was once given 700 Hz, the end of its search window. The
        # damping widens the peak and moves it by under 0.5 %: within 1 % of the undamped track's.
        ({"rail_loss_factor": 0.05}, 943.0),
        ({"rail_loss_factor": 0.05, "sleeper_spacing": 0.6}, _timoshenko_pinned_pinned(PAPER.rail, 0.6)),
        ({"rail_loss_factor": 0.1}, 943.0),
        # 0.9 m sleepers: the pinned-pinned mode at 545 Hz, where the old fixed window took it for the rail-on-pad
        ({"sleeper_spacing": 0.9}, _timoshenko_pinned_pinned(PAPER.rail, 0.9)),
    ],
)
def test_pinned_pinned_is_found_where_it_is(changes, expected_hz):
    track = PAPER
    for key, value in changes.items():
        track = _track(key, value, track)
    peaks = receptance_peaks(assemble_track(track))
    # the finite damped track's peak within 1 % of the simply supported span's frequency (1 070 Hz on 0.6 m
    # sleepers, 545 Hz on 0.9 m): the supports sit at the mode's nodes
    assert peaks["pinned_pinned"].frequency_hz == pytest.approx(expected_hz, rel=0.01)
    for kind in ("sleeper_on_ballast", "rail_on_pad"):  # no support resonance is the pinned-pinned peak again
        found = peaks[kind].frequency_hz
        assert found is None or abs(found / expected_hz - 1) > 0.2, (kind, found)


def test_0_9_m_sleepers_name_the_545_hz_peak_pinned_pinned():
    peaks = receptance_peaks(assemble_track(_track("sleeper_spacing", 0.9)))
    assert peaks["pinned_pinned"].label == "pinned-pinned"
    assert peaks["pinned_pinned"].frequency_hz == pytest.approx(545, rel=0.01)
    # the rail-on-pad mode (its band edge at 296 Hz) has no peak of its own above a sleeper on this track: said so
    rail = peaks["rail_on_pad"]
    assert rail.frequency_hz is None and "not resolved" in rail.reason and f"{rail.band_edge_hz:.0f} Hz" in rail.reason
    assert rail.as_dict()["frequency_hz"] is None and rail.as_dict()["reason"] == rail.reason


@pytest.mark.parametrize(
    "changes",
    [{}, {"pad_stiffness": 10e6}, {"pad_stiffness": 3000e6}, {"ballast_stiffness": 3000e6}, {"sleeper_mass": 20.0}],
    ids=["paper", "pads-10", "pads-3000", "ballast-3000", "sleeper-20"],
)
def test_band_edges_match_the_locally_reacting_support(changes):
    track = PAPER
    for key, value in changes.items():
        track = _track(key, value, track)
    named = named_band_edges(track)
    low, high = _locally_reacting(track)
    edges = sorted((named["sleeper_on_ballast"], named["rail_on_pad"]), key=lambda edge: edge.frequency_hz)
    # the rail's bending within a bay stiffens the bay-periodic modes: the lower within 5 %; the upper within 40 %
    # where a 3000 MN/m pad puts it near 1 kHz, the rail's own pinned-pinned range (the smeared model has no bay)
    assert edges[0].frequency_hz == pytest.approx(low, rel=0.05)
    assert edges[1].frequency_hz == pytest.approx(high, rel=0.4 if high > 700 else 0.05)
    # the names follow the springs: the sleeper-on-ballast mode strains the ballast more than the rail-on-pad one
    assert named["sleeper_on_ballast"].ballast_share > named["rail_on_pad"].ballast_share


def _accepted_values(key: str) -> list[float]:
    """Each track input's accepted minimum and maximum, two values between, and a tiny positive value where 0
    is accepted (a pad 1e-311 m wide, a loss factor of 1e-300)."""
    accepted = ACCEPTED[key]
    low, high = accepted.minimum, accepted.maximum
    between = np.geomspace(low, high, 4)[1:3] if low > 0 else [high / 10, high / 2]
    tiny = [1e-311] if low == 0 else []
    return [low, *tiny, *map(float, between), high]


SWEEP = [(entry.key, value) for entry in inputs_of("track") for value in _accepted_values(entry.key)]


@pytest.mark.parametrize(("key", "value"), SWEEP, ids=[f"{key}={value:.3g}" for key, value in SWEEP])
def test_every_accepted_track_gets_its_resonances(key, value):
    track = _track(key, value)
    model = assemble_track(track)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy warning leaks at an accepted value
        peaks = receptance_peaks(model)
    assert list(peaks) == list(RESONANCE_KINDS)
    for peak in peaks.values():
        assert math.isfinite(peak.band_edge_hz) and peak.band_edge_hz > 0
        if peak.frequency_hz is None:
            assert "not resolved" in peak.reason
            continue
        # a peak is a local maximum of its receptance, never the end of a range: higher than 1 % either side
        x = (track.n_bays // 2) * track.support.sleeper_spacing
        if peak.kind == "pinned_pinned":
            x += track.support.sleeper_spacing / 2
        f = peak.frequency_hz
        level = np.abs(track_receptance(model, [f / 1.01, f, f * 1.01], x))
        assert level[1] > level[0] and level[1] > level[2], (peak.kind, f)
    # the pinned-pinned resonance of every accepted track shows at midspan, by the simply supported span's
    # frequency (within 2 %: the loss factor's widening and a 0.3 m pad's support of the span's ends)
    expected = _timoshenko_pinned_pinned(track.rail, track.support.sleeper_spacing)
    assert peaks["pinned_pinned"].frequency_hz == pytest.approx(expected, rel=0.02)


@pytest.mark.slow
@pytest.mark.parametrize(("key", "value"), SWEEP, ids=[f"{key}={value:.3g}" for key, value in SWEEP])
def test_every_accepted_track_integrates_its_green_functions(key, value):
    # The same sweep through the time domain (the Green's functions that run, track and noise --run use), on
    # reduced numerics (30 ms, 4 positions per bay, up to 160 km/h): no numpy warning, finite responses.
    from wheelrail.core.parameters import TrackNumerics
    from wheelrail.core.track import moving_from_stationary, stationary_track_response

    numerics = TrackNumerics(duration=0.03, positions_per_bay=4, max_speed=160 / 3.6)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        response = stationary_track_response(_track(key, value), numerics, use_cache=False)
        green = moving_from_stationary(response, 100 / 3.6)
        weights = green.weights(1e-3 / (100 / 3.6))
    assert np.all(np.isfinite(green.values)) and np.all(np.isfinite(weights))


def test_support_parameters_at_their_exact_limits():
    # every track input at its exact minimum and maximum at once (the round-off allowance of ``Accepted.check``)
    for bound in ("minimum", "maximum"):
        values = {e.key: getattr(ACCEPTED[e.key], bound) for e in inputs_of("track")}
        values["pad_width"] = min(values["pad_width"], 0.5 * values["sleeper_spacing"])
        track = PAPER
        for key, value in values.items():
            track = _track(key, value, track)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            peaks = receptance_peaks(assemble_track(track))
        assert peaks["pinned_pinned"].band_edge_hz > 0
        assert isinstance(track.support, SupportParameters)
