"""The explorer's Wheel tab without a browser: the wheel it states, its natural frequencies by family and n, its
receptances at the contact beside the Track tab's, its sound power per band, and its shape fields' errors in the
page's words.

The tab's modes, and the noise chain's that its sound power uses, are computed up to 3 kHz and n = 0..4 (seconds,
not the page's 12.5 kHz and n = 0..10), its band means on 10 frequencies per band: what is tested is what the tab
draws from core's modes and radiation, not them (tests/physics/test_modal_wheel*, test_wheel_radiation.py).
The tests with the explorer (a server, seconds to start) are marked slow; reading the tab's fields is not.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.declared import inputs_of
from wheelrail.core.modal_wheel import contact_receptance, wheel_modes, wheel_profile_for
from wheelrail.core.noise import wheel_power
from wheelrail.core.noise.twins import band_frequencies
from wheelrail.explorer import wheel_tab
from wheelrail.explorer.config import NEAREST_WHEEL, page_message, read_wheel
from wheelrail.explorer.tabs import TrackTab, WheelTab

COARSE = {"max_frequency": 3000.0, "max_harmonic": 4}
POINTS_PER_BAND = 10


@pytest.fixture(scope="module", autouse=True)
def coarse_wheel():
    """The module's explorer (conftest's ``app``, made after this) computes its wheels' modes up to 3 kHz and
    n = 0..4, the noise chain's too (its radiation table then holds n = 0..4: the table's memory cache, keyed by
    the profile alone, is emptied before and after)."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(wheel_tab, "MODE_SETTINGS", COARSE)
        patch.setattr(wheel_tab, "WHEEL_POINTS_PER_BAND", POINTS_PER_BAND)
        patch.setattr(wheel_power, "MAX_FREQUENCY", COARSE["max_frequency"])
        patch.setattr(wheel_power, "MAX_HARMONIC", COARSE["max_harmonic"])
        wheel_power.radiation_table.cache_clear()
        yield
    wheel_power.radiation_table.cache_clear()


def _shown(app, **shape):
    """The paper's configuration (its R = 390 mm: the nearest named wheel is wheel_840), the tab's fields set, the
    wheel's modes and the track's curves computed here (what the background threads do), the tab redrawn."""
    for key in ("wheel_radius", "rail_crown_radius", "wheel_transverse_radius"):
        app.form.fields[key].value = ""
    for entry in inputs_of("track"):
        app.form.fields[entry.key].value = f"{entry.shown_default():g}"
    tab = app.tab(WheelTab)
    tab.name_dropdown.value = shape.pop("name", wheel_tab.NEAREST_WHEEL)
    tab.added_text.value = shape.pop("added", "")
    for key, field in tab.shape_fields.items():
        field.value = shape.get(key, "")
    app.page.last_error = None
    track_tab = app.tab(TrackTab)
    track = app.shown.params().track
    if not isinstance(track_tab.curves(track), tuple):
        track_tab._compute(track)
    try:
        profile, _ = tab.read(app.shown)
    except Exception:  # a refused shape: nothing to compute
        profile = None
    if profile is not None:
        key = (profile, tuple(sorted(tab.mode_settings.items())))
        tab.compute(key)
        tab.compute_power(key)
    app.redraw_tab(tab)
    return tab


@pytest.mark.slow
def test_the_wheel_tab_states_its_wheel_and_draws_the_natural_frequencies_by_family_and_n(app):
    tab = _shown(app)
    assert tab.mode_settings == COARSE
    words = tab.wheel_md.content
    assert "**Wheel:** wheel_840's shape at the run's rolling radius, diameter 780 mm (wheel_840: 840 mm)" in words
    assert "rim 135 mm wide, 45 mm deep; web 22 mm thick" in words and "up to 3000 Hz, n = 0..4" in words
    modes = wheel_modes(wheel_profile_for(0.39), **COARSE)  # core's own, read from the cache the tab filled
    assert words.endswith(f"{len(modes.frequency)} modes up to 3000 Hz, n = 0..4.")
    x, *columns = tab.frequencies.data
    assert list(x) == [0, 1, 2, 3, 4]
    labels = [label for label, *_ in tab.frequencies.series]
    assert labels[0] == "axial 1st"
    lowest_axial = [np.min(modes.frequency[(modes.harmonic == n) & (modes.family == "axial")]) for n in range(5)]
    np.testing.assert_allclose(columns[0], lowest_axial, rtol=1e-12)  # drawn as computed
    assert np.all(np.diff(columns[0][2:]) > 0)  # axial (n, 0) modes rise with n from n = 2 (a wheel's fan)
    for family in ("radial", "circumferential"):
        if np.any(modes.family == family):
            assert f"{family} 1st" in labels
    row_2 = next(line for line in tab.table_md.content.splitlines() if line.startswith("| 2 |"))
    axial_2 = np.sort(modes.frequency[(modes.harmonic == 2) & (modes.family == "axial")])
    assert row_2.split(" | ")[1] == ", ".join(f"{f:.0f}" for f in axial_2)
    for which in ("wheel natural frequencies", "wheel receptance", "wheel sound power"):  # the PNG menu's
        name, content = app.downloads.plot_png(which)
        assert content[:4] == b"\x89PNG" and name.endswith(".png")


@pytest.mark.slow
def test_the_wheel_receptance_is_drawn_beside_the_tracks_on_its_bands(app):
    tab = _shown(app)
    track_tab = app.tab(TrackTab)
    assert tab in track_tab.followers  # redrawn when the track's curves are computed
    labels = [label for label, *_ in tab.receptance.series]
    assert labels == ["wheel radial", "wheel axial", "wheel cross", "track above a sleeper", "track midspan"]
    f, radial, axial, cross, sleeper, midspan = tab.receptance.data
    bands = track_tab.curves(app.shown.params().track)[0]
    at = np.searchsorted(f, bands["frequency_hz"])
    np.testing.assert_allclose(f[at], bands["frequency_hz"], rtol=1e-12)  # every band centre is on the axis
    # the track's levels at its band centres are the Track tab's (interpolated only between them)
    np.testing.assert_allclose(sleeper[at], 20 * np.log10(bands["above_sleeper_m_per_n"]), atol=1e-9)
    np.testing.assert_allclose(midspan[at], 20 * np.log10(bands["midspan_m_per_n"]), atol=1e-9)
    modes = wheel_modes(wheel_profile_for(0.39), **COARSE)
    wheel = contact_receptance(modes, f)
    np.testing.assert_allclose(radial, 20 * np.log10(np.abs(wheel.radial)), atol=1e-9)
    np.testing.assert_allclose(cross, 20 * np.log10(np.abs(wheel.cross)), atol=1e-9)
    # below its first modes the clamped wheel is far stiffer than the track: at 100 Hz its radial receptance
    # (about 1e-9 m/N: -181 dB) is more than 15 dB below the paper's track's (about 8e-9 m/N: -162 dB)
    at_100 = int(np.argmin(np.abs(f - 100.0)))
    assert radial[at_100] < sleeper[at_100] - 15
    # each natural frequency in range is on the axis: the lowest radial n >= 2 mode's peak stands > 10 dB above the
    # curve 0.2 % either side (its half-power width is eta f = 0.01 % of f)
    f_radial = np.min(modes.frequency[(modes.family == "radial") & (modes.harmonic >= 2)])
    peak = int(np.argmin(np.abs(f - f_radial)))
    assert f[peak] == pytest.approx(f_radial, rel=1e-12)
    near = np.abs(f / f_radial - 1) > 0.002
    neighbours = [np.flatnonzero(near & (f < f_radial))[-1], np.flatnonzero(near & (f > f_radial))[0]]
    assert radial[peak] > max(radial[neighbours]) + 10
    assert np.all(np.isfinite(axial))


@pytest.mark.slow
def test_an_added_loss_factor_lowers_the_wheels_resonance(app):
    tab = _shown(app)
    f, radial = tab.receptance.data[0], tab.receptance.data[1]
    modes = wheel_modes(wheel_profile_for(0.39), **COARSE)
    f_radial = np.min(modes.frequency[(modes.family == "radial") & (modes.harmonic >= 2)])
    undamped = radial[int(np.argmin(np.abs(f - f_radial)))]
    tab = _shown(app, added="0.01")
    assert "added loss factor 0.01." in tab.wheel_md.content
    f, radial = tab.receptance.data[0], tab.receptance.data[1]
    damped = radial[int(np.argmin(np.abs(f - f_radial)))]
    # the mode's peak falls as 1 / eta (1e-4 to 1.01e-2: 40 dB) until the other modes' background is reached
    assert damped < undamped - 20


@pytest.mark.slow
def test_shape_fields_change_the_wheel_or_say_what_is_wrong(app):
    tab = _shown(app, wheel_web_thickness="30", name="freight_920")
    assert "**Wheel:** freight_920's shape (changed: web thickness)" in tab.wheel_md.content
    assert "diameter 780 mm (freight_920: 920 mm)" in tab.wheel_md.content
    assert "web 30 mm thick" in tab.wheel_md.content
    tab = _shown(app, wheel_tyre_width="500")
    assert tab.wheel_md.content == (
        "**Cannot make this wheel:** Tyre width 500 mm is outside the accepted 80 to 200 mm "
        "(a rim's width: 135 mm on standard-gauge wheels)"
    )
    assert not any(plot.visible for plot in tab.plots().values())  # no empty plots: the words say why
    tab = _shown(app, wheel_hub_width="wide")
    assert tab.wheel_md.content == "**Cannot make this wheel:** Hub width 'wide': not a number"
    tab = _shown(app, added="2")
    assert "Added loss factor 2 is outside the accepted 0 to 1" in tab.wheel_md.content
    assert app.page.last_error is None  # the tab says it; nothing was pressed
    _shown(app)


def test_the_wheel_fields_read_as_the_named_wheel_at_the_runs_radius_with_the_dimensions_typed():
    profile, added = read_wheel(NEAREST_WHEEL, 0.39, {"wheel_tyre_width": "", "wheel_web_thickness": "30"}, "")
    assert profile == replace(wheel_profile_for(0.39, "wheel_840"), web_thickness=0.03)
    assert added == 0.0
    profile, added = read_wheel("wheel_640", 0.32, {}, "0,05")  # a decimal comma, as the run form takes
    assert profile == wheel_profile_for(0.32, "wheel_640") and added == 0.05
    with pytest.raises(WheelrailError) as error:
        read_wheel("wheel_999", 0.39, {}, "")
    assert page_message(error.value).startswith("Wheel shape: unknown wheel 'wheel_999'")
    with pytest.raises(WheelrailError) as error:
        read_wheel(NEAREST_WHEEL, 0.39, {"wheel_contact_offset": "70"}, "")
    assert "Contact offset" in page_message(error.value)
    with pytest.raises(WheelrailError) as error:  # what a wheel is: the same rules as an outline's (section.py)
        read_wheel(NEAREST_WHEEL, 0.39, {"wheel_flange_thickness": "5"}, "")
    assert page_message(error.value).startswith("Flange thickness 5 mm: the cross-section is 5 mm thick at r = ")


@pytest.mark.slow
def test_the_wheels_sound_power_per_band_is_the_noise_chains(app):
    tab = _shown(app)
    assert tab.points_per_band == POINTS_PER_BAND
    # the total last: drawn over its parts, never hidden under the one that carries it
    assert [label for label, *_ in tab.power.series] == ["axial surfaces", "radial surfaces", "total"]
    f, axial, radial, total = tab.power.data
    assert f[0] == pytest.approx(50.1, abs=0.1) and f[-1] == pytest.approx(10e3) and len(f) == 24
    profile = wheel_profile_for(0.39)
    bands = band_frequencies(POINTS_PER_BAND)
    for b in (3, 12, 17):  # 100 Hz, 800 Hz, 2.5 kHz: the chain's response averaged over the band, in dB re 1 pW
        response = wheel_power.modal_wheel_response(profile, bands[b], 500.0)
        assert total[b] == pytest.approx(10 * np.log10(np.mean(response["power_per_force"]) / 1e-12), abs=1e-9)
    # the two surfaces' powers add up to the total (powers of different surfaces add)
    np.testing.assert_allclose(10 ** (total / 10), 10 ** (axial / 10) + 10 ** (radial / 10), rtol=1e-9)
    # far below its first modes a wheel radiates little (sigma ~ (ka)^2 or less): the 50-100 Hz bands are more than
    # 30 dB below the loudest band of 1-3 kHz, where its axial modes radiate (about -12 to 8 dB against 50-60 dB)
    assert np.max(total[:4]) < np.max(total[(f > 900) & (f < 3200)]) - 30


PLOTS_IN_PAGE = """() => Object.values((window.__viserTestpoints || {}).uplots || {}).map(t => {
    const r = t.chart.root.getBoundingClientRect();
    return {title: String((t.chart.root.querySelector('.u-title') || {}).textContent || ''),
            labels: t.chart.series.slice(1).map(s => String(s.label)), width: r.width, height: r.height};
}).filter(p => p.width > 0 && p.height > 0)"""


@pytest.mark.slow
def test_the_wheel_tab_in_the_page_shows_its_plots(open_page):
    """Headless Chromium: the Wheel tab, clicked, shows its three plots with the curves the page's session drew."""
    page, session, errors = open_page(1280, 800)
    tab = _shown(session)
    try:
        page.get_by_role("tab", name=WheelTab.title).click()
        page.wait_for_function(f"() => ({PLOTS_IN_PAGE})().length >= 3", timeout=90_000)
        plots = {plot["title"].split(":")[0]: plot for plot in page.evaluate(PLOTS_IN_PAGE)}
        assert plots["Natural frequencies by family and n"]["labels"][:2] == ["axial 1st", "axial 2nd"]
        assert plots["Receptance at the contact"]["labels"] == [label for label, *_ in tab.receptance.series]
        assert plots["Sound power of one wheel for 1 N radial force at the contact"]["labels"] == [
            "axial surfaces",
            "radial surfaces",
            "total",
        ]
        # each names the wheel (core's describe_wheel), the receptance the track too
        wheel = "wheel wheel_840, diameter 780 mm"
        assert all(plot["title"].split(": ", 1)[1].startswith(wheel) for plot in plots.values())
        assert plots["Receptance at the contact"]["title"].endswith(f"{wheel}; the paper's track")
        assert min(plot["width"] for plot in plots.values()) >= 480  # px: the results panel's plots
        assert not errors, errors
    finally:
        page.close()


@pytest.mark.slow
def test_the_wheel_is_computed_only_once_asked(app):
    """Opening the explorer computes no wheel (a first Run keeps the machine); Compute the wheel starts the worker on
    the shape shown, and later shapes follow."""
    tab = app.tab(WheelTab)
    tab.asked = False
    tab.shape_fields["wheel_web_thickness"].value = "27"  # a shape no other test computed
    app.redraw_tab(tab)
    profile, _ = tab.read(app.shown)
    key = (profile, tuple(sorted(tab.mode_settings.items())))
    assert key not in tab._modes and not tab._working and tab._wanted != key
    # nothing computed: no empty plots above the button, and the words are markdown (no literal asterisks)
    assert not any(plot.visible for plot in tab.plots().values())
    assert not any(plot.handle.visible for plot in tab.plots().values())
    assert tab.wheel_md.content.endswith(
        "Press **Compute the wheel** (below, under the *Wheel shape* folder) for this wheel's modes and sound power."
    )
    assert not any("*" in label for plot in tab.plots().values() for label, *_ in plot.series)
    tab.ask()
    assert tab.asked and tab._wanted == key  # the worker was handed this shape (it computes it in the background)
    tab.shape_fields["wheel_web_thickness"].value = ""


@pytest.mark.slow
def test_the_sound_power_shows_its_phase_bar_and_estimate_while_computed(app, monkeypatch):
    """The radiation table (a minute or more for a new radius, rim or bore) reports each harmonic and direction:
    while it is computed the power plot's line names the phase with the time left and the tab's bar moves; both go
    once the power is drawn. The radiation here is a stand-in held on an event at its third column."""
    import threading

    from wheelrail.core.files import cache
    from wheelrail.core.modal_wheel import radiation

    tab = _shown(app)
    profile, _ = tab.read(app.shown)
    key = (profile, tuple(sorted(tab.mode_settings.items())))
    entered, release, calls = threading.Event(), threading.Event(), []

    def efficiency(f, n, direction, **geometry):
        calls.append((n, direction))
        if len(calls) == 3:
            entered.set()
            assert release.wait(120)
        return np.full(len(f), 0.5)

    real_load = cache.load_entry
    monkeypatch.setattr(radiation, "wheel_radiation_efficiency", efficiency)
    monkeypatch.setattr(
        cache, "load_entry", lambda kind, *a: None if kind == "wheel-radiation" else real_load(kind, *a)
    )
    monkeypatch.setattr(cache, "save_entry", lambda *args, **kwargs: None)  # the stand-in's table is not kept
    wheel_power.radiation_table.cache_clear()
    tab._power.pop(tab._power_key(key))
    tab._wanted = key  # the shape shown, as the worker computes it
    worker = threading.Thread(target=tab.compute_power, args=(key,))
    worker.start()
    try:
        assert entered.wait(120)
        columns = 2 * (COARSE["max_harmonic"] + 1)
        assert tab.power_bar.visible and tab.power_bar.value == round(100.0 * 2 / columns, 1)
        line = tab.power.series[0][0]
        assert line.startswith(
            f"computing the wheel's sound power: {wheel_power.RADIATION_PHASE} (2 of {columns}), about "
        ), line
        assert line.endswith(" s left ...")
        release.set()
        worker.join(120)
        assert not tab.power_bar.visible and tab._progress is None
    finally:
        release.set()
        worker.join(120)
        tab._power.pop(tab._power_key(key), None)  # the stand-in's power: the real one again for the other tests
        wheel_power.radiation_table.cache_clear()
