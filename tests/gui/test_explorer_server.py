"""Explorer, server side: the controls drive real runs, bad input gives a message and the server keeps going.

Each test sets the controls as a browser would (``handle.value = ...``, which runs the callbacks) and presses
Run by calling what the button's callback calls (``ExplorerApp.start_run``); the runs are wheelrail.core's.
Stop, replace and compare are tested without a server in test_explorer_controller.py.
"""

import io
import socket
from types import SimpleNamespace

import numpy as np
import pytest

from wheelrail.core.engine.track_lines import window_lines
from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.declared import inputs_of
from wheelrail.core.parameters import KMH, ContactParameters, ModelParameters
from wheelrail.core.recording import read_recording
from wheelrail.core.reference_filters import reference_filters
from wheelrail.core.roughness import load_roughness, write_csv
from wheelrail.core.spectra.force import force_spectrum
from wheelrail.explorer.config import read_config
from wheelrail.explorer.scene import SCENE_PER_MM
from wheelrail.explorer.tabs import PatchTab, SpectraTab, TrackTab

pytestmark = pytest.mark.slow  # every test here takes seconds: `pytest -m 'not slow'` skips them


def _reset(
    app,
    *,
    set_name="corrugated-rail",
    line=0,
    model="hertz",
    speed=100.0,
    preload=65.0,
    length=0.6,
    wheel_set="none",
    geometry_mm=("", "", ""),
):
    app.form.wheel_set_dropdown.value = wheel_set
    for key, text in zip(("wheel_radius", "rail_crown_radius", "wheel_transverse_radius"), geometry_mm, strict=True):
        app.form.fields[key].value = text
    for entry in inputs_of("track"):  # the paper's track
        app.form.fields[entry.key].value = f"{entry.shown_default():g}"
    app.form.set_dropdown.value = set_name
    app.form.model_dropdown.value = model
    app.form.line_dropdown.value = str(line)
    app.form.fields["speed"].value = f"{speed:g}"
    app.form.fields["preload"].value = f"{preload:g}"
    app.form.length_text.value = f"{length:g}"
    app.page.last_error = None


def test_binds_localhost_by_default(app):
    assert app.server.get_host() == "127.0.0.1"


def test_field_hints_state_cores_accepted_ranges(app):
    assert app.form.fields["speed"].hint == "Train speed, 5 to 400 km/h; default 100 km/h"
    assert "1 to 500 kN" in app.form.fields["preload"].hint and "100 to 1250 mm" in app.form.fields["wheel_radius"].hint
    assert "50 to 5000 mm" in app.form.fields["rail_crown_radius"].hint
    assert "at least 50 mm in magnitude" in app.form.fields["wheel_transverse_radius"].hint
    assert app.form.fields["pad_stiffness"].hint == "Rail pad stiffness, per support, 10 to 3000 MN/m; default 120 MN/m"
    assert (
        app.form.fields["pad_stiffness"].label == "Pad stiffness (MN/m)"
        and app.form.fields["pad_stiffness"].value == "120"
    )


def test_a_track_field_changes_the_case_and_a_bad_one_is_worded(app):
    _reset(app)
    plain = app.shown
    app.form.fields["pad_stiffness"].value = "60"
    assert app.shown.params().track.support.pad_stiffness == 60e6 and app.shown.case() != plain.case()
    assert "pad stiffness 60 MN/m" in app.shown.case_label()
    app.form.fields["pad_stiffness"].value = "0"
    assert app.shown is None
    assert "Pad stiffness 0 MN/m is outside the accepted 10 to 3000 MN/m" in app.form.check_md.content
    assert not app.start_run()
    app.form.fields["pad_stiffness"].value = "120"
    assert app.shown == plain


def test_a_session_saves_and_loads_back(app):
    _reset(app, model="2d", line=1, speed=80, length=1.0)
    app.form.fields["sleeper_mass"].value = "40"
    name, content = app.session.download()
    saved = app.shown
    assert name == saved.file_stem() + "-session.json"
    _reset(app)
    assert app.shown != saved
    app.session.load(content)
    assert app.shown == saved and "Session loaded" in app.page.status_md.content
    with pytest.raises(WheelrailError, match="not a wheelrail session file"):
        app.session.load(b"{}")
    other = content.replace(b'"corrugated-rail"', b'"my-own-rail"')
    with pytest.raises(WheelrailError, match="'my-own-rail' is not loaded here; upload it first"):
        app.session.load(other)
    assert app.shown == saved  # a refused session changes nothing


@pytest.mark.parametrize(
    ("old", "new", "fragment"),
    [
        (b'"length_m": "1"', b'"length_m": "-1"', "Run length -1 m is outside the accepted"),
        (b'"length_m": "1"', b'"length_m": "1e308"', "Run length 1e+308 m is outside the accepted"),
        (b'"line": "1"', b'"line": "99"', "Line 99 is not in"),
        (b'"wheelrail_session": 1,', b'"wheelrail_session": 1, "colour": "red",', "unknown setting(s) 'colour'"),
        (b'"wheelrail_session": 1,', b'"wheelrail_session": 1, "x": ' + b"[" * 100_000 + b"]" * 100_000 + b",", "deep"),
    ],
)
def test_a_session_out_of_range_is_refused_whole_and_changes_nothing(app, old, new, fragment):
    _reset(app, model="2d", line=1, speed=80, length=1.0)
    name, content = app.session.download()
    saved = app.shown
    assert old in content
    _reset(app)
    before = app.shown
    with pytest.raises(WheelrailError) as error:
        app.session.load(content.replace(old, new))
    assert fragment in str(error.value) and "\n" not in str(error.value)
    assert app.shown == before and app.shown != saved  # not brought into range without a word: nothing loaded


def test_an_error_shown_goes_once_the_fields_are_fixed(app):
    _reset(app)
    for typed in ("inf", "nan", "1e999"):  # a callback used to raise OverflowError here ("unexpected error")
        app.form.fields["speed"].value = typed
        assert f"Speed '{typed}': not a number" in app.form.check_md.content and app.page.last_error is None
        assert not app.start_run() and app.page.last_error == f"Speed '{typed}': not a number"  # Run says the same
    app.page.report_error("something about that configuration")
    app.form.fields["speed"].value = "100"
    assert app.page.last_error is None and "**Error:**" not in app.page.status_md.content


def test_an_upload_too_short_for_any_run_is_refused_and_a_same_name_one_replaces(app, tmp_path):
    _reset(app)
    before = app.form.roughness_label
    with pytest.raises(WheelrailError, match="too short for a"):
        app.form.load_upload("tiny.csv", b"# kind: rail\nx_m,y_mm=0,y_mm=1\n0,1,1\n0.001,2,2\n")
    assert app.form.roughness_label == before and "upload: tiny.csv" not in app.form.set_dropdown.options
    rail = load_roughness("corrugated-rail")
    for scale in (1.0, 2.0):  # the same file name twice: the page shows the second file's data
        small = rail.with_heights(scale * rail.heights[6:13, :1500], y=rail.y[6:13], note="explorer test")
        write_csv(small, tmp_path / "same.csv")
        app.form.load_upload("same.csv", (tmp_path / "same.csv").read_bytes())
        assert np.allclose(app.form.roughness.heights, small.heights, atol=1e-9)


def test_controls_define_the_run(app, finish_run):
    _reset(app, set_name="cast-iron-wheel", line=2, model="2d", speed=80.0, preload=50.0, length=1.0)
    result = finish_run(app)
    assert app.page.last_error is None
    assert result.model == "2d" and result.line == 2
    assert result.speed == pytest.approx(80 * KMH)
    assert result.parameters["contact"]["preload"] == pytest.approx(50e3)
    assert result.force.shape == (1000,) and np.all(np.isfinite(result.force))
    assert abs(result.force.mean() - 50e3) < 0.1 * 50e3  # the wheel carries the preload chosen in the page
    assert app.replay.entry.config.as_dict() == {
        "model": "2d",
        "set": "cast-iron-wheel",
        "line": 2,
        "speed_kmh": 80.0,
        "preload_kn": 50.0,
        "length_m": 1.0,
    }
    assert app.page.status_md.content.startswith("Done: 2d on cast-iron-wheel, line 2, 80 km/h, 50 kN, 1 m")
    # one-line model: the strip (contact length) and the Hertz circle at the current force are shown
    assert app.scene.strip.visible and app.scene.force_circle.visible and not app.scene.heatmap.visible
    half_length = np.ptp(app.scene.strip.vertices[:, 0]) / 2 / 0.1 * 1e-3  # scene units (cm) -> m
    assert half_length == pytest.approx(result.contact_length[-1] / 2, rel=1e-5)
    # the force plot holds this run and is titled with its configuration
    plot = app.tab(PatchTab).force.handle
    assert np.allclose(plot.data[1], result.force / 1e3)
    assert plot.title == "Contact force: cast-iron-wheel, line 2, 80 km/h, 50 kN, 1 m; the paper's track"
    centres, levels = force_spectrum(result)
    assert np.array_equal(app.store.spectra(app.shown.case())["2d"][1], levels, equal_nan=True)


def test_3d_run_draws_the_pressure_heat_map_and_replays(app, finish_run):
    _reset(app, model="3d", length=0.8)
    result = finish_run(app)
    assert result.model == "3d" and result.pressure is not None
    assert app.scene.frames_drawn > 0 and app.scene.heatmap.visible and not app.scene.strip.visible
    ny, nx = result.pressure.shape[1:]
    assert app.scene.heatmap.image.shape == (ny, nx, 3)
    app.tab(PatchTab).time_slider.value = 10  # scrubbing shows an earlier step
    assert "step 10:" in app.tab(PatchTab).readout_md.content
    assert f"F = {result.force[10] / 1e3:.2f} kN" in app.tab(PatchTab).readout_md.content


def test_stale_contact_filters_disappear_when_the_configuration_changes(app, finish_run):
    """After a compare, changing the speed once left its contact filters on the plot and in the CSV."""
    _reset(app, model="compare", length=0.8)
    finish_run(app)
    filters = app.store.contact_filters(app.shown.case())
    assert set(filters) == {"3d", "2d", "hertz-winkler", "hertz-average"}
    labels = [label for label, _, _ in app.tab(SpectraTab).filters.series]
    assert labels[:4] == ["3d - hertz", "2d - hertz", "hertz-winkler - hertz", "hertz-average - hertz"]
    assert labels[4:] == ["cnossos", "averaging", "patch-correlated", "patch-incoherent"]  # dotted references
    assert [style for _, _, style in app.tab(SpectraTab).filters.series] == ["solid"] * 4 + ["dotted"] * 4
    assert app.tab(SpectraTab).filters.handle.title.endswith("line 0, 100 km/h, 65 kN, 0.8 m; the paper's track")
    app.form.fields["speed"].value = "80"
    assert [label for label, _, _ in app.tab(SpectraTab).filters.series] == labels[4:]  # the old filters are gone
    assert app.tab(SpectraTab).filters.handle.title.endswith("line 0, 80 km/h, 65 kN, 0.8 m; the paper's track")
    assert app.tab(SpectraTab).csv_button.disabled and app.tab(PatchTab).rrd_button.disabled
    with pytest.raises(WheelrailError, match="no force spectrum yet for corrugated-rail, line 0, 80 km/h"):
        app.downloads.spectra_csv()
    # the references follow the speed: on the force bands at 80 km/h
    references = reference_filters(65e3, 0.39, 80 * KMH).by_frequency["cnossos"]
    assert np.allclose(app.tab(SpectraTab).filters.handle.data[1], references[np.isfinite(references)])
    app.form.fields["speed"].value = "100"  # back: that configuration's runs show again
    assert [label for label, _, _ in app.tab(SpectraTab).filters.series] == labels
    name, content = app.downloads.spectra_csv()
    assert name == "wheelrail-spectra-corrugated-rail-line0-100kmh-65kN-0.8m.csv"
    text = content.decode().splitlines()
    assert text[0] == "# wheelrail explorer: corrugated-rail, line 0, 100 km/h, 65 kN, 0.8 m"
    assert text[1].startswith("band,centre_hz,3d_level_db") and "reference_cnossos_db" in text[1]


def test_downloads_are_named_after_the_configuration(app, tmp_path, finish_run):
    _reset(app, model="3d", length=0.6)
    result = finish_run(app)
    name, content = app.downloads.rrd()
    assert name == "wheelrail-3d-corrugated-rail-line0-100kmh-65kN-0.6m.rrd"
    assert app.page.last_download == (name, len(content))
    path = tmp_path / name
    path.write_bytes(content)
    assert np.allclose(read_recording(path).force, result.force)
    # every plot exports as a PNG named after the configuration and titled with it
    name, content = app.downloads.plot_png("contact force")
    assert name == "wheelrail-plot-corrugated-rail-line0-100kmh-65kN-0.6m-contact-force.png"
    assert content[:8] == b"\x89PNG\r\n\x1a\n" and len(content) > 5000
    from PIL import Image

    image = Image.open(io.BytesIO(content))
    assert image.size[0] > 500 and len(np.unique(np.asarray(image.convert("L")))) > 10  # a drawn chart, not a blank
    for which in ("displacement", "force spectra", "contact filters", "roughness spectrum", "lateral coherence"):
        assert app.downloads.plot_png(which)[1][:4] == b"\x89PNG"
    with pytest.raises(WheelrailError, match="unknown plot 'pie'"):
        app.downloads.plot_png("pie")


def test_only_valid_choices_are_offered_and_bad_values_are_refused(app, finish_run):
    _reset(app, model="hertz", length=1.0)
    result = finish_run(app)
    assert app.form.line_dropdown.options == tuple(str(n) for n in range(-9, 10))
    # 3d: only the lines whose window fits the set (core's window_lines)
    app.form.line_dropdown.value = "7"
    app.form.model_dropdown.value = "3d"
    rough = load_roughness("corrugated-rail")
    expected = window_lines(rough, ModelParameters(contact=ContactParameters(preload=65e3)))
    assert app.form.line_dropdown.options == tuple(map(str, expected)) and expected == (-2, -1, 0, 1, 2)
    assert app.form.line_dropdown.value == "2" and "Line 7 is not offered for 3d" in app.page.status_md.content
    for field, value, message in [
        (app.form.fields["speed"], "450", "Speed 450 km/h is outside the accepted 5 to 400 km/h"),
        (app.form.fields["speed"], "abc", "Speed 'abc': not a number"),
        (app.form.fields["preload"], "0", "Preload 0 kN is outside the accepted 1 to 500 kN"),
        (
            app.form.length_text,
            "9",
            "Run length 9 m is outside the accepted 0.572 to 7.959 m (on corrugated-rail at 100 km/h",
        ),
        (app.form.length_text, "0.1", "Run length 0.1 m is outside the accepted 0.572 to 7.959 m"),
    ]:
        old = field.value
        field.value = value
        assert message in app.form.check_md.content
        assert not app.start_run()
        assert message in app.page.last_error and "--" not in app.page.last_error
        field.value = old
    # a line sent by a page that was not offered moves to the nearest offered one, saying so
    app.form.line_dropdown.value = "9"
    assert app.form.line_dropdown.value == "2" and "Line 9 is not offered for 3d" in app.page.status_md.content
    with pytest.raises(
        WheelrailError,
        match="Line 9 is too near the edge of corrugated-rail for the 3d contact "
        "patch at 65 kN; choose a line from -2 to 2",
    ):
        read_config(rough, "corrugated-rail", line="9", model="3d", speed_kmh="100", preload_kn="65", length_m="1")
    app.form.model_dropdown.value = "hertz"
    app.form.line_dropdown.value = "0"
    # a malformed CSV upload
    bad = SimpleNamespace(
        target=SimpleNamespace(value=SimpleNamespace(name="bad.csv", content=b"x_m,z\n0,abc\n")), client=None
    )
    app.page.upload(bad, app.form.load_upload)
    assert app.page.last_error.startswith("upload 'bad.csv'")
    assert app.form.roughness_label == "corrugated-rail"
    big = SimpleNamespace(
        target=SimpleNamespace(value=SimpleNamespace(name="big.csv", content=b"0" * 1_200_000)), client=None
    )
    app.page.upload(big, app.form.load_upload)
    assert app.page.last_error == "upload 'big.csv' (1.14 MB) is over the 977 kB limit"
    app.page.upload(
        SimpleNamespace(
            target=SimpleNamespace(value=SimpleNamespace(name="../../etc/passwd", content=b"root")), client=None
        ),
        app.form.load_upload,
    )
    assert "expected a .csv or .npz" in app.page.last_error and "passwd" in app.page.last_error
    # a set name sent by a page is never opened as a server path
    app.form.set_dropdown.value = "/etc/passwd"
    assert app.page.last_error == "unknown roughness set '/etc/passwd'; choose a bundled set or upload a file"
    assert app.form.roughness_label == "corrugated-rail"
    # nothing computed is lost and the server keeps working
    assert app.store.entries(app.shown.case())["hertz"].result is result
    again = finish_run(app)
    assert again.model == "hertz" and app.page.status_md.content.startswith("Done: hertz")


def test_upload_a_user_csv_and_run_on_it(app, tmp_path, finish_run):
    rail = load_roughness("corrugated-rail")
    small = rail.with_heights(rail.heights[6:13, :1500], y=rail.y[6:13], note="explorer test")
    path = tmp_path / "mine.csv"
    write_csv(small, path)
    event = SimpleNamespace(
        target=SimpleNamespace(value=SimpleNamespace(name="C:\\data\\mine.csv", content=path.read_bytes())), client=None
    )
    app.form.model_dropdown.value = "2d"
    app.page.upload(event, app.form.load_upload)
    assert app.form.roughness_label == "upload: mine.csv"
    assert "upload: mine.csv" in app.form.set_dropdown.options and app.form.set_dropdown.value == "upload: mine.csv"
    assert app.form.line_dropdown.options == ("-3", "-2", "-1", "0", "1", "2", "3")
    assert "Run length 0.572 to 1.459 m" in app.form.check_md.content  # the bound of this file, shown
    _reset(app, set_name="upload: mine.csv", line=1, model="2d", length=1.0)
    result = finish_run(app)
    assert app.page.last_error is None and result.line == 1 and result.n_steps == 1000


def test_geometry_fields_refuse_bad_values_in_words(app):
    _reset(app, model="3d")
    for field, value, message in [
        (app.form.fields["wheel_radius"], "abc", "Wheel radius 'abc': not a number"),
        (app.form.fields["wheel_radius"], "-460", "Wheel radius -460 mm is outside the accepted 100 to 1250 mm"),
        (app.form.fields["rail_crown_radius"], "0", "Rail crown radius 0 mm is outside the accepted 50 to 5000 mm"),
        (
            app.form.fields["wheel_transverse_radius"],
            "0",
            "Wheel tread radius across 0 mm is outside the accepted range, a magnitude of at least 50 mm",
        ),
        # a concave tread tighter than the crown conforms with it across the rail: core's check, the page's words
        (
            app.form.fields["wheel_transverse_radius"],
            "-300",
            "Wheel tread radius across -300 mm: a concave tread of radius 0.3 m fits the "
            "rail crown of radius 0.39 m or closer",
        ),
        # a concave tread close to the crown makes a patch too wide for Hertz's theory at the preload
        (
            app.form.fields["wheel_transverse_radius"],
            "-390.5",
            "Wheel tread radius across -390.5 mm: the Hertz patch at the preload would be",
        ),
    ]:
        field.value = value
        assert message in app.form.check_md.content
        assert not app.start_run()
        assert (
            message in app.page.last_error
            and "--" not in app.page.last_error
            and "ContactParameters" not in app.page.last_error
        )
        field.value = ""
    # a patch too wide across for the set: said in words, no line offered is pretended
    app.form.fields["rail_crown_radius"].value, app.form.fields["wheel_transverse_radius"].value = "800", "-1000"
    assert "The 3d contact patch at 65 kN is 32.3 mm wide across the rail and 3d needs data 36 mm across" in (
        app.form.check_md.content
    )
    assert not app.start_run()
    app.form.fields["rail_crown_radius"].value = app.form.fields["wheel_transverse_radius"].value = ""
    # a wheel set is added to a rail set only
    _reset(app, set_name="cast-iron-wheel", wheel_set="sinter-wheel-1")
    assert not app.start_run()
    assert "A wheel roughness is added to a rail set, and cast-iron-wheel is a wheel set" in app.page.last_error
    app.form.wheel_set_dropdown.value = "/etc/passwd"  # a name sent by a page is never opened
    assert (
        app.page.last_error.startswith("unknown wheel set '/etc/passwd'")
        and app.form.wheel_set_dropdown.value == "none"
    )


def test_a_run_with_a_wheel_set_names_both_sets(app, finish_run):
    _reset(app, model="hertz", wheel_set="sinter-wheel-1")
    assert not app.start_run()  # the bundled wheel sets are 2.900 m round: not a 390 mm wheel's roughness
    assert (
        app.page.last_error.startswith(
            "Wheel radius 390 mm: the wheel set sinter-wheel-1 is 2.9 m round (a wheel of radius 0.4615 m)"
        )
        and "accepted 456.98 to 466.211 mm" in app.page.last_error
    )
    _reset(app, model="hertz", wheel_set="sinter-wheel-1", geometry_mm=("461.5", "", ""))
    assert app.form.wheel_set_dropdown.options == ("none", "cast-iron-wheel", "sinter-wheel-1", "sinter-wheel-2")
    result = finish_run(app)
    assert app.page.last_error is None
    assert result.header.roughness_name == "corrugated-rail"
    assert result.header.wheel_roughness_name == "sinter-wheel-1"
    assert app.page.status_md.content.startswith("Done: hertz on corrugated-rail + sinter-wheel-1, line 0")
    assert (
        app.tab(PatchTab).force.handle.title == "Contact force: corrugated-rail + sinter-wheel-1, line 0, 100 km/h, "
        "65 kN, 0.6 m, wheel radius 461.5 mm; the paper's track"
    )
    # the rail alone is another case: its plots do not show the combined run
    app.form.wheel_set_dropdown.value = "none"
    assert "hertz" not in app.store.entries(app.shown.case())
    assert app.tab(PatchTab).force.handle.title == (
        "Contact force: corrugated-rail, line 0, 100 km/h, 65 kN, 0.6 m, wheel radius 461.5 mm; the paper's track"
    )


def test_the_drawn_wheel_surface_pairs_the_wheel_set_by_lateral_position(app):
    # corrugated-rail lines 1 mm apart, sinter-wheel-1 2 mm: around line 1 the wheel drawn at the rail row
    # y = 1 mm is the mean of the wheel's lines at 0 and 2 mm (core's linear interpolation), not its line 1
    rail, wheel = load_roughness("corrugated-rail"), load_roughness("sinter-wheel-1")
    contact = ContactParameters()
    position = 0.5
    _, drawn = app.scene._surface_vertices(rail, position, 1, contact, wheel)
    _, smooth = app.scene._surface_vertices(rail, position, 1, contact, wheel.with_heights(0 * wheel.heights))
    n_x = app.scene._surface_x.size
    rows = (drawn[:, 2] - smooth[:, 2]).reshape(-1, n_x)  # the wheel's heights as drawn (scene units)
    y_rows = smooth[::n_x, 1]
    centre = int(np.argmin(np.abs(y_rows)))  # the rail row of line 1 (y = 1 mm)
    expected = app.scene._heights(wheel, [wheel.row_of_line(0), wheel.row_of_line(1)], position).mean(axis=0)
    # the wheel is drawn lifted wholly above the patch (its lowest point SURFACE_GAP above it): one constant
    # shift of the whole surface, which differs between the two draws
    shift = rows[centre] - expected * SCENE_PER_MM
    np.testing.assert_allclose(shift, shift.mean(), rtol=0, atol=1e-6)
    assert np.ptp(expected) * SCENE_PER_MM > 100 * 1e-6  # the heights compared are far above that tolerance


def test_changing_the_geometry_hides_the_old_results(app, finish_run):
    _reset(app, model="3d", length=0.6)
    old = finish_run(app)
    assert app.store.entries(app.shown.case())["3d"].result is old and not app.tab(PatchTab).rrd_button.disabled
    app.form.fields["wheel_radius"].value = "460"
    app.form.fields["rail_crown_radius"].value = "300"
    assert app.store.entries(app.shown.case()) == {}  # nothing of the old geometry is shown as current
    assert (
        app.tab(PatchTab).rrd_button.disabled and app.tab(SpectraTab).csv_button.disabled and app.replay.entry is None
    )
    assert app.tab(PatchTab).force.handle.title.endswith(
        "0.6 m, wheel radius 460 mm, rail crown radius 300 mm; the paper's track"
    )
    # the nominal Hertz outline is the ellipse of this geometry (semi-axes a along, b across; 1 scene unit 10 mm)
    contact = ContactParameters(wheel_radius=0.46, rail_crown_radius=0.3)
    a, b = contact.hertz_semi_axes()
    points = app.scene.nominal_circle.points.reshape(-1, 3)
    assert np.abs(points[:, 0]).max() * 1e-2 == pytest.approx(a, rel=1e-5)  # float32 points
    assert np.abs(points[:, 1]).max() * 1e-2 == pytest.approx(b, rel=1e-5)
    assert a > b * 1.1  # a wheel larger than the crown: longer along the rail than across
    new = finish_run(app)
    assert new.parameters["contact"]["wheel_radius"] == pytest.approx(0.46)
    assert new.parameters["contact"]["rail_crown_radius"] == pytest.approx(0.3)
    assert app.replay.entry.result is new
    app.form.fields["wheel_radius"].value = app.form.fields["rail_crown_radius"].value = (
        ""  # back: the old run shows again
    )
    assert app.store.entries(app.shown.case())["3d"].result is old


def test_wheelrail_explore_serves_the_page_on_localhost(free_port):
    import subprocess
    import sys
    import urllib.request

    port = free_port
    process = subprocess.Popen(
        [sys.executable, "-m", "wheelrail", "explore", "--port", str(port), "--set", "sinter-wheel-1"],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
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
    from wheelrail.cli import main  # the `wheelrail` command: core's commands and `explore`

    assert main(["explore", "--set", "nope"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("wheelrail explore: error: --set 'nope' is not a bundled set") and "\n" not in err


def test_runs_of_another_configuration_are_overlaid_only_on_purpose(app, finish_run):
    """The run list offers this session's other configurations; one chosen is drawn dashed and
    labelled with its configuration; 'none' takes it away again."""
    _reset(app, model="hertz", speed=100.0, length=0.8)
    finish_run(app)
    _reset(app, model="hertz", speed=80.0, length=0.8)
    finish_run(app)
    other = "corrugated-rail, line 0, 100 km/h, 65 kN, 0.8 m"
    options = app.tab(
        SpectraTab
    ).overlay_dropdown.options  # the module's tests share the app: their runs are listed too
    assert options[0] == "none" and other in options and app.shown.case_label() not in options
    assert [label for label, _, _ in app.tab(SpectraTab).spectra.series] == ["hertz"]  # nothing else by accident
    app.tab(SpectraTab).overlay_dropdown.value = other
    series = app.tab(SpectraTab).spectra.series
    labels = [label for label, _, _ in series]
    assert labels[0] == "hertz" and f"hertz [{other}]" in labels  # (an earlier test ran a compare there too)
    assert all(label.endswith(f"[{other}]") and style == "dashed" for label, _, style in series[1:])
    assert app.tab(SpectraTab).spectra.handle.title.endswith(f"(dashed: {other})")
    # the overlaid levels are that configuration's own, band for band where every curve is defined
    theirs = app.store.spectra(app.store.run_list()[other].case())
    columns = [app.store.spectra(app.shown.case())["hertz"][1], *(levels for _, levels in theirs.values())]
    keep = np.all(np.isfinite(columns), axis=0)
    index = labels.index(f"hertz [{other}]")
    assert np.allclose(app.tab(SpectraTab).spectra.handle.data[index + 1], theirs["hertz"][1][keep])
    app.tab(SpectraTab).overlay_dropdown.value = "none"
    assert [label for label, _, _ in app.tab(SpectraTab).spectra.series] == ["hertz"]


def test_the_track_tab_draws_the_lateral_decay_rate_against_its_limit(app):
    from wheelrail.core.noise.decay import track_lateral_decay

    _reset(app)
    tab = app.tab(TrackTab)
    track = app.shown.params().track
    tab._compute(track)
    assert [label for label, *_ in tab.lateral.series] == ["decay rate", "EN ISO 3095:2013 limit"]
    f, decay, limit = tab.lateral.data
    at_1k = int(np.argmin(np.abs(f - 1000)))
    assert limit[at_1k] == 0.2 and limit[int(np.argmin(np.abs(f - 250)))] == 2.04  # Figure 3, curve B
    expected = track_lateral_decay(track)  # core's numbers, band for band (NaN-free: 50 Hz-5 kHz)
    assert np.allclose(decay, expected["decay_rate_dB_per_m"][: len(decay)])
    # the paper's undamped rail decays laterally below the limit at 250-500 Hz and from 1.6 kHz
    # (tests/physics/test_track_lateral.py; validation/lateral_convergence.py)
    assert tab.lateral.handle.title.startswith(
        "Lateral decay rate of the paper's track is below EN ISO 3095:2013's lower limit at 250, 315, 400, 500, 1600"
    )
    # a lateral pad input changes the lateral curve, named as its title says
    app.form.fields["pad_lateral_stiffness"].value = "60"
    tab._compute(app.shown.params().track)
    assert tab.lateral.handle.title.startswith(
        "Lateral decay rate of the track with pad lateral stiffness 60 MN/m (else the paper's) "
    )
    assert not np.allclose(tab.lateral.data[1], decay)
    app.form.fields["pad_lateral_stiffness"].value = "30"


def test_the_track_tab_draws_receptance_and_decay_against_the_limit(app):

    _reset(app)
    tab = app.tab(TrackTab)
    track = app.shown.params().track
    tab._compute(track)  # what its background thread does for a new track (then it redraws)
    assert "pad stiffness 120 MN/m" in tab.track_md.content
    # its resonances, each named (tests/physics/test_track_resonances.py)
    words = tab.resonances_md.content
    assert "sleeper-on-ballast 110.6 Hz" in words and "rail-on-pad 284.8 Hz" in words
    assert "pinned-pinned 941.0 Hz" in words
    assert [label for label, *_ in tab.receptance.series] == ["above a sleeper", "midspan"]
    receptance = tab.receptance.data
    assert 40 < receptance[0][0] < 70 and receptance[0][-1] > 4000  # Hz: the bands 50 Hz-5 kHz
    assert np.all(receptance[1] < -150) and np.all(receptance[1] > -220)  # dB re 1 m/N: 1e-11 to 1e-7.5 m/N
    # the paper's track is below the limit at 400-800 Hz (2.3-3.7 dB/m against 6; tests/physics/test_track_decay.py)
    # and at 2.5 kHz
    assert tab.decay.handle.title == (
        "Vertical decay rate of the paper's track is below EN ISO 3095:2013's lower limit at 400, 500, 630, 800 "
        "and 2500 Hz"
    )
    decay, limit = tab.decay.data[1], tab.decay.data[2]
    f = tab.decay.data[0]
    at_500 = int(np.argmin(np.abs(f - 500)))
    assert decay[at_500] < limit[at_500] == 6.0
    # each plot and its PNG name the track: the paper's, or the inputs that differ from it
    assert tab.receptance.handle.title == "Point receptance of the paper's track"
    app.form.fields["pad_stiffness"].value = "60"
    tab._compute(app.shown.params().track)
    words = "the track with pad stiffness 60 MN/m (else the paper's)"
    assert tab.receptance.handle.title == f"Point receptance of {words}"
    assert tab.decay.handle.title.startswith(f"Vertical decay rate of {words} ")
    assert tab.receptance.figure().axes[0].get_title().replace("\n", " ") == f"Point receptance of {words}"
