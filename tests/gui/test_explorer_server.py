"""Explorer, server side: the controls drive real runs, bad input gives a message and the server keeps going.

Each test sets the controls as a browser would (``handle.value = ...``) and presses Run by calling what the
button's callback calls (``ExplorerApp.start_run``); the runs themselves are wheelrail.core's.
"""

import socket
import threading
from types import SimpleNamespace

import numpy as np
import pytest

from wheelrail.core.parameters import KMH
from wheelrail.core.recording import read_recording
from wheelrail.core.roughness import load_roughness, write_csv
from wheelrail.core.spectra import force_spectrum
from wheelrail.explorer.app import ExplorerApp


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def app():
    explorer = ExplorerApp(port=_free_port(), max_upload_bytes=1_000_000)
    yield explorer
    explorer.close()


def _run(app, timeout=300.0):
    assert app.start_run(), app.last_error
    assert app.wait(timeout), "run did not finish"
    assert not app.running
    return app.last_result


def _reset(app, *, set_name="corrugated-rail", line=0, model="hertz", speed=100.0, preload=65.0, length=0.3):
    app.set_dropdown.value = set_name
    app.line_slider.value = line
    app.model_dropdown.value = model
    app.speed_number.value = speed
    app.preload_number.value = preload
    app.length_number.value = length


def test_binds_localhost_by_default(app):
    assert app.server.get_host() == "127.0.0.1"


def test_controls_define_the_run(app):
    _reset(app, set_name="cast-iron-wheel", line=2, model="2d", speed=80.0, preload=50.0, length=1.0)
    result = _run(app)
    assert app.last_error is None
    assert result.model == "2d" and result.line == 2
    assert result.speed == pytest.approx(80 * KMH)
    assert result.parameters["contact"]["preload"] == pytest.approx(50e3)
    assert result.force.shape == (1000,) and np.all(np.isfinite(result.force))
    assert abs(result.force.mean() - 50e3) < 0.1 * 50e3  # the wheel carries the preload chosen in the page
    assert app.config.as_dict() == {"model": "2d", "set": "cast-iron-wheel", "line": 2, "speed_kmh": 80.0,
                                    "preload_kn": 50.0, "length_m": 1.0}
    assert app.frames_drawn > 0 and app.progress == 1.0
    # one-line model: the strip (contact length) and the Hertz circle at the current force are shown
    assert app.strip_mesh.visible and app.force_circle.visible and not app.patch_mesh.visible
    half_length = np.ptp(app.strip_mesh.vertices[:, 0]) / 2 / 0.1 * 1e-3  # scene units (cm) -> m
    assert half_length == pytest.approx(result.contact_length[-1] / 2, rel=1e-5)
    # the force plot holds this run
    plot = app._plots["force"]
    assert np.allclose(plot.data[1], result.force / 1e3)
    # spectra of the run come from core
    centres, levels = force_spectrum(result)
    assert np.array_equal(app.spectra["2d"][1], levels, equal_nan=True)


def test_3d_run_draws_the_pressure_patch_and_replays(app):
    _reset(app, model="3d", length=0.8)
    result = _run(app)
    assert result.model == "3d" and result.pressure is not None
    assert app.frames_drawn > 0 and app.time_to_first_frame is not None
    ny, nx = result.pressure.shape[1:]
    vertices = app.patch_mesh.vertices
    assert vertices.shape == (ny * nx, 3) and app.patch_mesh.visible
    # the last frame shows the last step: heights are the pressure at the stated scale (3 mm per GPa)
    z_mm = vertices[:, 2] / 0.1
    assert np.allclose(z_mm, result.pressure[-1].reshape(-1) / 1e9 * 3.0, atol=1e-4)
    assert app.patch_points.colors.shape == (ny * nx, 3)
    # scrubbing (the Step slider) shows an earlier step
    app.time_slider.value = 10
    assert np.allclose(app.patch_mesh.vertices[:, 2] / 0.1, result.pressure[10].reshape(-1) / 1e9 * 3.0, atol=1e-4)
    assert "step 10" in app.readout_md.content


def test_compare_runs_every_model_and_gives_contact_filters(app):
    _reset(app, model="compare", length=0.8)
    _run(app)
    assert set(app.results) == {"3d", "2d", "hertz", "hertz-winkler", "hertz-average"}
    filters = app.contact_filters()
    assert set(filters) == {"3d", "2d", "hertz-winkler", "hertz-average"}
    _, hertz = force_spectrum(app.results["hertz"])
    _, two_d = force_spectrum(app.results["2d"])
    assert np.allclose(filters["2d"][1], two_d - hertz, equal_nan=True)
    assert app._plot_series["spectra"][1:] == ("3d", "2d", "hertz", "hertz-winkler", "hertz-average")
    assert app._plot_series["filters"][1:] == ("3d", "2d", "hertz-winkler", "hertz-average")
    text = app.spectra_csv().splitlines()
    assert text[0].startswith("band_centre_hz,3d_level_db") and "2d_contact_filter_db" in text[0]
    assert len(text) == 1 + len(hertz)


def test_downloads(app, tmp_path):
    _reset(app, model="3d", length=0.6)
    result = _run(app)
    name, content = app.download_rrd()
    assert name == "wheelrail-3d-line0.rrd" and app.last_download == (name, len(content))
    path = tmp_path / name
    path.write_bytes(content)
    back = read_recording(path)
    assert np.allclose(back.force, result.force)
    name, content = app.download_spectra_csv()
    assert name.endswith(".csv") and content.decode().startswith("band_centre_hz")


def test_bad_inputs_give_a_message_and_keep_the_results(app):
    _reset(app, model="hertz", length=1.0)
    result = _run(app)
    # speed of 0
    app.speed_number.value = 0.0
    assert not app.start_run()
    assert "speed" in app.last_error and "0 km/h" in app.last_error
    assert "Error" in app.status_md.content
    assert app.last_result is result
    # a line outside the set (the corrugated rail has lines -9..9)
    app.speed_number.value = 100.0
    app.line_slider.value = 12
    assert not app.start_run()
    assert "line 12" in app.last_error and "-9" in app.last_error
    app.line_slider.value = 0
    # a malformed CSV upload
    bad = SimpleNamespace(target=SimpleNamespace(value=SimpleNamespace(name="bad.csv", content=b"x_m,z\n0,abc\n")),
                          client=None)
    app._on_upload(bad)
    assert app.last_error.startswith("upload 'bad.csv'")
    assert app.roughness_label == "corrugated-rail"
    # an upload over the size limit (this app: 1 MB)
    big = SimpleNamespace(target=SimpleNamespace(value=SimpleNamespace(name="big.csv", content=b"0" * 1_200_000)),
                          client=None)
    app._on_upload(big)
    assert app.last_error == "upload 'big.csv' (1.14 MB) is over the 977 kB limit"
    # not a roughness file; a browser-supplied path is only a label
    app._on_upload(SimpleNamespace(target=SimpleNamespace(value=SimpleNamespace(name="../../etc/passwd",
                                                                                content=b"root")), client=None))
    assert "expected a .csv or .npz" in app.last_error and "passwd" in app.last_error
    # a set name sent by a page is never opened as a server path
    app.set_dropdown.value = "/etc/passwd"
    assert app.last_error == "unknown roughness set '/etc/passwd'; choose a bundled set or upload a file"
    assert app.roughness_label == "corrugated-rail"
    app.set_dropdown.value = "corrugated-rail"
    # nothing computed is lost and the server keeps working
    assert app.last_result is result and "hertz" in app.spectra
    again = _run(app)
    assert app.last_error is None and again.model == "hertz"


def test_upload_a_user_csv_and_run_on_it(app, tmp_path):
    rail = load_roughness("corrugated-rail")
    small = rail.with_heights(rail.heights[6:13, :1500], y=rail.y[6:13], note="explorer test")
    path = tmp_path / "mine.csv"
    write_csv(small, path)
    event = SimpleNamespace(target=SimpleNamespace(value=SimpleNamespace(name="C:\\data\\mine.csv",
                                                                         content=path.read_bytes())), client=None)
    app._on_upload(event)
    assert app.roughness_label == "upload: mine.csv"
    assert "upload: mine.csv" in app.set_dropdown.options and app.set_dropdown.value == "upload: mine.csv"
    assert (app.line_slider.min, app.line_slider.max) == (-3, 3)
    _reset(app, set_name="upload: mine.csv", line=1, model="2d", length=1.0)
    result = _run(app)
    assert app.last_error is None and result.line == 1 and result.n_steps == 1000


def test_stop_cancels_and_a_new_run_replaces_an_old_one(app, monkeypatch):
    # A 3d run is held at each frame it draws until it is cancelled, so "still running" never depends on how
    # fast the machine is (a 7.5 m 3d run takes well under a second on some).
    drawn = threading.Event()
    draw = app.draw_state

    def held_draw(state, view):
        draw(state, view)
        drawn.set()
        if view.model == "3d":
            while not (app._run is None or app._run.cancelled):
                drawn.wait(0.005)  # re-check the condition; the outcome never depends on this interval

    monkeypatch.setattr(app, "draw_state", held_draw)
    _reset(app, model="3d", length=7.5)
    assert app.start_run()
    assert drawn.wait(60)
    # choosing another set during a run changes the page, not the run
    app.set_dropdown.value = "sinter-wheel-1"
    assert app.running and app.last_error is None
    app.stop()
    assert app.wait(30)
    assert not app.running and app.status.startswith("Stopped 3d")
    assert 0 < app.last_result.n_steps < 7500 and app.last_result.roughness_name == "corrugated-rail"
    app.set_dropdown.value = "corrugated-rail"
    # Stop pressed while the run is still being prepared stops it before its first step
    app.length_number.value = 1.0
    assert app.start_run()
    app.stop()
    assert app.wait(30)
    assert app.status.startswith("Stopped 3d") and app.last_result.n_steps < 1000
    app.length_number.value = 7.5
    # pressing Run again while a run goes on replaces it cleanly
    drawn.clear()
    assert app.start_run()
    assert drawn.wait(60) and app.running
    app.model_dropdown.value = "hertz"
    app.length_number.value = 1.0
    assert app.start_run()
    assert app.wait(60)
    assert app.last_error is None
    assert app.last_result.model == "hertz" and app.last_result.n_steps == 1000
    assert app.config.model == "hertz"


def test_wheelrail_explore_serves_the_page_on_localhost():
    import subprocess
    import sys
    import urllib.request

    port = _free_port()
    process = subprocess.Popen([sys.executable, "-m", "wheelrail.core.cli", "explore", "--port", str(port), "--set",
                                "sinter-wheel-1"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        for line in process.stdout:  # viser's banner, then ours once the app is built
            if line.startswith("wheelrail explorer: "):
                assert line.split()[2] == f"http://127.0.0.1:{port}"
                break
        else:
            raise AssertionError(f"wheelrail explore exited with {process.wait()}")
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=10) as response:
            assert response.status == 200 and b"<html" in response.read().lower()
        # bound to the loopback address only: another address of this machine does not answer
        others = {info[4][0] for info in socket.getaddrinfo(socket.gethostname(), None, socket.AF_INET)}
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:  # the outward interface's address
            try:
                probe.connect(("192.0.2.123", 9))  # UDP connect sends nothing
                others.add(probe.getsockname()[0])
            except OSError:
                pass
        for address in others - {"127.0.0.1"}:
            if not address.startswith("127."):
                with socket.socket() as s:
                    s.settimeout(1)
                    assert s.connect_ex((address, port)) != 0
    finally:
        process.terminate()
        process.wait(10)


def test_wheelrail_explore_rejects_an_unknown_set(capsys):
    from wheelrail.core.cli import main

    assert main(["explore", "--set", "nope"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("wheelrail explore: error: --set 'nope' is not a bundled set") and "\n" not in err
