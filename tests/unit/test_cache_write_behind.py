"""A new track's cache entry is written in the background: the caller has the responses at once, this process's
readers of the folder wait for the write, the process exits only once it is on disk, and a failure is one line."""

import subprocess
import sys
import threading

import numpy as np
import pytest

from wheelrail.core import track
from wheelrail.core.files import cache
from wheelrail.core.parameters import TrackNumerics, TrackParameters

SMALL = TrackNumerics(duration=0.005, positions_per_bay=2, max_speed=100 / 3.6)
COARSE = TrackParameters(n_bays=20)  # the cache's files and threads are checked here, not the track's physics
WEDGE = ("data", "counts", "offsets", "stored_x", "excitation_positions")


def _held_writes(monkeypatch, release: threading.Event) -> list[str]:
    """np.savez made to wait for ``release`` in a writer thread (and to refuse the caller's thread); returns the
    names of the threads that wrote."""
    real = np.savez
    writers = []

    def held(handle, **arrays):
        writers.append(threading.current_thread().name)
        if threading.current_thread() is threading.main_thread():
            raise AssertionError("the entry is written in the caller's thread")
        release.wait()
        real(handle, **arrays)

    monkeypatch.setattr(np, "savez", held)
    return writers


def test_a_new_track_is_returned_before_its_entry_is_written(tmp_path, monkeypatch):
    # before: the caller waited for the SHA-256 and the write of the entry (208 MB, ~1 s on the default track)
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    returned = threading.Event()
    writers = _held_writes(monkeypatch, returned)
    track.clear_memory()
    response = track.stationary_track_response(COARSE, SMALL)  # the write waits for this call to return
    key = track.track_key(COARSE, SMALL)
    assert not response.cache_entry.done()
    assert [p.name for p in tmp_path.iterdir() if p.suffix == ".npz"] == []  # only its temporary so far
    returned.set()
    arrays = cache.load_entry("track-wedge", key, WEDGE)  # waits for this process's write of it
    assert arrays is not None
    np.testing.assert_array_equal(arrays["data"], response.data)
    assert response.cache_path == str(cache.entry_path("track-wedge", key)) and response.cache_entry.done()
    assert writers and writers[0].startswith("wheelrail-cache-write")
    assert list(tmp_path.glob(".*.tmp")) == []


def test_the_folders_readers_wait_for_the_writes_under_way(tmp_path, monkeypatch):
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    returned = threading.Event()
    _held_writes(monkeypatch, returned)
    track.clear_memory()
    track.stationary_track_response(COARSE, SMALL)
    returned.set()
    (entry,) = cache.entries(describe=True)  # listed once written, with its description
    assert entry.kind == "track-wedge" and entry.meta["compute_s"] > 0
    track.clear_memory()
    assert track.stationary_track_response(COARSE, SMALL).cache_entry == str(entry.path)  # read back, not written
    assert cache.clear() == [entry.path]


def test_an_error_in_the_writer_thread_is_one_warning(tmp_path, monkeypatch):
    # an error that is no OSError (e.g. out of memory) would print the thread's traceback
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))

    def failing(handle, **arrays):
        raise MemoryError("no memory for the digest")

    monkeypatch.setattr(np, "savez", failing)
    track.clear_memory()
    with pytest.warns(UserWarning, match="could not write the cache entry .*track-wedge.*no memory for the digest"):
        response = track.stationary_track_response(COARSE, SMALL)
        assert response.cache_path == ""  # the write ended, with nothing written
    assert list(tmp_path.iterdir()) == []


WRITE_AT_EXIT = """
import threading, numpy as np
from wheelrail.core import track
from wheelrail.core.parameters import TrackNumerics, TrackParameters
real = np.savez
def at_exit(handle, **arrays):
    threading.main_thread().join()  # the main thread has finished: only the interpreter's shutdown is left
    real(handle, **arrays)
np.savez = at_exit
track.stationary_track_response(TrackParameters(n_bays=20), TrackNumerics(duration=0.005, positions_per_bay=2,
                                max_speed=100 / 3.6))
"""


def test_the_process_exits_once_the_entry_is_written(tmp_path, monkeypatch):
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    done = subprocess.run([sys.executable, "-c", WRITE_AT_EXIT], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
    key = track.track_key(COARSE, SMALL)
    arrays = cache.load_entry("track-wedge", key, WEDGE)
    assert arrays is not None and arrays["data"].shape == (int(arrays["counts"].sum()), 2)
    assert list(tmp_path.glob(".*.tmp")) == []
