"""Disk cache of the track's Green's functions: keyed, atomic, corrupt and stale entries rebuilt."""

import dataclasses

import numpy as np
import pytest

from wheelrail.core import track
from wheelrail.core.files import cache
from wheelrail.core.parameters import TrackNumerics, TrackParameters

SMALL = TrackNumerics(duration=0.005, positions_per_bay=2, max_speed=100 / 3.6)
# a short track (20 bays, not 70): these tests check the cache's keys, files and reports, not the track's physics
COARSE = TrackParameters(n_bays=20)


def _fresh(numerics=SMALL, parameters=COARSE):
    track.clear_memory()
    response = track.stationary_track_response(parameters, numerics)
    cache.wait_for_writes()  # its entry is written in the background; these tests read and edit the file
    return response


def test_cache_lives_where_the_environment_says(tmp_path, monkeypatch):
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    response = _fresh()
    assert response.cache_path.startswith(str(tmp_path))
    assert list(tmp_path.glob("*.tmp")) == []  # atomic write leaves no temporary file
    again = _fresh()
    assert again.cache_path == response.cache_path
    np.testing.assert_array_equal(again.data, response.data)


def test_key_covers_every_parameter():
    base = track.track_key(TrackParameters(), SMALL)
    changed = [
        track.track_key(dataclasses.replace(TrackParameters(), n_bays=71), SMALL),
        track.track_key(
            TrackParameters(support=dataclasses.replace(TrackParameters().support, pad_damping=17e3)), SMALL
        ),
        track.track_key(TrackParameters(), dataclasses.replace(SMALL, time_step=4e-6)),
        track.track_key(TrackParameters(), dataclasses.replace(SMALL, max_speed=30.0)),
    ]
    assert len({base, *changed}) == 5


def test_a_sub_nanometre_pad_shares_the_point_supports_entry():
    # --pad-width-mm 1e-308 is the point support (track.fe.POINT_PAD_WIDTH): its responses are the point
    # support's, so it reads the point support's 208 MB entry rather than computing and storing its own
    def key(width):
        return track.track_key(
            TrackParameters(support=dataclasses.replace(TrackParameters().support, pad_width=width)), SMALL
        )

    assert key(1e-308) == key(0.0) == track.track_key(TrackParameters(), SMALL)
    assert key(0.05) != key(0.0) and key(1e-9) != key(0.0)


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
    key = track.track_key(COARSE, SMALL)
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
        "from wheelrail.core.files import cache\n"
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
    mine = tmp_path / f".wheelrail-track-wedge-{'a' * 24}.npz.0123abcd.{cache.writer()}.tmp"  # this process: alive
    elsewhere = tmp_path / f".wheelrail-track-wedge-{'b' * 24}.npz.0123abcd.otherhost-1.tmp"  # judged by age
    for path in (mine, elsewhere):
        path.write_bytes(b"partial")
    assert cache.remove_stale_temporaries(tmp_path) == []
    later = mine.stat().st_mtime + cache.STALE_TEMPORARY_S + 1
    assert sorted(cache.remove_stale_temporaries(tmp_path, now=later)) == sorted([mine, elsewhere])


def test_files_the_cache_did_not_write_are_never_removed(tmp_path, monkeypatch):
    # before: every lookup removed any hidden *.tmp older than an hour in the cache folder
    import os

    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    foreign = [tmp_path / name for name in (".x.tmp", ".entry.npz.def.tmp", ".notes.txt.0123abcd.host-1.tmp")]
    foreign.append(tmp_path / "unrelated-0123456789abcdef01234567.txt")
    old = cache.STALE_TEMPORARY_S * 10
    for path in foreign:
        path.write_bytes(b"someone else's")
        os.utime(path, (path.stat().st_mtime - old,) * 2)
    assert cache.load_entry("track-wedge", "0" * 64, ("data",)) is None
    cache.save_entry("track-wedge", "0" * 64, {"data": np.zeros(3)})
    cache.clear()
    assert all(path.read_bytes() == b"someone else's" for path in foreign)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in foreign)


@pytest.mark.parametrize("code", ["EROFS", "ENOSPC"])
def test_an_unwritable_cache_keeps_the_result_and_warns_once(tmp_path, monkeypatch, code):
    # before: a read-only or full folder aborted the run after the computation (bare [Errno 30/28])
    import errno
    import os

    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    good = _fresh()
    (tmp_path / good.cache_path.split("/")[-1]).unlink()
    monkeypatch.setattr(cache, "_WARNED_UNWRITABLE", set())

    def refused(*args, **kwargs):
        raise OSError(getattr(errno, code), os.strerror(getattr(errno, code)))

    monkeypatch.setattr(np, "savez", refused)
    with pytest.warns(UserWarning, match="could not write the cache.*WHEELRAIL_CACHE_DIR") as caught:
        response = _fresh()
        assert cache.save_entry("wheel-foh", "1" * 64, {"phi": np.eye(2)}) is None  # the same folder: no new warning
    assert len([w for w in caught if "could not write" in str(w.message)]) == 1
    assert response.cache_path == ""
    np.testing.assert_array_equal(response.data, good.data)
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # no temporary left


def test_a_read_only_cache_folder_keeps_the_result(tmp_path, monkeypatch):
    import os

    if os.geteuid() == 0:
        pytest.skip("root writes into a read-only folder (the failure is simulated in the test above)")
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(cache, "_WARNED_UNWRITABLE", set())
    tmp_path.chmod(0o555)
    try:
        with pytest.warns(UserWarning, match="could not write the cache"):
            response = _fresh()
    finally:
        tmp_path.chmod(0o755)
    assert response.cache_path == "" and list(tmp_path.iterdir()) == []


def test_a_tampered_entry_is_rebuilt(tmp_path, monkeypatch):
    # before: an entry edited consistently (valid ZIP, right key, finite arrays) was trusted
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    good = _fresh()
    path = tmp_path / good.cache_path.split("/")[-1]
    with np.load(path) as data:
        arrays = {name: data[name] for name in data.files}
    arrays["data"] = arrays["data"] * np.float32(1.5)  # +3.5 dB on every Green's function
    with open(path, "wb") as handle:
        np.savez(handle, **arrays)
    with pytest.warns(UserWarning, match="digest"):
        rebuilt = _fresh()
    np.testing.assert_array_equal(rebuilt.data, good.data)
    # an entry without a digest (an earlier wheelrail's) is not trusted either
    del arrays["cache_digest"]
    with open(path, "wb") as handle:
        np.savez(handle, **arrays)
    with pytest.warns(UserWarning, match="no digest"):
        rebuilt = _fresh()
    np.testing.assert_array_equal(rebuilt.data, good.data)


@pytest.mark.parametrize("below", [False, True], ids=["file", "below-a-file"])
def test_a_cache_setting_naming_a_file_is_one_clear_error(tmp_path, monkeypatch, below):
    # before: WHEELRAIL_CACHE_DIR=a file gave a bare [Errno 17]
    from wheelrail.core.errors import WheelrailError

    afile = tmp_path / "afile"
    afile.write_text("x")
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(afile / "sub" if below else afile))
    with pytest.raises(WheelrailError, match="WHEELRAIL_CACHE_DIR=.*afile.*set WHEELRAIL_CACHE_DIR to a folder"):
        cache.load_entry("track-wedge", "0" * 64, ("data",))
    assert afile.read_text() == "x"


def _entry(kind: str, digit: str, megabytes: float, age_s: float):
    import os
    import time

    path = cache.save_entry(kind, digit * 64, {"data": np.zeros(int(megabytes * 1e6) // 8)})
    os.utime(path, (time.time() - age_s,) * 2)
    return path


def test_the_cache_is_bounded_least_recently_used_first(tmp_path, monkeypatch):
    # before: the cache grew without limit (208 MB per track)
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    monkeypatch.setenv("WHEELRAIL_CACHE_MAX_GB", "0.0035")  # 3.5 MB: three 1 MB entries and change
    oldest, middle, newest = (_entry("track-wedge", d, 1.0, age) for d, age in (("a", 300), ("b", 200), ("c", 100)))
    foreign = tmp_path / "notes-0123456789abcdef01234567.bin"
    foreign.write_bytes(b"x" * 2_000_000)
    assert cache.load_entry("track-wedge", "a" * 64, ("data",)) is not None  # used now: the newest use
    fourth = _entry("wheel-foh", "d", 1.0, 0)  # 4 MB of entries > 3.5 MB: the least recently used goes
    assert not middle.exists() and oldest.exists() and newest.exists() and fourth.exists() and foreign.exists()
    big = cache.save_entry("track-wedge", "e" * 64, {"data": np.zeros(5_000_000 // 8)})  # alone above the limit
    assert big.exists() and [entry.path for entry in cache.entries()] == [big]
    assert foreign.exists()  # never ours, never counted, never removed


@pytest.mark.parametrize("value", ["0", "-1", "nan", "inf", "abc", "1_0"])
def test_a_bad_cache_limit_is_one_clear_error(tmp_path, monkeypatch, value):
    from wheelrail.core.errors import WheelrailError

    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    monkeypatch.setenv("WHEELRAIL_CACHE_MAX_GB", value)
    with pytest.raises(WheelrailError, match="WHEELRAIL_CACHE_MAX_GB"):
        cache.save_entry("wheel-foh", "1" * 64, {"phi": np.eye(2)})


def test_an_entry_describes_what_it_holds(tmp_path, monkeypatch):
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    parameters = dataclasses.replace(COARSE, support=dataclasses.replace(COARSE.support, pad_stiffness=300e6))
    _fresh(parameters=parameters)
    (entry,) = cache.entries(describe=True)
    assert entry.kind == "track-wedge" and entry.meta["description"]["track"]["support"]["pad_stiffness"] == 300e6
    assert entry.meta["compute_s"] > 0 and entry.meta["work"] > 0


def integrating_phase(events) -> str:
    return next(phase for phase, _, _ in events if phase.startswith("integrating"))


def test_the_precompute_reports_its_phases(tmp_path, monkeypatch):
    # before: a cold first run showed "1 of 2" for minutes; the integration now reports per block
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    numerics = dataclasses.replace(SMALL, positions_per_bay=32)  # 2 blocks of 9 and 8 load positions
    events = []
    track.clear_memory()
    reported = track.stationary_track_response(COARSE, numerics, progress=lambda *event: events.append(event))
    phases = list(dict.fromkeys(phase.split(" (")[0] for phase, _, _ in events))
    assert phases == [
        "assembling the FE track",
        "loading the integration's compiled code",
        "integrating the track's impulse responses",
        "writing the cache entry",
    ]
    integrating = [(done, total) for phase, done, total in events if phase.startswith("integrating")]
    from wheelrail.core.track.stationary import column_blocks

    # at the start, then as each block of load positions ends (in parallel threads: the columns done add up);
    # positions 0 .. 16 integrated, 17 .. 31 their mirror images (stationary.mirror_plan)
    blocks = [end - first for first, end in column_blocks(17)]  # 9 and 8, ending in either order
    assert integrating in ([(0, 17), (blocks[0], 17), (17, 17)], [(0, 17), (blocks[1], 17), (17, 17)])
    assert "17 load positions x 1001 steps, the other 15 their mirror images" in integrating_phase(events)
    quiet = track.compute_stationary_response(COARSE, numerics)  # one call, no groups
    np.testing.assert_array_equal(reported.data, quiet.data)  # the same blocks, the same numbers
    # a second track: the cache knows how fast this machine integrates, so the phase carries an estimate
    events.clear()
    other = dataclasses.replace(COARSE, support=dataclasses.replace(COARSE.support, pad_stiffness=300e6))
    from wheelrail.core.track.progress import track_progress

    with track_progress(lambda *event: events.append(event)):
        track.clear_memory()
        track.stationary_track_response(other, numerics)
    assert any(phase.startswith("integrating") and ", about " in phase for phase, _, _ in events)


def test_a_cache_folder_that_cannot_be_created_keeps_the_result(tmp_path, monkeypatch):
    # before: a folder that could not be created (permission denied) aborted every lookup with a bare errno
    import pathlib

    target = tmp_path / "not-allowed"
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(target))
    monkeypatch.setattr(cache, "_WARNED_UNWRITABLE", set())
    real_mkdir = pathlib.Path.mkdir

    def refused(self, *args, **kwargs):
        if self == target:
            raise PermissionError(13, "Permission denied", str(self))
        return real_mkdir(self, *args, **kwargs)

    monkeypatch.setattr(pathlib.Path, "mkdir", refused)
    with pytest.warns(UserWarning, match="could not write the cache in .*not-allowed.*WHEELRAIL_CACHE_DIR"):
        response = _fresh()
    assert response.cache_path == "" and cache.entries() == [] and not target.exists()


def test_a_file_named_like_an_entry_is_not_removed_unless_the_cache_wrote_it(tmp_path, monkeypatch):
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    users = tmp_path / f"track-wedge-{'c' * 24}.npz"  # a user's own archive under an entry-like name
    np.savez(users, data=np.arange(3))
    notes = tmp_path / f"wheel-foh-{'d' * 24}.npz"
    notes.write_text("notes")
    renamed = tmp_path / f"track-wedge-{'e' * 24}.npz"  # an entry's copy under another key's name
    cache.save_entry("track-wedge", "f" * 64, {"data": np.zeros(3)}).rename(renamed)
    foreign = {path: path.read_bytes() for path in (users, notes, renamed)}
    mine = cache.save_entry("track-wedge", "0" * 64, {"data": np.zeros(3)})
    assert [entry.path for entry in cache.entries()] == [mine]
    assert cache.evict(0) == [mine]
    mine = cache.save_entry("track-wedge", "0" * 64, {"data": np.zeros(3)})
    assert cache.clear() == [mine]
    assert sorted(tmp_path.iterdir()) == sorted(foreign)
    assert all(path.read_bytes() == content for path, content in foreign.items())
