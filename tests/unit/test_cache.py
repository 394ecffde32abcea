"""Disk cache of the track's Green's functions: keyed, atomic, corrupt and stale entries rebuilt."""

import dataclasses

import numpy as np
import pytest

from wheelrail.core import cache, track
from wheelrail.core.parameters import TrackNumerics, TrackParameters

SMALL = TrackNumerics(duration=0.005, positions_per_bay=2, max_speed=100 / 3.6)


def _fresh(numerics=SMALL, parameters=None):
    track._MEMORY.clear()
    return track.stationary_track_response(parameters, numerics)


def test_cache_lives_where_the_environment_says(tmp_path, monkeypatch):
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    response = _fresh()
    assert response.cache_path.startswith(str(tmp_path))
    assert list(tmp_path.glob("*.tmp")) == []  # atomic write leaves no temporary file
    again = _fresh()
    assert again.cache_path == response.cache_path
    np.testing.assert_array_equal(again.data, response.data)


def test_key_covers_every_parameter():
    base = track._track_key(TrackParameters(), SMALL)
    changed = [
        track._track_key(dataclasses.replace(TrackParameters(), n_bays=71), SMALL),
        track._track_key(
            TrackParameters(support=dataclasses.replace(TrackParameters().support, pad_damping=1.0)), SMALL
        ),
        track._track_key(TrackParameters(), dataclasses.replace(SMALL, time_step=4e-6)),
        track._track_key(TrackParameters(), dataclasses.replace(SMALL, max_speed=30.0)),
    ]
    assert len({base, *changed}) == 5


def test_corrupt_entry_is_detected_and_rebuilt(tmp_path, monkeypatch):
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    good = _fresh()
    path = tmp_path / good.cache_path.split("/")[-1]
    raw = bytearray(path.read_bytes())
    raw[len(raw) // 2: len(raw) // 2 + 64] = b"\x00" * 64  # flip bytes inside the stored arrays
    path.write_bytes(bytes(raw))
    with pytest.warns(UserWarning, match="unusable cache entry"):
        rebuilt = _fresh()
    np.testing.assert_array_equal(rebuilt.data, good.data)
    path.write_bytes(b"not a zip file")
    with pytest.warns(UserWarning, match="unusable cache entry"):
        rebuilt = _fresh()
    np.testing.assert_array_equal(rebuilt.data, good.data)


def test_stale_entry_is_not_used(tmp_path, monkeypatch):
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    good = _fresh()
    key = track._track_key(TrackParameters(), SMALL)
    # an entry under the right file name but written for other parameters
    cache.save_entry("track-wedge", "0" * 64, {"data": np.zeros(3)})
    (tmp_path / cache.entry_path("track-wedge", "0" * 64).name).replace(cache.entry_path("track-wedge", key))
    with pytest.warns(UserWarning, match="stale"):
        rebuilt = _fresh()
    np.testing.assert_array_equal(rebuilt.data, good.data)
