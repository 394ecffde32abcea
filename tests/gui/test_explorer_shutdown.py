"""The explorer closes cleanly: closing it stops and joins every thread it started (runs, the Track and Wheel tabs'
computations, replay), nothing updates its page afterwards, and a process that starts and stops it exits with
status 0 and prints no "Exception ignored", thread exception or warning.

The script runs in a subprocess (the tests' cache: the track is prepared) and closes the explorer while a run, the
Track tab's receptance and the Wheel tab's modes are being computed in the background.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest

pytestmark = pytest.mark.slow  # a subprocess that imports the explorer and computes a track: seconds

SCRIPT = textwrap.dedent(
    """
    import threading
    import warnings

    warnings.simplefilter("always")  # every warning printed (viser's "queued on a closed connection" among them)

    from wheelrail.explorer.app import ExplorerApp
    from wheelrail.explorer.headless import HeadlessTab
    from wheelrail.explorer.tabs import WheelTab

    app = ExplorerApp(port={port})
    tab = HeadlessTab(app.port)  # a tab of the explorer: its session
    assert app.wait_for(lambda: app.sessions, 120)
    session = next(iter(app.sessions.values()))
    session.tab(WheelTab).ask()  # the Wheel tab's worker computes this wheel's modes
    session.form.model_dropdown.value = "hertz"
    session.form.length_text.value = "0.6"
    assert session.start_run(), session.page.last_error  # a run being prepared
    app.close()
    tab.close()
    alive = sorted(t.name for t in threading.enumerate() if t is not threading.main_thread() and t.is_alive())
    print("threads after close:", alive, flush=True)
    assert not [name for name in alive if name.startswith("wheelrail")], alive
    """
)


def test_starting_and_stopping_the_explorer_exits_cleanly(tmp_path, free_port):
    env = {**os.environ, "PYTHONWARNINGS": "always"}
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT.format(port=free_port)],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
        cwd=tmp_path,
    )
    output = done.stdout + done.stderr
    assert done.returncode == 0, output
    assert "threads after close: []" in done.stdout or "wheelrail" not in done.stdout.split("threads after close:")[1]
    for sign in ("Exception ignored", "Exception in thread", "Traceback", "Warning", "closed connection"):
        assert sign not in output, output
