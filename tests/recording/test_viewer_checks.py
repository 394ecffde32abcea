"""--connect and --spawn are checked before the run: one line, at once, no rerun log, no wasted computation.

A closed local port stands for an absent viewer (the connection is refused at once: no test waits)."""

from __future__ import annotations

import socket
import sys
from pathlib import Path

import pytest

import wheelrail.core.recording.outputs as outputs
from wheelrail.cli.dispatch import main
from wheelrail.core.errors import WheelrailError

RUN = ["run", "--set", "corrugated-rail", "--model", "hertz", "--length-m", "0.1"]


def _closed_port() -> int:
    """A local port nothing listens on (bound, then released)."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@pytest.fixture
def no_run(monkeypatch):
    """The run must not start: the viewer is checked before any computation."""

    def refuse(*args, **kwargs):
        raise AssertionError("the run started before the viewer was checked")

    monkeypatch.setattr("wheelrail.cli.commands.run._prepare", refuse)


def _one_line_error(capfd) -> str:
    out, err = capfd.readouterr()  # file descriptors: rerun's own (Rust) logs would show here
    assert out == "" and len(err.strip().splitlines()) == 1, err
    assert "\x1b[" not in err  # no coloured log line
    return err.strip()


def test_connect_to_no_viewer_is_one_line_before_the_run(tmp_path, capfd, no_run):
    port = _closed_port()
    out = tmp_path / "run.npz"
    assert main([*RUN, "--connect", f"127.0.0.1:{port}", "--out", str(out)]) != 0
    error = _one_line_error(capfd)
    assert error.startswith(f"wheelrail run: error: --connect 127.0.0.1:{port}: no rerun viewer answers there")
    assert list(tmp_path.iterdir()) == []  # nothing half-written, no .partial


def test_spawn_without_a_desktop_is_one_line_before_the_run(tmp_path, capfd, no_run, monkeypatch):
    for name in ("DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setattr(sys, "platform", "linux")
    monkeypatch.setattr(outputs, "DEFAULT_VIEWER_PORT", _closed_port())  # no viewer already open there
    assert main([*RUN, "--spawn", "--rrd", str(tmp_path / "r.rrd")]) != 0
    error = _one_line_error(capfd)
    assert "--spawn: no desktop for the viewer's window (neither DISPLAY nor WAYLAND_DISPLAY is set)" in error
    assert "record to a .rrd file" in error  # what to do instead
    assert list(tmp_path.iterdir()) == []


def test_the_viewer_is_found_beside_the_running_python(monkeypatch, tmp_path):
    """Without the environment's bin folder on PATH, the viewer installed with rerun-sdk is still found."""
    monkeypatch.setenv("PATH", str(tmp_path))
    found = outputs.viewer_executable()
    assert found == Path(sys.executable).parent / ("rerun.exe" if sys.platform == "win32" else "rerun")
    assert found.is_file()
    # neither beside Python nor on PATH: say where it was looked for, and what provides it
    monkeypatch.setattr(sys, "executable", str(tmp_path / "bin" / "python"))
    with pytest.raises(WheelrailError) as info:
        outputs.viewer_executable()
    message = str(info.value)
    assert str(tmp_path / "bin") in message and "PATH" in message and "rerun-sdk" in message
    assert len(message.splitlines()) == 1
