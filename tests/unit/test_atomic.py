"""Atomic writes: complete file or nothing under the final name, ordinary permissions."""

import errno
import os
import subprocess
import sys

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.files.atomic import atomic_write
from wheelrail.core.roughness import load_roughness, write_csv


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def test_written_file_has_ordinary_permissions(tmp_path):
    path = atomic_write(tmp_path / "a.npz", lambda handle: np.savez(handle, x=np.arange(3)))
    assert (path.stat().st_mode & 0o777) == (0o666 & ~_umask())  # not mkstemp's private 0600
    assert np.load(path)["x"].tolist() == [0, 1, 2]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.npz"]


def test_no_write_changes_the_process_umask(tmp_path, monkeypatch):
    # os.umask sets the mask of the whole process: a writer calling it races with every other thread
    def forbidden(mask):
        raise AssertionError("atomic_write must not call os.umask")

    expected = 0o666 & ~_umask()
    monkeypatch.setattr(os, "umask", forbidden)
    path = atomic_write(tmp_path / "c.txt", lambda handle: handle.write("x"), "w")
    assert (path.stat().st_mode & 0o777) == expected


def test_failed_write_leaves_nothing(tmp_path):
    target = tmp_path / "b.csv"
    target.write_text("old")

    def broken(handle):
        handle.write("half")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError):
        atomic_write(target, broken, "w")
    assert target.read_text() == "old"  # the previous complete file is untouched
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.csv"]


def test_exports_use_it(tmp_path):
    path = write_csv(load_roughness("sinter-wheel-2"), tmp_path / "w.csv")
    assert (path.stat().st_mode & 0o777) == (0o666 & ~_umask())


def test_files_written_together_appear_together(tmp_path):
    from wheelrail.core.files.atomic import all_or_none

    old = tmp_path / "b.png"
    old.write_text("previous figure")
    with pytest.raises(WheelrailError, match=r"^no space left on device writing .*b\.png$"):
        with all_or_none():
            atomic_write(tmp_path / "a.csv", lambda handle: handle.write("table"), "w")
            assert not (tmp_path / "a.csv").exists()  # not before the block's end

            def full(handle):
                handle.write("half")
                raise OSError(28, "No space left on device")

            atomic_write(old, full, "w")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.png"] and old.read_text() == "previous figure"
    with all_or_none():
        atomic_write(tmp_path / "a.csv", lambda handle: handle.write("table"), "w")
        atomic_write(old, lambda handle: handle.write("new figure"), "w")
    assert (tmp_path / "a.csv").read_text() == "table" and old.read_text() == "new figure"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "b.png"]


def test_a_failed_write_names_the_file_and_the_reason(tmp_path):
    def full(handle):
        handle.write(b"half")
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    with pytest.raises(WheelrailError) as caught:
        atomic_write(tmp_path / "r.npz", full)
    assert str(caught.value) == f"no space left on device writing {tmp_path / 'r.npz'}"
    assert list(tmp_path.iterdir()) == []


_KILLED_WRITER = """
import sys
from wheelrail.core.files.atomic import atomic_write

def write(handle):
    handle.write(b"half of a result")
    handle.flush()
    print("writing", flush=True)
    sys.stdin.read()  # held here until killed

atomic_write(sys.argv[1], write)
"""


def _killed_while_writing(path) -> int:
    """Start a writer of ``path``, kill -9 it while its temporary file is open (it says so first); its pid."""
    child = subprocess.Popen(
        [sys.executable, "-c", _KILLED_WRITER, str(path)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True
    )
    try:
        assert child.stdout.readline().strip() == "writing"
    finally:
        child.kill()
        child.wait()
        child.stdin.close()
        child.stdout.close()
    return child.pid


def test_the_temporary_of_a_writer_killed_mid_write_is_removed_by_the_next_write(tmp_path, monkeypatch):
    from wheelrail.core.files import atomic

    pid = _killed_while_writing(tmp_path / "result.npz")
    left = [p.name for p in tmp_path.iterdir()]
    assert len(left) == 1 and left[0].startswith(".wheelrail-result.npz.") and left[0].endswith(f"-{pid}.tmp")
    # a user's file named like a temporary but not ours, and one of a writer still running, are kept
    (tmp_path / ".result.npz.0123abcd.tmp").write_text("the user's")
    running = tmp_path / f".wheelrail-other.npz.0123abcd.{atomic.writer()}.tmp"
    running.write_text("being written")
    monkeypatch.setattr(atomic, "_SWEPT", set())  # a new process's first write into the folder
    atomic_write(tmp_path / "result.npz", lambda handle: handle.write(b"complete"))
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        [".result.npz.0123abcd.tmp", running.name, "result.npz"]
    )
    assert (tmp_path / "result.npz").read_bytes() == b"complete"


def test_an_output_that_is_an_input_is_refused_however_spelled(tmp_path, monkeypatch):
    from wheelrail.core.files.atomic import refuse_inputs

    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    (tmp_path / "set.csv").write_text("x_m,h\n")
    os.link(tmp_path / "set.csv", tmp_path / "hard.csv")
    (tmp_path / "soft.csv").symlink_to(tmp_path / "set.csv")
    for output in ("set.csv", "sub/../set.csv", tmp_path / "hard.csv", "soft.csv"):
        with pytest.raises(WheelrailError, match="is the input file set.csv: writing it would destroy the input"):
            refuse_inputs([output], ["corrugated-rail", "set.csv"])  # a bundled name is no file: skipped
    refuse_inputs(["other.csv", "sub/set.csv"], ["set.csv", None])
