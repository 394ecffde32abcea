"""The per-speed cache of what a run reads of its track (the moving Green's functions and their weights at
the run's step): the very arrays the stationary responses give, read back without them."""

import os

import numpy as np
import pytest

from wheelrail.core import track
from wheelrail.core.files import cache
from wheelrail.core.parameters import FOH_MAX_STEP, TrackNumerics, TrackParameters

SMALL = TrackNumerics(duration=0.005, positions_per_bay=2, max_speed=100 / 3.6)
SPEED = 80 / 3.6  # m/s


@pytest.fixture(scope="module")
def response():
    return track.stationary_track_response(TrackParameters(), SMALL)  # from the tests' cache once computed


@pytest.fixture
def cache_with_wedge(tmp_path, monkeypatch, response):
    """An empty cache but for the stationary responses of SMALL (as after their one-off precompute)."""
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    track.clear_memory()
    wedge = {name: getattr(response, name) for name in ("data", "counts", "offsets", "stored_x")}
    key = track.track_key(TrackParameters(), SMALL)
    cache.save_entry("track-wedge", key, {**wedge, "excitation_positions": response.excitation_positions})
    yield tmp_path
    track.clear_memory()


def _direct(response, speed, time_step, method="auto"):
    return track.moving_from_stationary(response, speed).weights(time_step, method=method)


@pytest.mark.parametrize("time_step", [1e-3 / SPEED, 2 * FOH_MAX_STEP])  # first-order hold; trapezoidal
def test_cached_weights_are_bit_identical_and_need_no_wedge(cache_with_wedge, response, time_step):
    expected = _direct(response, SPEED, time_step)
    first = track.moving_weights(SPEED, time_step, None, SMALL)
    # bit-identical (no tolerance): the entry holds the array the stationary responses gave
    np.testing.assert_array_equal(first, expected)
    assert len(list(cache_with_wedge.glob("track-weights-*.npz"))) == 1
    assert len(list(cache_with_wedge.glob("track-moving-*.npz"))) == 1
    for wedge in cache_with_wedge.glob("track-wedge-*.npz"):
        wedge.unlink()  # from now on nothing may need the stationary responses
    track.clear_memory()
    np.testing.assert_array_equal(track.moving_weights(SPEED, time_step, None, SMALL), expected)
    green = track.moving_green_functions(SPEED, None, SMALL)
    np.testing.assert_array_equal(green.values, track.moving_from_stationary(response, SPEED).values)
    assert green.time_step == response.time_step
    assert list(cache_with_wedge.glob("track-wedge-*.npz")) == []


def test_each_speed_step_and_method_has_its_own_entry(cache_with_wedge, response):
    dt = 1e-3 / SPEED
    a = track.moving_weights(SPEED, dt, None, SMALL)
    b = track.moving_weights(1.25 * SPEED, dt, None, SMALL)
    c = track.moving_weights(SPEED, 0.5 * dt, None, SMALL)
    d = track.moving_weights(SPEED, dt, None, SMALL, method="trapezoidal")
    assert len(list(cache_with_wedge.glob("track-weights-*.npz"))) == 4
    assert len(list(cache_with_wedge.glob("track-moving-*.npz"))) == 2
    np.testing.assert_array_equal(b, _direct(response, 1.25 * SPEED, dt))
    np.testing.assert_array_equal(c, _direct(response, SPEED, 0.5 * dt))
    np.testing.assert_array_equal(d, _direct(response, SPEED, dt, "trapezoidal"))
    assert not np.array_equal(a, b) and not np.array_equal(a, d)


def test_damaged_entries_are_rebuilt(cache_with_wedge):
    good = track.moving_weights(SPEED, 1e-3 / SPEED, None, SMALL)
    for entry in [*cache_with_wedge.glob("track-weights-*.npz"), *cache_with_wedge.glob("track-moving-*.npz")]:
        entry.write_bytes(b"not a zip file")
    with pytest.warns(UserWarning, match="unusable cache entry"):
        rebuilt = track.moving_weights(SPEED, 1e-3 / SPEED, None, SMALL)
    np.testing.assert_array_equal(rebuilt, good)


def test_prepare_run_reads_the_cached_weights(cache_with_wedge, response):
    from wheelrail.core.engine import prepare_run

    run = prepare_run("corrugated-rail", model="hertz", length=0.05, track_numerics=SMALL)
    np.testing.assert_array_equal(run.loop.weights, _direct(response, 100 / 3.6, run.params.run.time_step))


def test_weights_read_again_come_from_memory_while_their_entry_is_unchanged(cache_with_wedge, monkeypatch):
    # a study's runs read the same weights again and again: the file and its digest once, then the array in memory
    from wheelrail.core.track import moving

    reads = []
    read = moving._cached_array
    monkeypatch.setattr(
        moving, "_cached_array", lambda kind, *args: reads.append(kind == "track-weights") or read(kind, *args)
    )
    dt = 1e-3 / SPEED
    first = track.moving_weights(SPEED, dt, None, SMALL)  # computed from the wedge and written
    assert track.moving_weights(SPEED, dt, None, SMALL) is first and sum(reads) == 1
    (entry,) = cache_with_wedge.glob("track-weights-*.npz")
    stat = entry.stat()
    os.utime(entry, ns=(stat.st_atime_ns, stat.st_mtime_ns + 10**9))  # touched: read again
    again = track.moving_weights(SPEED, dt, None, SMALL)
    assert sum(reads) == 2 and again is not first
    np.testing.assert_array_equal(again, first)
    entry.unlink()
    assert track.moving_weights(SPEED, dt, None, SMALL) is not again and sum(reads) == 3
