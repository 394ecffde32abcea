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
            TrackParameters(support=dataclasses.replace(TrackParameters().support, pad_damping=17e3)), SMALL
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
    raw[len(raw) // 2 : len(raw) // 2 + 64] = b"\x00" * 64  # flip bytes inside the stored arrays
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


@pytest.mark.parametrize(("offset", "value"), [(8, 0x01), (10, 99), (6, 0xFF)], ids=["encrypted", "method", "version"])
@pytest.mark.slow
def test_one_damaged_zip_header_byte_is_rebuilt(tmp_path, monkeypatch, offset, value):
    # one byte of the ZIP's central directory (flag, compression method, version needed) made
    # np.load raise RuntimeError ("encrypted") or NotImplementedError, which escaped the cache
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    good = _fresh()
    path = tmp_path / good.cache_path.split("/")[-1]
    raw = bytearray(path.read_bytes())
    raw[raw.index(b"PK\x01\x02") + offset] = value  # the first member's central directory record
    path.write_bytes(bytes(raw))
    with pytest.warns(UserWarning, match="unusable cache entry"):
        rebuilt = _fresh()
    np.testing.assert_array_equal(rebuilt.data, good.data)


def test_temporary_of_a_killed_writer_is_removed(tmp_path, monkeypatch):
    # a real kill -9 in the middle of writing an entry: the child blocks inside np.savez until killed
    import signal
    import subprocess
    import sys

    script = (
        "import sys, numpy as np\n"
        "from wheelrail.core import cache\n"
        "def blocked(handle, **arrays):\n"
        "    handle.write(b'x' * 1000); handle.flush(); print('writing', flush=True); sys.stdin.read()\n"
        "np.savez = blocked\n"
        "cache.save_entry('track-wedge', '0' * 64, {'data': np.zeros(3)})\n"
    )
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    child = subprocess.Popen([sys.executable, "-c", script], stdin=subprocess.PIPE, stdout=subprocess.PIPE)
    assert child.stdout.readline().strip() == b"writing"
    child.send_signal(signal.SIGKILL)
    child.wait()
    left = list(tmp_path.glob(".*.tmp"))
    assert len(left) == 1 and left[0].stat().st_size == 1000
    assert cache.load_entry("track-wedge", "0" * 64, ("data",)) is None  # a lookup cleans up
    assert list(tmp_path.glob(".*.tmp")) == []


def test_temporaries_of_live_writers_are_kept_until_stale(tmp_path):
    mine = tmp_path / f".entry.npz.abc.{cache._writer()}.tmp"  # this process: alive
    anonymous = tmp_path / ".entry.npz.def.tmp"  # no writer named (atomic_write's): judged by age only
    for path in (mine, anonymous):
        path.write_bytes(b"partial")
    assert cache.remove_stale_temporaries(tmp_path) == []
    later = mine.stat().st_mtime + cache.STALE_TEMPORARY_S + 1
    assert sorted(cache.remove_stale_temporaries(tmp_path, now=later)) == sorted([mine, anonymous])
