"""Wheel and rail roughness together: r = r_rail + r_wheel on the model grid."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from wheelrail.cli.commands._common import CLI_NAMES
from wheelrail.core.engine import prepare_run, simulate
from wheelrail.core.engine.results import RunHeader, RunResult
from wheelrail.core.engine.track_lines import run_lines, window_lines
from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import ContactParameters, ModelParameters
from wheelrail.core.roughness import RoughnessSet, lines_along_track, load_roughness, to_model_grid
from wheelrail.core.spectra.force import force_spectrum
from wheelrail.explorer.config import page_message

RAIL = load_roughness("corrugated-rail")
BUNDLED_WHEEL = load_roughness("sinter-wheel-1")  # 2.900 m round: the roughness of a 461.5 mm wheel
# A wheel set goes round its own wheel (ranges.check_wheel_circumference). The physics tests keep the paper's
# 390 mm circle and give the wheel set its circumference: the same heights on a 15.5 % shorter spacing.
WHEEL = dataclasses.replace(BUNDLED_WHEEL, dx=BUNDLED_WHEEL.dx * 2 * np.pi * 0.39 / BUNDLED_WHEEL.length)
BUNDLED = ModelParameters(contact=ContactParameters(radius=BUNDLED_WHEEL.length / (2 * np.pi)))  # its own wheel
SMALL = 0.05  # scale of both bundled sets: rms 0.46 um (rail) and 0.13 um (wheel) against a 77 um approach


def _scaled(rough, scale):
    return rough.with_heights(rough.heights * scale)


@pytest.mark.parametrize("model", ["hertz", "2d", "3d"])
@pytest.mark.slow
def test_a_wheel_of_zero_heights_changes_nothing(model, step_arrays):
    # r_rail + 0.0 is r_rail bit for bit, so every array of the run is identical
    length = 0.3 if model == "3d" else 2.0
    alone = simulate(RAIL, model=model, length=length)
    both = simulate(RAIL, wheel_roughness=_scaled(WHEEL, 0.0), model=model, length=length)
    for name in step_arrays:
        np.testing.assert_array_equal(getattr(both, name), getattr(alone, name), err_msg=name)
    if model == "3d":
        np.testing.assert_array_equal(both.pressure, alone.pressure)


@pytest.mark.parametrize("model", ["hertz", "2d", "3d"])
@pytest.mark.slow
def test_small_roughness_superposes(model):
    # Linear regime: the dynamic force of the combined run (minus the smooth run's, which holds the
    # sleeper-passing excitation common to all runs) is the sum of those of the rail alone and the wheel
    # alone, sample by sample. What is left is the contact's non-linearity, of the order of r / delta:
    # measured 0.14 % (hertz), 1e-11 (2d: the same springs stay compressed, a linear law) and 0.33 % (3d) of
    # the rms dynamic force. Bound 1 %.
    length = 1.0 if model == "3d" else 3.0
    smooth = _scaled(RAIL, 0.0)
    rail, wheel = _scaled(RAIL, SMALL), _scaled(WHEEL, SMALL)
    base = simulate(smooth, model=model, length=length).force
    rail_only = simulate(rail, model=model, length=length).force - base
    wheel_only = simulate(smooth, wheel_roughness=wheel, model=model, length=length).force - base
    both = simulate(rail, wheel_roughness=wheel, model=model, length=length).force - base
    assert np.max(np.abs(both - rail_only - wheel_only)) < 0.01 * np.std(both)
    # and the wheel alone on a smooth rail is the wheel set run by itself (its lines repeat the same way)
    np.testing.assert_allclose(
        simulate(wheel, model=model, length=length).force - base, wheel_only, atol=1e-6 * np.std(both)
    )


@pytest.mark.parametrize("model", ["hertz", "2d"])
@pytest.mark.slow
def test_force_spectrum_is_the_energy_sum_of_independent_sets(model):
    # Two independent sets in the linear regime: the combined run's force spectrum (dynamic part, as above)
    # is the energy sum of the two separate runs per third-octave band from 100 Hz to 2 kHz. Within 1 dB
    # is the aim; over the 7.9 m rail (0.28 s after the start-up skip) a band holds few independent estimates
    # (bandwidth x duration = 6 at 100 Hz, 75 at 1.25 kHz), so the cross term of the two finite records is
    # not negligible where their levels are within ~10 dB: measured 0.73 dB worst (250 Hz, hertz and 2d),
    # within 0.71 dB in the other 13 bands. Superposition itself holds to 1 %
    # (test above), so the excess is the data's cross-correlation, not the model. Bound 1.5 dB.
    smooth = _scaled(RAIL, 0.0)
    rail, wheel = _scaled(RAIL, SMALL), _scaled(WHEEL, SMALL)
    base = simulate(smooth, model=model)
    dt = base.time_step

    def levels(result):
        return force_spectrum(result.force - base.force, dt)

    centres, rail_levels = levels(simulate(rail, model=model))
    _, wheel_levels = levels(simulate(smooth, wheel_roughness=wheel, model=model))
    _, both = levels(simulate(rail, wheel_roughness=wheel, model=model))
    band = (centres > 99) & (centres < 2100)
    energy_sum = 10 * np.log10(10 ** (rail_levels / 10) + 10 ** (wheel_levels / 10))
    np.testing.assert_allclose(both[band], energy_sum[band], atol=1.5)


def test_wrong_kinds_are_one_clear_error():
    with pytest.raises(WheelrailError, match="the wheel roughness is a rail set") as info:
        prepare_run(RAIL, wheel_roughness="corrugated-rail", length=0.1)
    assert "\n" not in str(info.value)
    with pytest.raises(WheelrailError, match="the rail roughness must be a rail set"):
        prepare_run(WHEEL, wheel_roughness=WHEEL, length=0.1)


def test_header_and_files_name_both_sets(tmp_path):
    result = simulate("corrugated-rail", wheel_roughness="sinter-wheel-1", model="hertz", length=0.2, params=BUNDLED)
    assert result.roughness_name == "corrugated-rail" and result.wheel_roughness_name == "sinter-wheel-1"
    back = RunResult.load_npz(result.save_npz(tmp_path / "run.npz"))
    assert back.header == result.header
    # a header written before the wheel set existed reads back with none
    old = simulate("corrugated-rail", model="hertz", length=0.05).header.to_dict()
    assert "wheel_roughness" not in old and RunHeader.from_dict(old).wheel_roughness_name is None


WHEEL_ROUND = 2.45  # m, the circumference of _across_sets' wheel set


def _across_sets():
    """A rail set of 19 lines 1 mm apart (small random heights) and a wheel set of 25 lines 2 mm apart whose
    amplitude grows across the tread: r_W(x, y) = A(y) sin(2 pi x / 50 mm), A(y) = 2 um (1 + y / 25 mm), 0.08
    to 3.92 um over +-24 mm. A is linear in y, so the wheel between two of its lines is known exactly. The wheel
    set is 2.45 m round, 49 wavelengths: the paper's 390 mm wheel (2 pi R = 2.4504 m, within the 1 % a wheel
    set must keep to its wheel's circumference, ranges.check_wheel_circumference)."""
    rng = np.random.default_rng(7)
    rail = RoughnessSet(
        heights=0.3e-6 * rng.standard_normal((19, 1501)),
        dx=1e-3,
        y=np.arange(-9, 10) * 1e-3,
        kind="rail",
        description="random rail",
    )
    wheel_y = np.arange(-12, 13) * 2e-3
    wheel_x = np.arange(4900) * 0.5e-3  # 2.45 m round: 49 wavelengths
    heights = _amplitude(wheel_y)[:, None] * np.sin(2 * np.pi * wheel_x / 0.05)[None, :]
    wheel = RoughnessSet(heights=heights, dx=0.5e-3, y=wheel_y, kind="wheel", description="amplitude across")
    return rail, wheel


def _amplitude(y):
    return 2e-6 * (1 + np.asarray(y) / 25e-3)


def _wheel_at(y, x):
    """The wheel set of _across_sets at lateral position y (m) under wheel positions x (m) along the rail."""
    return _amplitude(y) * np.sin(2 * np.pi * np.mod(x, WHEEL_ROUND) / 0.05)


@pytest.mark.parametrize("model", ["hertz", "2d"])
@pytest.mark.parametrize("line", [2, -3])
def test_one_line_models_pair_the_wheel_by_lateral_position(model, line):
    # Rail line n lies at y = n mm; the wheel set's line n at 2n mm. The surfaces that touch are the rail at
    # y = n mm and the wheel at y = n mm (between two wheel lines for odd n), so the roughness the model sees
    # is r_rail(line n) + A(n mm) sin(...); pairing by number would give A(2n mm), 8 % (line 2) to 14 %
    # (line -3) off. Linear interpolation of a linear A is exact, and the wheel's samples fall on the model
    # grid, so the tolerance is round-off (1e-18 m on 4 um).
    rail, wheel = _across_sets()
    result = simulate(rail, wheel_roughness=wheel, model=model, line=line, length=1.0)
    y_line = rail.y[rail.row_of_line(line)]
    expected = np.interp(result.x, rail.x, rail.line(line)) + _wheel_at(y_line, result.x)
    np.testing.assert_allclose(result.roughness, expected, rtol=0, atol=1e-18)
    # and the force is that of one rail set holding the combined surface by hand (the run sees nothing else)
    combined = rail.x
    by_hand = rail.heights.copy()
    by_hand[rail.row_of_line(line)] += _wheel_at(y_line, combined)
    alone = simulate(rail.with_heights(by_hand), model=model, line=line, length=1.0)
    np.testing.assert_allclose(result.force, alone.force, rtol=1e-12)


def test_3d_window_pairs_the_wheel_by_lateral_position():
    # Every row of the 3D window: the rail row at y_line + y' plus the wheel at that same y (y' the row's
    # offset). Line 1 (y = 1 mm) falls between the wheel's lines at 0 and 2 mm; number pairing would centre
    # the wheel on its line 1 at 2 mm. Exact as above.
    rail, wheel = _across_sets()
    run = prepare_run(rail, wheel_roughness=wheel, model="3d", line=1, length=0.05)
    alone = prepare_run(rail, model="3d", line=1, length=0.05)
    np.testing.assert_array_equal(run.window_y, alone.window_y)
    x = np.arange(run.track.lines.shape[1]) * run.dx
    expected = _wheel_at((1e-3 + run.window_y)[:, None], x[None, :])
    np.testing.assert_allclose(run.track.lines - alone.track.lines, expected, rtol=0, atol=1e-18)


def test_bundled_sets_pair_by_position():
    # corrugated-rail (1 mm lines) + sinter-wheel-1 (2 mm lines), line 2: the wheel line under the rail's
    # y = 2 mm is the wheel set's line 1, not its line 2 (at 4 mm). On the wheel the bundled set goes round
    # (BUNDLED, R = 461.5 mm).
    run = prepare_run(
        "corrugated-rail", wheel_roughness="sinter-wheel-1", model="hertz", line=2, length=0.5, params=BUNDLED
    )
    alone = prepare_run("corrugated-rail", model="hertz", line=2, length=0.5, params=BUNDLED)
    wheel = BUNDLED_WHEEL
    n = run.track.lines.shape[1]
    expected = lines_along_track(to_model_grid(wheel, run.dx), [1], (n - 1) * run.dx, run.dx)[0]
    np.testing.assert_allclose(run.track.lines[0] - alone.track.lines[0], expected, rtol=0, atol=1e-18)
    # 3d, line -1 (y = -1 mm, between the wheel's lines at -2 and 0 mm): the window's rows are the wheel
    # interpolated across at the rows' own positions
    run3 = prepare_run(
        "corrugated-rail", wheel_roughness="sinter-wheel-1", model="3d", line=-1, length=0.02, params=BUNDLED
    )
    alone3 = prepare_run("corrugated-rail", model="3d", line=-1, length=0.02, params=BUNDLED)
    grid = to_model_grid(wheel, run3.dx, run3.dx)  # 1 mm across: the wheel at every millimetre
    lines = [grid.line_of_row(int(np.argmin(np.abs(grid.y - y)))) for y in -1e-3 + run3.window_y]
    n = run3.track.lines.shape[1]
    expected = lines_along_track(grid, lines, (n - 1) * run3.dx, run3.dx)
    np.testing.assert_allclose(run3.track.lines - alone3.track.lines, expected, rtol=0, atol=1e-15)


def test_a_wheel_set_that_does_not_cover_the_line_is_refused():
    rail, wheel = _across_sets()
    narrow = wheel.with_heights(wheel.heights[10:15], y=wheel.y[10:15])  # -4..4 mm
    with pytest.raises(WheelrailError, match=r"line 5: the rail set's line lies at y = 5 mm.*-4 \.\. 4 mm") as info:
        prepare_run(rail, wheel_roughness=narrow, model="hertz", line=5, length=0.1)
    assert "\n" not in str(info.value)
    # as data (the line, and the lines the wheel set covers as its range), worded by each front end
    error = info.value
    assert (error.parameter, error.value, error.minimum, error.maximum) == ("line", 5, -4, 4)
    assert "; accepted -4 to 4 (the wheel set is paired with the rail set by lateral position)" in str(error)
    assert error.render(CLI_NAMES).startswith("--line 5: the rail set's line lies at y = 5 mm")
    assert page_message(error).startswith("Line 5: the rail set's line lies at y = 5 mm")
    # a 3d patch needs the wheel across its width (b + 1 element = 7 mm each side at 65 kN): none fits +-4 mm
    with pytest.raises(WheelrailError, match="wheel roughness data") as info:
        prepare_run(rail, wheel_roughness=narrow, model="3d", line=0, length=0.1)
    assert "\n" not in str(info.value) and info.value.parameter == "line"
    assert str(info.value).endswith("; no line can be run")
    # a wheel set of one line covers its own position only
    single = wheel.with_heights(wheel.heights[12:13], y=wheel.y[12:13])
    prepare_run(rail, wheel_roughness=single, model="hertz", line=0, length=0.1)
    with pytest.raises(WheelrailError, match="y = 1 mm"):
        prepare_run(rail, wheel_roughness=single, model="hertz", line=1, length=0.1)


def test_run_lines_follow_the_wheel_sets_coverage():
    rail, wheel = _across_sets()
    narrow = wheel.with_heights(wheel.heights[10:15], y=wheel.y[10:15])  # -4..4 mm
    assert run_lines(rail, "hertz") == tuple(range(-9, 10))
    assert run_lines(rail, "hertz", wheel=narrow) == tuple(range(-4, 5))
    assert run_lines(rail, "3d", wheel=narrow) == ()
    assert run_lines(rail, "3d", wheel=wheel) == run_lines(rail, "3d") == window_lines(rail)
    # every line offered runs
    for line in run_lines(rail, "hertz", wheel=narrow):
        prepare_run(rail, wheel_roughness=narrow, model="hertz", line=line, length=0.01)


def test_the_energetic_sum_of_two_roughness_spectra_is_the_spectrum_of_their_sum():
    """The explorer's combined roughness spectrum: rail and wheel levels added energetically
    (``energy_sum``) match the spectrum of the summed heights of two independent sets."""
    from wheelrail.core.roughness import roughness_spectrum
    from wheelrail.core.spectra.levels import energy_sum

    rng = np.random.default_rng(7)
    first = RAIL.with_heights(rng.normal(0.0, 2e-6, RAIL.heights.shape))
    second = RAIL.with_heights(rng.normal(0.0, 1e-6, RAIL.heights.shape))
    both = RAIL.with_heights(first.heights + second.heights)
    speed = 100 / 3.6
    spectra = [roughness_spectrum(s, speed=speed) for s in (first, second, both)]
    levels = [spectrum.levels_db for spectrum in spectra]
    summed = energy_sum(levels[0], levels[1])
    wanted = np.isfinite(levels[2]) & (spectra[2].band_centres >= 200.0)
    assert wanted.sum() >= 15
    # independent random signals: the cross term of the two is zero on average and scatters with the
    # number of FFT bins a band averages; from 200 Hz (100 km/h, 8 m of data) a band holds >= 13 bins x 7
    # lines, a relative scatter of 0.8 / sqrt(91), 0.36 dB: 1 dB is about three of it
    np.testing.assert_allclose(summed[wanted], levels[2][wanted], atol=1.0)
    # exact identities: equal levels add 10 lg 2 dB; a NaN band stays NaN
    doubled = 10 * np.log10(2)
    np.testing.assert_allclose(energy_sum([10.0, -5.0], [10.0, -5.0]), [10 + doubled, -5 + doubled])
    assert np.isnan(energy_sum([np.nan], [3.0])[0])
