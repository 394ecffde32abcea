"""The per-speed cache of the moving Green's functions' weights (what a run reads of its track): the cached
weights are the very array the stationary responses give, read back without them."""

import numpy as np
import pytest

from wheelrail.core import track
from wheelrail.core.parameters import FOH_MAX_STEP, TrackNumerics

SMALL = TrackNumerics(duration=0.005, positions_per_bay=2, max_speed=100 / 3.6)
SPEED = 80 / 3.6  # m/s


def _direct(speed, time_step):
    return track.moving_green_functions(speed, None, SMALL, use_cache=False).weights(time_step)


@pytest.mark.parametrize("time_step", [1e-3 / SPEED, 2 * FOH_MAX_STEP])  # first-order hold; trapezoidal
def test_cached_weights_are_bit_identical_and_need_no_wedge(tmp_path, monkeypatch, time_step):
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    track._MEMORY.clear()
    expected = _direct(SPEED, time_step)
    first = track.moving_weights(SPEED, time_step, None, SMALL)
    # bit-identical (no tolerance): the entry holds the array the stationary responses gave
    np.testing.assert_array_equal(first, expected)
    entries = sorted(tmp_path.glob("track-weights-*.npz"))
    assert len(entries) == 1
    for wedge in tmp_path.glob("track-wedge-*.npz"):
        wedge.unlink()  # the second call must not need the stationary responses
    track._MEMORY.clear()
    again = track.moving_weights(SPEED, time_step, None, SMALL)
    np.testing.assert_array_equal(again, expected)
    assert list(tmp_path.glob("track-wedge-*.npz")) == []


def test_each_speed_and_step_has_its_own_entry(tmp_path, monkeypatch):
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    track._MEMORY.clear()
    a = track.moving_weights(SPEED, 1e-3 / SPEED, None, SMALL)
    b = track.moving_weights(1.25 * SPEED, 1e-3 / SPEED, None, SMALL)
    c = track.moving_weights(SPEED, 0.5e-3 / SPEED, None, SMALL)
    assert len(list(tmp_path.glob("track-weights-*.npz"))) == 3
    np.testing.assert_array_equal(b, _direct(1.25 * SPEED, 1e-3 / SPEED))
    np.testing.assert_array_equal(c, _direct(SPEED, 0.5e-3 / SPEED))
    assert not np.array_equal(a, b[:, : a.shape[1]])


def test_damaged_weights_entry_is_rebuilt(tmp_path, monkeypatch):
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    track._MEMORY.clear()
    good = track.moving_weights(SPEED, 1e-3 / SPEED, None, SMALL)
    (entry,) = tmp_path.glob("track-weights-*.npz")
    entry.write_bytes(b"not a zip file")
    with pytest.warns(UserWarning, match="unusable cache entry"):
        rebuilt = track.moving_weights(SPEED, 1e-3 / SPEED, None, SMALL)
    np.testing.assert_array_equal(rebuilt, good)


def test_prepare_run_reads_the_cached_weights(tmp_path, monkeypatch):
    from wheelrail.core.interaction import prepare_run

    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    track._MEMORY.clear()
    run = prepare_run("corrugated-rail", model="hertz", length=0.05, track_numerics=SMALL)
    np.testing.assert_array_equal(run.loop.weights, _direct(100 / 3.6, run.params.run.time_step))
