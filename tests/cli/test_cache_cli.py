"""``wheelrail cache`` (list, clear), the cache settings' errors, multi-file outputs and the precompute's account."""

import errno
import io
import json
import os

import numpy as np
import pytest

from wheelrail.core.files import cache


@pytest.fixture
def folder(tmp_path, monkeypatch):
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    return tmp_path


def _track_entry():
    """A small track-wedge entry described as a track (what stationary_track_response writes)."""
    key = cache.cache_key(
        "track-wedge",
        {
            "track": {
                "support": {
                    "pad_stiffness": 3e8,
                    "sleeper_mass": 125.0,
                    "sleeper_spacing": 0.6,
                    "ballast_stiffness": 1.4e8,
                },
                "n_bays": 70,
            }
        },
    )
    return cache.save_entry("track-wedge", key, {"data": np.zeros(250_000)}, info={"compute_s": 20.0})


def test_cache_lists_its_entries(folder, cli):
    track = _track_entry()
    wheel = cache.save_entry("wheel-foh", "1" * 64, {"phi": np.eye(4)})
    (folder / ".someone-elses.tmp").write_text("x")
    code, out, err = cli("cache", "--json")
    assert code == 0 and err == ""
    listing = json.loads(out)
    assert listing["folder"] == str(folder) and listing["limit_bytes"] == 4_000_000_000
    assert [entry["file"] for entry in listing["entries"]] == [wheel.name, track.name]  # most recently used first
    assert listing["total_bytes"] == track.stat().st_size + wheel.stat().st_size
    first = listing["entries"][1]
    assert first["kind"] == "track-wedge" and first["size_bytes"] == track.stat().st_size
    assert first["holds"] == "pad 300 MN/m, sleeper 125 kg every 0.6 m, ballast 140 MN/m, 70 bays"
    code, out, err = cli("cache")
    assert code == 0 and err == "" and str(folder) in out and "WHEELRAIL_CACHE_MAX_GB" in out
    assert "pad 300 MN/m" in out and f"{track.stat().st_size / 1e6:9.1f}" in out
    code, out, err = cli("cache", "list", "--kind", "wheel-foh", "--json")
    assert [entry["kind"] for entry in json.loads(out)["entries"]] == ["wheel-foh"]


def test_cache_clear_removes_its_own_entries_only(folder, cli):
    track = _track_entry()
    wheel = cache.save_entry("wheel-foh", "1" * 64, {"phi": np.eye(4)})
    foreign = [folder / ".x.tmp", folder / "notes.txt", folder / "track-wedge-notes.npz"]
    for path in foreign:
        path.write_text("not the cache's")
    code, out, err = cli("cache", "clear", "--kind", "track-wedge", "--json")
    assert code == 0 and err == "" and json.loads(out)["removed"] == [track.name]
    assert wheel.exists() and not track.exists()
    code, out, _ = cli("cache", "clear")
    assert code == 0 and "removed 1 entry" in out and not wheel.exists()
    assert sorted(folder.iterdir()) == sorted(foreign)


@pytest.mark.parametrize("setting", ["WHEELRAIL_CACHE_DIR", "WHEELRAIL_CACHE_MAX_GB"])
def test_a_bad_cache_setting_is_one_line(tmp_path, monkeypatch, cli, setting):
    afile = tmp_path / "afile"
    afile.write_text("x")
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(afile if setting == "WHEELRAIL_CACHE_DIR" else tmp_path))
    monkeypatch.setenv("WHEELRAIL_CACHE_MAX_GB", "-2" if setting == "WHEELRAIL_CACHE_MAX_GB" else "4")
    for argv in (["cache"], ["track", "--json"]):
        code, out, err = cli(*argv)
        assert code == 2 and out == "" and err.count("\n") == 1 and setting in err and "Errno" not in err, err


def test_filters_leaves_no_table_when_its_figure_fails(tmp_path, monkeypatch, cli):
    # before: `filters --csv F --plot G` left F when G failed (a full disk)
    import matplotlib.figure

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", full)
    code, _, err = cli("filters", "--csv", str(tmp_path / "f.csv"), "--plot", str(tmp_path / "g.png"))
    assert err == f"wheelrail filters: error: no space left on device writing {tmp_path / 'g.png'}\n"
    assert list(tmp_path.iterdir()) == []


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_a_new_track_is_announced_on_a_terminal(folder):
    import dataclasses

    from wheelrail.cli.commands._progress import announce_track_precompute
    from wheelrail.core import track
    from wheelrail.core.parameters import TrackNumerics, TrackParameters

    numerics = TrackNumerics(duration=0.005, positions_per_bay=16, max_speed=100 / 3.6)
    short = TrackParameters(n_bays=20)  # 20 bays, not 70: what is announced, not the track's physics
    screen = _Terminal()
    with announce_track_precompute("run", screen):
        track.clear_memory()
        track.stationary_track_response(short, numerics)
    text = screen.getvalue()
    assert "wheelrail run: this track is not in the disk cache" in text and str(folder) in text
    for phase in ("assembling the FE track", "integrating the track's impulse responses (9 load", "writing"):
        assert f"wheelrail run: {phase}" in text
    assert "0/9 [" in text and "load position/s" in text  # the bar: 9 positions integrated, 7 mirrored
    piped = io.StringIO()  # not a terminal: nothing (pipes and --json stay clean)
    with announce_track_precompute("run", piped):
        track.clear_memory()
        track.stationary_track_response(short, dataclasses.replace(numerics, duration=0.004))
    assert piped.getvalue() == ""


@pytest.mark.slow
def test_run_leaves_no_recording_when_its_arrays_fail(tmp_path, monkeypatch, cli):
    # before: the recording was published first, then --out failed on the full disk: a .rrd without its .npz
    from wheelrail.core.engine.results import RunResult

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(RunResult, "save_npz", full)
    out, rrd = tmp_path / "run.npz", tmp_path / "run.rrd"
    argv = ["run", "--set", "corrugated-rail", "--length-m", "0.05", "--out", str(out), "--rrd", str(rrd), "--json"]
    code, _, err = cli(*argv)
    assert code == 1 and "No space left" in err
    assert list(tmp_path.iterdir()) == []
