"""A finished recording is marked complete; one whose writer was killed reads with an "incomplete" warning,
and its hidden ``.partial`` file is removed by the next recording into the folder (ours only)."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import pytest
from test_recording import N_STEPS, synthetic_result

from wheelrail.cli.dispatch import main
from wheelrail.core.recording import read_recording, record_result
from wheelrail.core.recording.outputs import _host

KILLED_AT = 650  # steps sent before the writer is killed (of N_STEPS = 700; 20 ms skip + 94 steps)

WRITER = textwrap.dedent(
    f"""
    import os, signal, sys
    sys.path.insert(0, {str(Path(__file__).parent)!r})
    from test_recording import synthetic_result
    from wheelrail.core.recording import RecordingOptions, RecordingSink

    result = synthetic_result(model="hertz")
    sink = RecordingSink(rrd=sys.argv[1], options=RecordingOptions(chunk_steps=50))
    sink.start(result)
    for step in range({KILLED_AT}):
        sink(result.state(step))
    sink.flush()
    sink.stream.flush()  # what a killed run had written: every block sent so far
    os.kill(os.getpid(), signal.SIGKILL)
    """
)


@pytest.fixture(scope="module")
def killed(tmp_path_factory):
    """(folder, the .partial a killed writer left, its pid)."""
    folder = tmp_path_factory.mktemp("killed")
    done = subprocess.run([sys.executable, "-c", WRITER, str(folder / "run.rrd")], capture_output=True, timeout=300)
    assert done.returncode == -9, done.stderr.decode()
    (partial,) = folder.glob(".run.rrd.*.partial")
    assert not (folder / "run.rrd").exists()
    pid = int(partial.name.split(".rrd.", 1)[1].rsplit("-", 2)[1])
    return folder, partial, pid


def test_a_finished_recording_reads_without_warning(tmp_path, capsys):
    path = record_result(synthetic_result(model="hertz"), tmp_path / "done.rrd")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        back = read_recording(path)
    assert back.n_steps == N_STEPS
    assert main(["spectra", str(path)]) == 0
    assert "incomplete" not in capsys.readouterr().err


def test_a_killed_recording_renamed_reads_with_an_incomplete_warning(killed, tmp_path, capsys):
    _, partial, _ = killed
    renamed = tmp_path / "renamed.rrd"
    renamed.write_bytes(partial.read_bytes())
    with pytest.warns(UserWarning, match=r"renamed.rrd is an incomplete recording: it holds 650 steps"):
        back = read_recording(renamed)
    assert back.n_steps == KILLED_AT
    # the command line: one warning line, then the spectrum of the part recorded
    done = subprocess.run(
        [sys.executable, "-m", "wheelrail", "spectra", str(renamed)], capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0 and "band (Hz)" in done.stdout, done.stderr
    assert done.stderr.count("\n") == 1 and done.stderr.startswith("wheelrail spectra: warning: "), done.stderr
    assert "incomplete recording" in done.stderr


def test_the_next_recording_removes_stale_partials_of_this_host_only(killed, tmp_path):
    folder, partial, pid = killed
    assert partial.name.startswith(f".run.rrd.{_host()}-{pid}-")
    keep = [
        folder / f".live.rrd.{_host()}-{os.getppid()}-0123abcd.partial",  # a writer still running
        folder / f".other.rrd.elsewhere-{pid}-0123abcd.partial",  # another host's (shared folder)
        folder / ".old.rrd.0123abcd.partial",  # named otherwise: not recognisably ours
        folder / f".notes.txt.{_host()}-{pid}-0123abcd.partial",  # not a recording
        folder / "run.partial",
    ]
    for path in keep:
        path.write_text("not ours to delete")
    record_result(synthetic_result(model="hertz", n=40), folder / "next.rrd")
    assert not partial.exists()
    assert all(path.exists() for path in keep)
    assert socket.gethostname()  # the host part names this machine
