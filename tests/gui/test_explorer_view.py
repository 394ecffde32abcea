"""Explorer, server side: the 3D view, readout, slider and progress belong to the configuration shown.

The controls are set as a browser would (``handle.value = ...`` runs the callbacks) and Run is pressed by
calling what the button calls (``ExplorerApp.start_run``); the runs are wheelrail.core's, short (0.6 m).
"""

import io
import threading
from types import SimpleNamespace

import numpy as np
import pytest

from wheelrail.core.drawing import palette
from wheelrail.core.drawing.patch import colour_table, table_colours
from wheelrail.core.models import model_names
from wheelrail.core.noise.components import noise_components
from wheelrail.core.parameters import ContactParameters
from wheelrail.explorer.panel import NO_OVERLAY
from wheelrail.explorer.scene import PRESSURE_HEIGHT, PRESSURE_TOP, SCENE_PER_MM
from wheelrail.explorer.tabs import NoiseTab, PatchTab, RoughnessTab, SpectraTab

pytestmark = pytest.mark.slow  # every test here starts a server and runs the model: `pytest -m 'not slow'` skips them


def _reset(app, *, model="3d", speed="100", length="0.6", geometry_mm=("", "", "")):
    app.form.wheel_set_dropdown.value = "none"
    (
        app.form.fields["wheel_radius"].value,
        app.form.fields["rail_crown_radius"].value,
        app.form.fields["wheel_transverse_radius"].value,
    ) = geometry_mm
    app.form.set_dropdown.value = "corrugated-rail"
    app.form.model_dropdown.value = model
    app.form.line_dropdown.value = "0"
    app.form.fields["speed"].value = speed
    app.form.fields["preload"].value = "65"
    app.form.length_text.value = length
    app.page.last_error = None


def _heat_map_of(result, step, contact=None):
    """The heat map the scene draws for ``step`` of ``result`` (rows top (+y) to bottom)."""
    contact = ContactParameters() if contact is None else contact
    colours = table_colours(
        np.asarray(result.pressure[step], dtype=np.float64),
        PRESSURE_TOP * contact.hertz_peak_pressure(),
        colour_table(),
    )
    return colours[::-1]


def _assert_cleared(app):
    scene = app.scene
    assert not scene.heatmap.visible and not scene.strip.visible and not scene.surface.visible
    assert "no run of this configuration yet" in app.tab(PatchTab).readout_md.content.lower()
    assert (
        app.tab(PatchTab).time_slider.disabled
        and app.tab(PatchTab).play_button.disabled
        and app.tab(PatchTab).rrd_button.disabled
    )
    assert app.form.progress == 0


def _assert_shows_last_step(app, result):
    n = result.n_steps
    assert app.scene.heatmap.visible
    assert (
        app.tab(PatchTab).time_slider.max == n - 1
        and app.tab(PatchTab).time_slider.value == n - 1
        and not app.tab(PatchTab).time_slider.disabled
    )
    assert f"step {n - 1}:" in app.tab(PatchTab).readout_md.content
    assert f"x = {result.x[-1]:.4f} m" in app.tab(PatchTab).readout_md.content
    assert np.array_equal(app.scene.heatmap.image, _heat_map_of(result, n - 1, result_contact(result)))
    assert app.form.progress == 100


def result_contact(result):
    contact = result.parameters["contact"]
    return ContactParameters(**contact)


def test_the_view_follows_the_configuration_shown(app, finish_run):
    """The 3D view, readout, slider and progress of the configuration the controls describe, or cleared."""
    _reset(app, length="0.8")
    longer = finish_run(app)
    _reset(app, length="0.6")
    _assert_cleared(app)  # a configuration without a run: the 0.8 m patch is not left on screen
    result = finish_run(app)
    _assert_shows_last_step(app, result)
    app.form.fields["speed"].value = "200"
    _assert_cleared(app)
    app.form.fields["speed"].value = "100"
    _assert_shows_last_step(app, result)
    app.form.length_text.value = "0.8"  # the longer run: its own steps, positions and slider range
    _assert_shows_last_step(app, longer)
    app.form.length_text.value = "0.6"
    app.form.fields["wheel_radius"].value, app.form.fields["rail_crown_radius"].value = "460", "300"
    _assert_cleared(app)  # the old circle patch does not lie under the new ellipse
    app.form.fields["wheel_radius"].value = app.form.fields["rail_crown_radius"].value = ""
    _assert_shows_last_step(app, result)
    app.tab(PatchTab).time_slider.value = 100  # scrubbing draws that step of this run
    assert "step 100:" in app.tab(PatchTab).readout_md.content
    assert np.array_equal(app.scene.heatmap.image, _heat_map_of(result, 100))


def test_the_view_is_cleared_after_an_upload(app, tmp_path, finish_run):
    from wheelrail.core.roughness import load_roughness, write_csv

    _reset(app)
    finish_run(app)
    rail = load_roughness("corrugated-rail")
    small = rail.with_heights(rail.heights[:, :1500], note="explorer view test")
    path = tmp_path / "view.csv"
    write_csv(small, path)
    event = SimpleNamespace(
        target=SimpleNamespace(value=SimpleNamespace(name="view.csv", content=path.read_bytes())), client=None
    )
    app.page.upload(event, app.form.load_upload)
    assert app.form.roughness_label == "upload: view.csv"
    _assert_cleared(app)  # the corrugated rail's heat map does not stay


def test_a_compare_replays_and_downloads_the_model_chosen(app, finish_run):
    """After compare, a model selector chooses what is replayed, plotted as displacement and downloaded."""
    _reset(app, model="compare")
    finish_run(app)
    app.form.fields["speed"].value = "80"
    app.form.fields["speed"].value = "100"  # back on the compare's configuration
    models = [m for m in model_names() if m in app.store.entries(app.shown.case())]
    first = models[0]  # registry order: 3d
    assert app.tab(PatchTab).displacement.handle.title.startswith(f"Displacement, {first}:")
    assert app.replay.entry.config.model == first  # the view replays what the plots name
    assert app.tab(PatchTab).model_shown.options == tuple(models) and not app.tab(PatchTab).model_shown.disabled
    assert app.tab(PatchTab).model_shown.value == first
    assert app.downloads.rrd()[0].startswith(f"wheelrail-{first}-")
    app.tab(PatchTab).model_shown.value = "2d"
    assert app.replay.entry.config.model == "2d"
    assert app.tab(PatchTab).displacement.handle.title.startswith("Displacement, 2d:")
    assert app.tab(PatchTab).readout_md.content.startswith("**2d**")
    assert app.scene.strip.visible and not app.scene.heatmap.visible  # a one-line model's strip
    name, _ = app.downloads.rrd()
    assert name == "wheelrail-2d-corrugated-rail-line0-100kmh-65kN-0.6m.rrd"
    # the Noise tab draws the shown model's parts and every model's total solid, each in its own colour of core's
    # palette (their distances under colour-vision deficiency: tests/unit/test_palette.py), the totals last
    solid = [(label, colour) for label, colour, style in app.tab(NoiseTab).power.series if style == "solid"]
    expected = [(f"2d: {part.name}", part.colour) for part in noise_components()]
    expected += [(f"{m}: total", palette.model_colour(m, model_names())) for m in models]
    assert solid == expected and len({colour for _, colour in solid}) == len(solid)


def test_the_raised_surface_is_drawn_before_it_is_shown(app, finish_run):
    """Ticked after a run, the raised pressure surface has the vertices of the step shown (no stale mesh)."""
    _reset(app)
    result = finish_run(app)
    app.tab(PatchTab).raised_box.value = True
    try:
        surface = app.scene.surface
        ny, nx = result.pressure.shape[1:]
        assert surface.visible
        assert surface.vertices.shape == (ny * nx, 3) and int(surface.faces.max()) < ny * nx
        step = int(app.tab(PatchTab).time_slider.value)
        height = surface.vertices[:, 2].reshape(ny, nx) / SCENE_PER_MM  # mm
        expected = result.pressure[step] / 1e9 * PRESSURE_HEIGHT
        assert np.allclose(height, expected, atol=1e-4)  # float32 vertices
    finally:
        app.tab(PatchTab).raised_box.value = False


def test_exported_pngs_keep_their_whole_title(app, finish_run):
    """A long title (configuration with a geometry) wraps inside the PNG instead of running off both sides."""
    from PIL import Image

    _reset(app, model="hertz", geometry_mm=("460", "300", "-1000"))
    finish_run(app)
    assert len(app.tab(PatchTab).force.handle.title) > 120
    for which in ("contact force", "displacement", "force spectra", "contact filters"):
        _, content = app.downloads.plot_png(which)
        grey = np.asarray(Image.open(io.BytesIO(content)).convert("L"))
        top = grey[: grey.shape[0] // 6]  # the title's band
        assert top.min() < 100  # the title is drawn
        for edge in (top[:, :4], top[:, -4:]):
            assert edge.min() > 200, f"{which}: the title touches the edge of the PNG"


def test_the_3d_view_explains_itself(app, finish_run):
    """From above by default, the Hertz semi-axes labelled, p0 said; surfaces at the step shown, never over
    the patch."""
    camera = app.server.initial_camera
    assert np.allclose(camera.position[:2], 0.0) and camera.position[2] > 0  # straight above: no foreshortening
    assert np.allclose(camera.up, (0.0, 1.0, 0.0))  # x (rolling direction) to the right, y up
    _reset(app, geometry_mm=("460", "300", ""))
    contact = ContactParameters(wheel_radius=0.46, rail_crown_radius=0.3)
    a, b = (v * 1e3 for v in contact.hertz_semi_axes())
    assert app.scene.a_label.text == f"a = {a:.2f} mm" and app.scene.b_label.text == f"b = {b:.2f} mm"
    result = finish_run(app)
    assert f"p0 = {contact.hertz_peak_pressure() / 1e6:.0f} MPa" in app.tab(PatchTab).readout_md.content
    app.tab(PatchTab).time_slider.value = 150
    app.tab(PatchTab).surfaces_box.value = True
    try:
        scene = app.scene
        rail, wheel = scene.rail_mesh.vertices, scene.wheel_lines.points
        assert rail[:, 2].max() < 0 < wheel[..., 2].min()  # the patch lies at z = 0, between them
        expected, _ = scene._surface_vertices(app.form.roughness, float(result.x[150]), 0, contact)
        assert np.allclose(rail, expected)  # drawn where the wheel is at the step shown
        app.tab(PatchTab).time_slider.value = 400
        expected, _ = scene._surface_vertices(app.form.roughness, float(result.x[400]), 0, contact)
        assert np.allclose(scene.rail_mesh.vertices, expected)
    finally:
        app.tab(PatchTab).surfaces_box.value = False


def _upload(app, name, rough, tmp_path):
    from wheelrail.core.roughness import write_csv

    path = tmp_path / name
    write_csv(rough, path)
    app.page.upload(
        SimpleNamespace(
            target=SimpleNamespace(value=SimpleNamespace(name=name, content=path.read_bytes())), client=None
        ),
        app.form.load_upload,
    )
    assert app.form.roughness_label == f"upload: {name}", app.page.last_error


def test_the_line_menu_and_the_run_length_follow_the_set_loaded(app, tmp_path):
    from wheelrail.core.roughness import load_roughness

    rail = load_roughness("corrugated-rail")
    _reset(app, length="3")
    _upload(app, "three-lines.csv", rail.with_heights(rail.heights[8:11, :1500], y=rail.y[8:11]), tmp_path)
    # the run length is brought within what the file holds, saying so
    assert app.form.length_text.value == "1.459" and "1.459 m is set" in app.page.status_md.content
    # 3d needs more room across than three lines 1 mm apart: no line is offered, and the page says why
    assert app.form.line_dropdown.options == ("no line fits",)
    assert "no line of upload: three-lines.csv leaves room for it" in app.form.check_md.content
    assert not app.start_run()
    app.form.model_dropdown.value = "hertz"
    assert app.form.line_dropdown.options == ("-1", "0", "1")
    _reset(app, geometry_mm=("", "5000", ""))  # a 5 m crown: a patch too wide for every line
    assert app.form.line_dropdown.options == ("no line fits",)
    app.form.fields["rail_crown_radius"].value = ""
    assert app.form.line_dropdown.options == ("-2", "-1", "0", "1", "2")


def test_the_roughness_tab_reads_as_noise_engineers_read_it(app, tmp_path):
    from wheelrail.core.roughness import load_roughness, roughness_spectrum
    from wheelrail.core.spectra.levels import energy_sum

    _reset(app)
    app.form.wheel_set_dropdown.value = "sinter-wheel-1"
    plot = app.tab(RoughnessTab).spectrum
    labels = [label for label, _, _ in plot.series]
    assert labels == [
        "rail: corrugated-rail, lines -3..3",
        "wheel: sinter-wheel-1, lines -3..3",
        "combined (energetic sum)",
        "ISO 3095:2013 limit (rail)",
    ]
    assert [style for _, _, style in plot.series] == ["solid", "solid", "solid", "dotted"]
    assert plot.handle.title == "Roughness spectrum: corrugated-rail + sinter-wheel-1 at 100 km/h"
    rail = roughness_spectrum(load_roughness("corrugated-rail"), speed=100 / 3.6)
    wheel = roughness_spectrum(load_roughness("sinter-wheel-1"), speed=100 / 3.6)
    combined = energy_sum(rail.levels_db, wheel.levels_db)
    centres = plot.data[0]
    for i, f in enumerate(centres):
        band = int(np.argmin(np.abs(rail.band_centres - f)))
        if np.isfinite(combined[band]):
            assert plot.data[3][i] == pytest.approx(combined[band])
    # frequency with its nominal band names below, wavelength on top
    axes = plot.handle.axes
    assert axes[0]["values"][:3] == ["63", "125", "250"] and axes[2]["label"] == "wavelength (mm) at 100 km/h"
    assert axes[2]["side"] == 0 and "100" in axes[2]["values"]
    speed = 100 / 3.6
    for f, mm in zip(axes[2]["splits"], axes[2]["values"], strict=True):  # lambda = v / f, on the page
        assert float(mm) == pytest.approx(speed / f * 1e3)
    top = plot.figure().axes[1]  # and in the PNG
    for f, label in zip(top.get_xticks(), top.get_xticklabels(), strict=True):
        assert float(label.get_text()) == pytest.approx(speed / f * 1e3)
    assert app.tab(RoughnessTab).coherence.handle.scales["y"]["range"] == [0.0, 1.0]
    app.form.wheel_set_dropdown.value = "none"
    # a pure sine: the bands without roughness are not drawn at the FFT's numerical floor
    base = load_roughness("corrugated-rail")
    x = np.arange(3000) * base.dx
    sine = base.with_heights(np.tile(5e-6 * np.sin(2 * np.pi * x / 0.05), (3, 1)), y=base.y[8:11])
    _upload(app, "sine.csv", sine, tmp_path)
    levels = app.tab(RoughnessTab).spectrum.data[1]
    finite = levels[np.isfinite(levels)]
    assert finite.size and finite.min() >= finite.max() - 120.0
    assert app.tab(RoughnessTab).spectrum.handle.scales["y"]["range"][0] >= finite.max() - 125.0


class HeldRun:
    """A stand-in one-line run of ``n`` steps whose step ``hold_at`` waits for ``release`` (or cancel)."""

    def __init__(self, model, n, hold_at):
        self.model, self.n_steps, self.hold_at = model, n, hold_at
        self.reached, self.release, self._cancel = threading.Event(), threading.Event(), threading.Event()
        self.done = 0
        self.force = 65e3 + np.random.default_rng(3).standard_normal(n)
        self.window_x = self.window_y = None

    def _state(self, s):
        return SimpleNamespace(step=s, position=s * 1e-3, force=self.force[s], contact_length=0.011, pressure=None)

    def steps(self):
        for s in range(self.n_steps):
            if s == self.hold_at:
                self.reached.set()
                while not (self.release.is_set() or self._cancel.is_set()):
                    self.release.wait(60.0)
            if self._cancel.is_set():
                return
            self.done = s + 1
            yield self._state(s)

    def chunk_states(self):  # a chunk of one step each
        return self.steps()

    def cancel(self):
        self._cancel.set()

    @property
    def cancelled(self):
        return self._cancel.is_set()

    def result(self):
        n = self.done
        return SimpleNamespace(
            model=self.model,
            n_steps=n,
            force=self.force[:n],
            x=np.arange(n) * 1e-3,
            xi_wheel=np.zeros(n),
            xi_rail=np.zeros(n),
            time_step=1e-3 / (100 / 3.6),
            window_x=None,
            window_y=None,
            state=self._state,
        )


def test_a_run_reaches_the_view_only_while_its_configuration_is_shown(app):
    """A run of one configuration goes on while the page shows another: its frames and progress stay off
    that page's view; back on its configuration the view shows it."""
    from wheelrail.explorer.controller import RunController

    run = HeldRun("hertz", 3000, hold_at=1500)
    own = app.controller
    app.controller = RunController(app, app.store, prepare=lambda *a, **k: run, frame_interval=0.0)
    try:
        _reset(app, model="hertz", speed="90", length="3")
        assert app.start_run()
        assert run.reached.wait(60.0)
        assert app.scene.strip.visible and "step 1499:" in app.tab(PatchTab).readout_md.content
        app.form.fields["speed"].value = "91"  # another configuration while the run goes on
        _assert_cleared(app)
        drawn = app.scene.frames_drawn
        run.release.set()
        assert app.controller.wait(60.0)
        assert app.scene.frames_drawn == drawn and app.form.progress == 0  # nothing of the run arrived
        _assert_cleared(app)
        app.form.fields["speed"].value = "90"  # back: its run, last step
        assert app.scene.strip.visible and "step 2999:" in app.tab(PatchTab).readout_md.content
        assert app.form.progress == 100 and app.tab(PatchTab).time_slider.max == 2999
    finally:
        run.release.set()
        app.controller.wait(60.0)
        app.controller = own


def test_the_noise_tab_shows_the_runs_sound_power_beside_cnossos_and_plays_its_pass_by(app, tmp_path, finish_run):
    """Noise tab: per-component sound power (A-weighted, per axle) of the model shown and CNOSSOS-EU beside it,
    from the run's own RunNoise; totals and pass-by level for the train of the tab's fields; the pass-by as a
    playable, calibrated WAV; an overlaid run dashed; the recording carries the sound power."""
    import base64
    import json
    import re

    from rerun.chunk import RrdReader
    from scipy.io import wavfile

    from wheelrail.core.noise.run_noise import pass_by_level
    from wheelrail.core.spectra.levels import a_weighting

    _reset(app, model="hertz", length="1")
    result = finish_run(app)
    entry = app.replay.entry
    noise = entry.noise
    assert noise is not None and noise.configuration["run"]["model"] == "hertz"
    tab = app.tab(NoiseTab)
    labels = [label for label, _, _ in tab.power.series]
    assert labels[:5] == ["hertz: rail", "hertz: rail_lateral", "hertz: sleeper", "hertz: wheel", "hertz: total"]
    assert labels[-3:] == ["CNOSSOS-EU: track", "CNOSSOS-EU: vehicle", "CNOSSOS-EU: total"]
    # the plotted total: one wheel's sound power + 3 dB (an axle) + A-weighting, on the bands the run resolves
    plotted = dict(zip(labels, tab.power.data[1:], strict=True))
    kept = np.isin(noise.frequency_hz, tab.power.data[0])
    expected = noise.sound_power_db["total"][kept] + 10 * np.log10(2) + a_weighting(noise.frequency_hz[kept])
    np.testing.assert_allclose(plotted["hertz: total"], expected, atol=1e-9)
    np.testing.assert_allclose(
        plotted["CNOSSOS-EU: total"], (noise.cnossos.total_db + a_weighting(noise.frequency_hz))[kept], atol=1e-9
    )
    row = next(line for line in tab.totals_md.content.splitlines() if line.startswith("| **hertz**"))
    total = noise.axle_dba
    assert f"| {total:.1f} | {pass_by_level(total, 40, 200.0):.1f} |" in row
    tab.axles_text.value = "8"
    tab.train_length_text.value = "40"
    row = next(line for line in tab.totals_md.content.splitlines() if line.startswith("| **hertz**"))
    assert row.endswith(f"| {pass_by_level(total, 8, 40.0):.1f} |")
    tab.axles_text.value = "0"  # refused in the table's words; no pass-by for it
    assert "Train axles 0: not a whole number of at least 1" in tab.totals_md.content
    assert tab.audio_button.disabled
    tab.axles_text.value = "8"
    # the pass-by: played from the page, downloaded as the same WAV; its level is the table's (calibration)
    name, data = app.tab(NoiseTab).make_pass_by()
    assert name == "wheelrail-hertz-corrugated-rail-line0-100kmh-65kN-1m-pass-by-8axles-40m.wav"
    embedded = re.search(r'src="data:audio/wav;base64,([^"]+)"', tab.audio_html.content).group(1)
    assert base64.b64decode(embedded) == data and app.tab(NoiseTab).download_wav()[1] == data
    rate, samples = wavfile.read(io.BytesIO(data))
    assert rate == 48_000  # a standard rate; the run's own is v / dx
    assert len(samples) == pytest.approx((40.0 / result.speed + 2.0) * rate, abs=2)  # T_p and 1 s either side
    assert f"L_pAeq,Tp {pass_by_level(total, 8, 40.0):.1f} dB(A)" in tab.audio_html.content
    summary = json.loads(app.tab(NoiseTab).download_json()[1])
    assert summary["pass_by_LpAeq_dBA"] == pytest.approx(pass_by_level(total, 8, 40.0))
    assert summary["cnossos"]["total_dBA"] == pytest.approx(noise.cnossos.total_dba)
    tab.axles_text.value = "9"  # the player held the 8-axle pass-by: it goes
    assert tab.audio_html.content == "" and tab.wav_button.disabled
    # the recording of the run carries its sound-power spectra
    path = tmp_path / "noise.rrd"
    path.write_bytes(app.downloads.rrd()[1])
    assert any(c.entity_path == "/spectra/sound_power/total" for c in RrdReader(path).stream())
    # another configuration overlaid from the Noise tab's menu: both menus show it, its total is dashed
    _reset(app, model="hertz", speed="120", length="1")
    finish_run(app)
    other = app.shown.case_label()
    app.form.fields["speed"].value = "100"
    tab.overlay_dropdown.value = other
    assert app.tab(SpectraTab).overlay_dropdown.value == other
    dashed = [label for label, _, style in tab.power.series if style == "dashed"]
    assert dashed == [f"hertz: total [{other}]"]
    assert any(line.startswith(f"| hertz [{other}]") for line in tab.totals_md.content.splitlines())
    tab.overlay_dropdown.value = NO_OVERLAY
    app.form.fields["speed"].value = "130"  # no run of this configuration
    assert "no run of this configuration yet" in tab.power.series[0][0] and tab.audio_button.disabled


def test_the_top_view_is_fitted_again_when_the_view_resizes_until_the_user_moves_it(app):
    """A page's first camera report may come before the panels dock (the whole window's aspect): the top view is
    fitted again to the docked 3D view's size, and never after the user has moved the camera."""
    import contextlib

    from wheelrail.explorer.scene import top_view

    class Camera:
        def __init__(self):
            self.image_width, self.image_height = 1280, 800
            self.position, self.look_at, self.up_direction = (3.0, 3.0, 3.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)
            self.callbacks = []

        def on_update(self, callback):
            self.callbacks.append(callback)

        def report(self, width, height, position=None):
            self.image_width, self.image_height = width, height
            if position is not None:
                self.position = position
            for callback in self.callbacks:
                callback(self)

    camera = Camera()
    client = SimpleNamespace(camera=camera, atomic=contextlib.nullcontext)
    app.page.fit_camera(client)
    camera.report(1280, 800)  # before the panels dock: fitted to the whole window
    assert camera.position == pytest.approx(top_view(1.6)["position"])
    camera.report(372, 800)  # docked: fitted again to the 3D view between the panels
    assert camera.position == pytest.approx(top_view(372 / 800)["position"])
    assert camera.up_direction == (0.0, 1.0, 0.0)
    camera.report(372, 800, position=(1.0, -4.0, 6.0))  # the user turns the view
    camera.report(600, 800)  # and widens the window: their camera stays
    assert camera.position == (1.0, -4.0, 6.0)


def test_the_status_line_leaves_a_finished_run_when_the_settings_describe_another(app, finish_run):
    """After Done, a field edited: the status line no longer speaks of that run as shown (the Patch tab says there is
    no run of this configuration); back to the run's settings, it is Done again."""
    _reset(app, model="hertz", speed="100", length="0.6")
    finish_run(app)
    done = app.page.status_md.content
    assert done.startswith("Done: hertz on corrugated-rail, line 0, 100 km/h")
    app.form.fields["speed"].value = "95"
    status = app.page.status_md.content
    assert not status.startswith("Done") and "Step slider" not in status
    assert "no run of hertz on corrugated-rail, line 0, 95 km/h" in status and "**Run**" in status
    assert "no run of this configuration yet" in app.tab(PatchTab).readout_md.content.lower()
    app.form.fields["speed"].value = "100"
    assert app.page.status_md.content == done
    app.form.fields["preload"].value = "not a number"
    assert not app.page.status_md.content.startswith("Done")
    app.form.fields["preload"].value = "65"
    assert app.page.status_md.content == done


def test_plot_titles_announce_a_dashed_curve_only_when_one_is_drawn(app, finish_run):
    """A hertz-only run overlaid has a force spectrum (dashed, and announced) and no contact filter (hertz is the
    reference): the contact filters' title does not announce a dashed curve."""
    _reset(app, model="hertz", speed="90", length="0.6")
    finish_run(app)
    other = app.shown.case_label()
    _reset(app, model="hertz", speed="85", length="0.6")
    finish_run(app)
    tab = app.tab(SpectraTab)
    tab.overlay_dropdown.value = other
    assert [style for *_, style in tab.spectra.series].count("dashed") == 1
    assert tab.spectra.handle.title.endswith(f"(dashed: {other})")
    assert "dashed" not in [style for *_, style in tab.filters.series]
    assert "dashed" not in tab.filters.handle.title
    tab.overlay_dropdown.value = NO_OVERLAY


def test_the_spectra_tab_says_what_its_spectra_analysed(app, finish_run):
    """The Spectra tab states the record its force spectra analysed (core's ``spectrum_record``: the start left out,
    the duration analysed, the bands resolved), as ``run`` and ``spectra`` print it; a short run resolves only the
    upper bands, and the note says so rather than leaving the gaps unexplained."""
    from wheelrail.core.spectra.force import spectrum_record

    _reset(app, model="hertz", speed="100", length="0.6")
    result = finish_run(app)
    note = app.tab(SpectraTab).record_md.content
    assert spectrum_record(result).words() in note
    assert "left out" in note and "resolved" in note
    app.form.fields["speed"].value = "95"  # no run of this configuration: no record to state
    assert spectrum_record(result).words() not in app.tab(SpectraTab).record_md.content
    app.form.fields["speed"].value = "100"
