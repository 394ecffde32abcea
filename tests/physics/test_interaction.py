"""Time-domain interaction (paper section 2, eqs. 1-14): validation against theory and the paper."""

import threading

import numpy as np
import pytest

from wheelrail.core.engine import prepare_run, simulate
from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import ContactParameters, ModelParameters
from wheelrail.core.roughness import RoughnessSet, load_roughness
from wheelrail.core.spectra.force import force_spectrum
from wheelrail.core.track import moving_green_functions
from wheelrail.core.wheel import wheel_receptance

P = ModelParameters()
SPEED = P.run.speed
L_S = P.track.support.sleeper_spacing
F_SLEEPER = SPEED / L_S


def _set(heights, dy=1e-3, kind="rail"):
    heights = np.atleast_2d(heights)
    n = heights.shape[0]
    y = (np.arange(n) - (n - 1) // 2) * dy
    return RoughnessSet(heights=heights, dx=1e-3, y=y, kind=kind, description="test")


def _smooth(length=3.0, lines=19):
    return _set(np.zeros((lines, int(round(length / 1e-3)) + 1)))


@pytest.mark.parametrize("model", ["hertz", "2d", "3d"])
def test_smooth_surfaces_mean_force_and_sleeper_passing(model):
    # Smooth wheel and rail: the only excitation is the varying track stiffness within a bay. The mean
    # force equals the preload within 0.5 % (the run starts in static equilibrium and the
    # soft suspension carries the mean), and the force is periodic with the sleeper-passing period
    # L_S / v: its strongest spectral line above 5 Hz lies within one frequency bin of v / L_S.
    length = 4 * L_S if model == "3d" else 8 * L_S
    result = simulate(_smooth(length + 0.1), model=model, length=length)
    force = result.force
    assert np.all(np.isfinite(force)) and result.loss_of_contact_steps == 0
    assert force.mean() == pytest.approx(P.contact.preload, rel=5e-3)
    spectrum = np.abs(np.fft.rfft((force - force.mean()) * np.hanning(len(force))))
    freqs = np.fft.rfftfreq(len(force), result.time_step)
    keep = freqs > 5
    peak = freqs[keep][np.argmax(spectrum[keep])]
    assert abs(peak - F_SLEEPER) <= freqs[1] + 1e-9
    # every sleeper bay looks the same: after the default run-in (0.3 s) the start-up transient is gone and
    # the force one bay apart repeats within 0.1 N (measured 2e-4 N for hertz; 2.1 N after the old 1 m run-in)
    # of its 2.6 kN variation.
    n_bay = int(round(L_S / P.run.element_size))
    tail = force[-2 * n_bay :]
    assert np.max(np.abs(tail[n_bay:] - tail[:n_bay])) < 0.1


def test_smooth_3d_patch_is_the_hertz_circle():
    # On smooth surfaces the 3D patch is the Hertz circle of radius a (5.48 mm at 65 kN). On the 1 mm
    # grid the patch covers about pi a^2 / (1 mm^2) = 94 elements; the count varies by a ring of
    # elements as the load varies with the sleeper position, so 8 % on the area (4 % on the radius),
    # and the peak pressure is within 5 % of p0 = 1032.6 MPa (the 1 mm grid's own error, see the
    # contact solver tests).
    result = simulate(_smooth(1.5), model="3d", length=1.3)
    a = ContactParameters().hertz_radius()
    assert np.mean(result.contact_area) == pytest.approx(np.pi * a**2, rel=0.08)
    step = result.n_steps // 2
    load = result.force[step]
    pressure = result.pressure[step]
    assert pressure.max() == pytest.approx(ContactParameters().hertz_peak_pressure(load), rel=0.05)
    # the patch is centred under the wheel and round: its extents along x and y agree within one element
    rows, cols = np.nonzero(pressure > 0)
    assert abs((cols.max() - cols.min()) - (rows.max() - rows.min())) <= 1
    assert abs(result.window_x[cols].mean()) < 1e-3 and abs(result.window_y[rows].mean()) < 1e-3


def _moving_receptance(freqs):
    """Mean over the bay of the Fourier transform of the moving Green's function (linear theory)."""
    green = moving_green_functions(SPEED)
    t = green.time
    transform = np.exp(-2j * np.pi * np.outer(freqs, t)) @ green.values.T * green.time_step
    return transform.mean(axis=1)


def test_small_sinusoidal_roughness_matches_linear_theory():
    # For small roughness r(x) = r0 sin(2 pi x / lambda) the steady force amplitude of `hertz` is
    # r0 / |alpha_W + alpha_R + 1/k_H| (linearised Hertz stiffness k_H = 3/2 P / delta_H, alpha_R the
    # bay-averaged moving receptance). The frequencies are chosen midway between sleeper-passing
    # harmonics and the fit window is a whole number of bays, so the parametric sleeper-passing lines
    # are orthogonal to the fitted sine. Measured on the converged track: -0.05, +0.02, +0.04, +0.41, +0.04,
    # +0.11 dB (192 Hz-3 kHz; the 320 Hz case was 1 dB off when the bay was band-limited). Tolerance 0.6 dB:
    # the remaining differences are the parametric side-bands (the receptance varies by ~6 % within a bay,
    # largest near pinned-pinned, 876 Hz) and the Hertz nonlinearity (r0 = 0.2 um is 0.3 % of the approach).
    r0 = 0.2e-6
    contact = P.contact
    k_h = 1.5 * contact.preload / contact.hertz_approach()
    n_bay = int(round(L_S / P.run.element_size))
    harmonics = (4, 7, 11, 20, 35, 70)  # 192, 320, 492, 876, 1517, 3013 Hz
    track_receptance = _moving_receptance([(n + 0.5) * F_SLEEPER for n in harmonics])
    for n, alpha_r in zip(harmonics, track_receptance, strict=True):
        f = (n + 0.5) * F_SLEEPER
        wavelength = SPEED / f
        x = np.arange(int(4.2 / 1e-3)) * 1e-3
        result = simulate(_set(r0 * np.sin(2 * np.pi * x / wavelength)), model="hertz", length=4.0)
        window = slice(result.n_steps - 4 * n_bay, result.n_steps)
        t = result.time[window]
        basis = np.stack([np.sin(2 * np.pi * f * t), np.cos(2 * np.pi * f * t), np.ones_like(t)], axis=1)
        coeff, *_ = np.linalg.lstsq(basis, result.force[window], rcond=None)
        amplitude = np.hypot(coeff[0], coeff[1])
        expected = r0 / abs(wheel_receptance(P.wheel, [f])[0] + alpha_r + 1 / k_h)
        assert 20 * np.log10(amplitude / expected) == pytest.approx(0.0, abs=0.6), f


def _levels(result):
    return force_spectrum(result)


def test_2d_and_hertz_winkler_agree():
    # Paper section 3.4: the 2D model and the Hertz spring with the Winkler pre-filter give very similar
    # contact filters. On the corrugated rail they agree within 1 dB per band from 63 Hz to 3.15 kHz
    # (measured: within 0.5 dB; above, a 2 m run leaves few spectral lines per band).
    rail = load_roughness("corrugated-rail")
    centres, two_d = _levels(simulate(rail, model="2d", length=2.0))
    _, winkler = _levels(simulate(rail, model="hertz-winkler", length=2.0))
    band = (centres > 60) & (centres < 3300)
    np.testing.assert_allclose(two_d[band], winkler[band], atol=1.0)


def test_3d_with_laterally_uniform_roughness_agrees_with_2d():
    # Roughness that does not vary across the contact: the 3D model sees the 2D situation, so up to
    # 1 kHz (wavelengths > 28 mm, much longer than the patch) the force levels agree within 1.5 dB
    # (measured: within 0.7 dB; the 3D half-space and the 2D bedding differ slightly in stiffness).
    rail = load_roughness("corrugated-rail")
    uniform = np.repeat(rail.line(0)[None, :], rail.n_lines, axis=0)
    rough = RoughnessSet(heights=uniform, dx=rail.dx, y=rail.y, kind="rail", description="uniform")
    centres, three_d = _levels(simulate(rough, model="3d", length=2.0))
    _, two_d = _levels(simulate(rough, model="2d", length=2.0))
    band = (centres > 60) & (centres < 1100)
    np.testing.assert_allclose(three_d[band], two_d[band], atol=1.5)


@pytest.mark.slow
def test_3d_gives_lower_high_frequency_force_on_uncorrelated_roughness():
    # The paper's main finding: with low lateral correlation (sinter-braked wheel) the 3D model averages
    # over the roughness across the patch and gives a lower force at high frequencies than the 2D model
    # on the centre line. Summed over the bands 1-5 kHz the 3D level is at least 2 dB lower (measured
    # about 5 dB; the paper reports mean differences up to 7 dB).
    wheel = load_roughness("sinter-wheel-1")
    centres, three_d = _levels(simulate(wheel, model="3d", length=2.0))
    _, two_d = _levels(simulate(wheel, model="2d", length=2.0))
    band = (centres > 900) & (centres < 5500)
    total = lambda levels: 10 * np.log10(np.sum(10 ** (levels[band] / 10)))  # noqa: E731
    assert total(three_d) < total(two_d) - 2.0


@pytest.mark.parametrize("model", ["hertz", "hertz-winkler", "hertz-average", "2d", "3d"])
def test_loss_of_contact_is_physics_not_an_error(model):
    # A light wheel (5 kN, static approach 13 um) on a 30 um, 50 mm sine (555 Hz at 100 km/h) bounces:
    # about half the steps have no contact (measured 530-560 of 1200 in every model). Force >= 0, zero
    # on many steps, no NaN, and contact is regained after every loss (P2-like impacts up to ~4 P).
    params = ModelParameters(contact=ContactParameters(preload=5e3))
    x = np.arange(int(1.3 / 1e-3)) * 1e-3
    rough = _set(np.repeat((30e-6 * np.sin(2 * np.pi * x / 0.05))[None, :], 19, axis=0))
    result = simulate(rough, model=model, length=1.2, params=params)
    force = result.force
    assert np.all(np.isfinite(force)) and np.all(force >= 0)
    assert 300 < result.loss_of_contact_steps < 900
    lost = np.nonzero(force == 0)[0]
    assert np.any(force[lost[-1] :] > 0)  # contact regained after the last loss
    assert np.all(np.isfinite(result.xi_wheel)) and np.all(np.isfinite(result.xi_rail))
    assert force.max() > 2 * params.contact.preload


def test_streaming_and_cancellation():
    # One-line models run in compiled chunks of CHUNK steps: a cancel takes effect at the end of the chunk.
    from wheelrail.core.engine.laws.base import CHUNK

    run = prepare_run("cast-iron-wheel", model="hertz", length=10.0)
    seen = []
    for state in run.steps():
        seen.append(state.force)
        if state.step == 99:
            run.cancel()
    partial = run.result()
    assert run.cancelled and 100 <= partial.n_steps <= CHUNK < run.n_steps
    np.testing.assert_array_equal(partial.force[:100], seen[:100])
    # a cancel event given to simulate stops it too (here before the first step)
    event = threading.Event()
    event.set()
    assert simulate("corrugated-rail", model="hertz", length=0.5, cancel=event).n_steps == 0


def test_streamed_states_equal_the_result():
    run = prepare_run("cast-iron-wheel", model="3d", length=0.05)
    states = list(run.steps())
    result = run.result()
    assert [s.step for s in states] == list(range(result.n_steps))
    np.testing.assert_array_equal([s.force for s in states], result.force)
    np.testing.assert_array_equal(states[20].pressure, result.pressure[20])
    assert result.pressure.shape[1:] == (25, 25)


def test_streamed_states_read_every_field_of_its_step():
    """steps() reads a chunk's arrays at once: every field of every state is its step's number in the result
    (exactly), and without the maps kept each state's map is its own step's, not the reused chunk buffer's."""
    from dataclasses import astuple

    kept = prepare_run("corrugated-rail", model="3d", length=0.6)
    states = list(kept.steps())
    result = kept.result()
    assert len(states) == result.n_steps == 600
    names = ("time", "x", "force", "xi_wheel", "xi_rail", "roughness", "contact_length", "contact_area")
    rows = np.array([astuple(state)[:9] for state in states])
    np.testing.assert_array_equal(rows[:, 0], np.arange(600))
    for column, name in enumerate(names, start=1):
        np.testing.assert_array_equal(rows[:, column], getattr(result, name), err_msg=name)
    streamed = list(prepare_run("corrugated-rail", model="3d", length=0.6, keep_pressure=False).steps())
    np.testing.assert_array_equal(np.array([state.pressure for state in streamed]), result.pressure)
    assert result.pressure.max() > 5e8  # loaded maps (p0 ~ 1 GPa), not the empty window


def test_chunk_states_are_the_steps_at_each_chunks_end():
    """chunk_states() (what the explorer draws live) yields the state of each chunk's last step, field by field
    and map for map the one steps() yields there, and the run's result is the same after either."""
    from dataclasses import astuple

    from wheelrail.core.engine.laws.halfspace import CHUNK_3D

    states = list(prepare_run("corrugated-rail", model="3d", length=0.6).steps())
    run = prepare_run("corrugated-rail", model="3d", length=0.6)
    ends = list(run.chunk_states())
    steps = [state.step for state in ends]
    assert steps == [min(k + CHUNK_3D, 600) - 1 for k in range(0, 600, CHUNK_3D)]
    for state in ends:
        assert astuple(state)[:9] == astuple(states[state.step])[:9]
        np.testing.assert_array_equal(state.pressure, states[state.step].pressure)
    np.testing.assert_array_equal(run.result().force, [state.force for state in states])


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"model": "4d"}, "unknown contact model"),
        ({"line": 40}, "line 40: not in the roughness set; accepted -9 to 9"),
        ({"length": 100.0}, "length 100 m: with the 20 mm window margins at each end the run needs more"),
        ({"length": -1.0}, "run length must be positive"),
        ({"run_in_length": float("nan")}, "run_in_length"),
    ],
)
def test_bad_input(kwargs, fragment):
    with pytest.raises(WheelrailError, match=fragment):
        prepare_run("corrugated-rail", **kwargs)
