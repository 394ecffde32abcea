"""The explorer's run controller without a server: stop, replace, compare, failures, keyed results.

Runs are stand-ins with the interface of ``InteractionRun`` whose steps wait on events, so that "still
running" never depends on how fast the machine is; no test sleeps.
"""

import dataclasses
import threading
from types import SimpleNamespace

import numpy as np
import pytest

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.models import REFERENCE_MODEL
from wheelrail.core.parameters import KMH
from wheelrail.core.spectra.force import force_spectrum
from wheelrail.core.spectra.levels import contact_filter
from wheelrail.explorer.config import COMPARE_ORDER, RunConfig
from wheelrail.explorer.controller import RunController

WAIT = 60.0  # s: only a bound on a hung thread, never reached when the code works


class FakeRun:
    """n steps of a force record; step ``hold_at`` waits until ``release`` is set (or the run is cancelled)."""

    def __init__(self, model, n, *, hold_at=None, amplitude=1.0):
        self.model, self.n_steps, self.hold_at = model, n, hold_at
        self.reached = threading.Event()
        self.release = threading.Event()
        self._cancel = threading.Event()
        self.done = 0
        rng = np.random.default_rng(len(model))
        self.force = 65e3 + amplitude * rng.standard_normal(n)
        self.window_x = self.window_y = None

    def steps(self):
        for s in range(self.n_steps):
            if self._cancel.is_set():
                return
            if s == self.hold_at:
                self.reached.set()
                while not (self.release.is_set() or self._cancel.is_set()):
                    self.release.wait(WAIT)
                if self._cancel.is_set():
                    return
            self.done = s + 1
            yield SimpleNamespace(step=s, position=s * 1e-3, force=self.force[s], pressure=None)

    def chunk_states(self):  # a chunk of one step each
        return self.steps()

    def cancel(self):
        self._cancel.set()
        self.release.set()

    @property
    def cancelled(self):
        return self._cancel.is_set()

    def result(self):
        return SimpleNamespace(
            model=self.model, n_steps=self.done, force=self.force[: self.done], time_step=1e-3 / (100 * KMH)
        )


class Recorder:
    """A listener that records what the controller said; ``ended`` is set when a run reports its end."""

    def __init__(self):
        self.statuses, self.errors, self.done, self.outcomes, self.frames = [], [], [], [], 0
        self.ended = threading.Event()

    def status(self, text):
        self.statuses.append(text)

    def progress(self, fraction):
        pass

    def frame(self, state, view):
        self.frames += 1

    def live(self, result, view):
        pass

    def model_done(self, entry, view):
        self.done.append(entry)

    def error(self, message):
        self.errors.append(message)

    def finished(self, config, outcome):
        self.outcomes.append((config, outcome))
        self.ended.set()


def _config(model="3d", speed_kmh=100.0, line=0):
    inputs = () if speed_kmh == 100.0 else (("speed", speed_kmh * KMH),)
    return RunConfig(set_label="corrugated-rail", line=line, model=model, length=1.0, inputs=inputs)


def _controller(runs):
    """A controller whose prepare hands out the given FakeRuns by model (a list per model, in order)."""
    listener = Recorder()
    handed = []

    def prepare(roughness, *, model, line, params, length):
        run = runs[model].pop(0)
        handed.append(run)
        return run

    return RunController(listener, prepare=prepare, frame_interval=0.0), listener, handed


def test_a_run_reports_frames_spectrum_and_done():
    run = FakeRun("2d", 2000)
    controller, listener, _ = _controller({"2d": [run]})
    config = _config("2d")
    controller.start(config, roughness=None)
    assert listener.ended.wait(WAIT)
    assert listener.outcomes == [(config, "done")] and not listener.errors
    assert "Preparing the track for 100 km/h" in listener.statuses[0]  # the first run says why it waits
    assert listener.frames == 2000 + 1  # every step (interval 0) and the last one again
    entry = controller.store.entries(config.case())["2d"]
    assert np.array_equal(entry.spectrum[1], force_spectrum(entry.result)[1], equal_nan=True)


def test_stop_keeps_the_steps_done_and_gives_no_spectrum():
    run = FakeRun("3d", 5000, hold_at=300)
    controller, listener, _ = _controller({"3d": [run]})
    controller.start(_config("3d"), roughness=None)
    assert run.reached.wait(WAIT)
    controller.stop()
    assert listener.ended.wait(WAIT)
    assert listener.outcomes[-1][1] == "stopped"
    entry = listener.done[-1]
    assert entry.result.n_steps == 300 and entry.spectrum is None and "stopped after 300" in entry.problem
    assert listener.statuses[-1].startswith("Stopped 3d after 300 of 5000 steps")


def test_a_new_run_replaces_an_old_one_which_reports_nothing_more():
    old = FakeRun("3d", 5000, hold_at=100)
    new = FakeRun("hertz", 1000)
    controller, listener, _ = _controller({"3d": [old], "hertz": [new]})
    controller.start(_config("3d"), roughness=None)
    assert old.reached.wait(WAIT)
    controller.start(_config("hertz"), roughness=None)
    assert listener.ended.wait(WAIT)
    assert controller.wait(WAIT)
    assert old.cancelled and old.done == 100
    assert [outcome for _, outcome in listener.outcomes] == ["done"]  # the replaced run said nothing
    assert [e.config.model for e in listener.done] == ["hertz"]


def test_compare_runs_every_model_reference_first_and_gives_contact_filters():
    runs = {m: [FakeRun(m, 3000, amplitude=1.0 + i)] for i, m in enumerate(COMPARE_ORDER)}
    controller, listener, handed = _controller(runs)
    config = _config("compare")
    controller.start(config, roughness=None)
    assert listener.ended.wait(WAIT)
    assert listener.outcomes == [(config, "done")]
    assert [run.model for run in handed] == list(COMPARE_ORDER) and COMPARE_ORDER[0] == REFERENCE_MODEL
    filters = controller.store.contact_filters(config.case())
    assert set(filters) == set(COMPARE_ORDER) - {REFERENCE_MODEL}
    spectra = controller.store.spectra(config.case())
    assert np.allclose(filters["2d"][1], contact_filter(spectra["2d"][1], spectra[REFERENCE_MODEL][1]), equal_nan=True)


def test_a_run_too_short_for_a_spectrum_is_an_error_not_done():
    controller, listener, _ = _controller({"hertz": [FakeRun("hertz", 20)]})
    controller.start(_config("hertz"), roughness=None)
    assert listener.ended.wait(WAIT)
    assert listener.outcomes[-1][1] == "failed"
    assert listener.errors and listener.errors[0].startswith("hertz: no force spectrum")


def test_core_errors_reach_the_page_in_its_words():
    # core's error as data (the input's key, value and range, SI); the page names the input by its field
    listener = Recorder()

    def prepare(roughness, **kwargs):
        raise WheelrailError(
            "the run needs more than the 2.999 m of rail roughness data",
            Blame("preload", 9e3, unit="N", maximum=2.959e3),
        )

    controller = RunController(listener, prepare=prepare)
    controller.start(_config("hertz"), roughness=None)
    assert listener.ended.wait(WAIT)
    assert listener.errors == [
        "Preload 9 kN: the run needs more than the 2.999 m of rail roughness data; accepted at most 2.959 kN"
    ]


def test_results_are_kept_per_configuration():
    runs = {"hertz": [FakeRun("hertz", 3000), FakeRun("hertz", 3000, amplitude=3.0)]}
    controller, listener, _ = _controller(runs)
    first, second = _config("hertz", speed_kmh=100.0), _config("hertz", speed_kmh=80.0)
    for config in (first, second):
        listener.ended.clear()
        controller.start(config, roughness=None)
        assert listener.ended.wait(WAIT)
    assert controller.store.entries(first.case())["hertz"].config == first
    assert controller.store.entries(second.case())["hertz"].config == second
    assert controller.store.contact_filters(second.case()) == {}  # no other model of that case yet
    with pytest.raises(WheelrailError, match="no force spectrum yet"):
        controller.store.csv_text(_config("hertz", line=3))


def test_a_wheel_set_and_the_geometry_reach_prepare_and_key_the_results():
    """The wheel set goes to prepare_run as wheel_roughness=, the geometry in params.contact; a run of
    another wheel set or geometry is another case (never shown as the current one)."""
    listener = Recorder()
    calls = []

    def prepare(roughness, *, model, line, params, length, wheel_roughness=None):
        calls.append((roughness, wheel_roughness, params.contact))
        return FakeRun(model, 3000)

    controller = RunController(listener, prepare=prepare, frame_interval=0.0)
    plain = _config("hertz")
    combined = RunConfig(
        set_label="corrugated-rail",
        line=0,
        model="hertz",
        length=1.0,
        wheel_set_label="sinter-wheel-1",
        inputs=(("wheel_radius", 0.46), ("rail_crown_radius", 0.3)),
    )
    with pytest.raises(WheelrailError, match="wheel roughness must be given exactly"):
        controller.start(combined, "rail")  # the configuration names a wheel set: its roughness is needed
    for config, wheel in ((plain, None), (combined, "wheel")):
        listener.ended.clear()
        controller.start(config, "rail", wheel)
        assert listener.ended.wait(WAIT)
    # bundled sets go by name (the result's header records it); the geometry in params.contact
    assert calls[0][:2] == ("corrugated-rail", None) and calls[0][2].wheel_radius is None
    rail, wheel, contact = calls[1]
    assert (rail, wheel) == ("corrugated-rail", "sinter-wheel-1")
    assert (contact.wheel_radius, contact.rail_crown_radius, contact.preload) == (0.46, 0.3, 65e3)
    assert plain.case() != combined.case()
    assert set(controller.store.entries(plain.case())) == {"hertz"}
    assert controller.store.entries(combined.case())["hertz"].config == combined
    assert combined.case_label() == (
        "corrugated-rail + sinter-wheel-1, line 0, 100 km/h, 65 kN, 1 m, wheel radius 460 mm, rail crown radius 300 mm"
    )
    assert combined.file_stem() == (
        "wheelrail-hertz-corrugated-rail-sinter-wheel-1-line0-100kmh-65kN-1m-R460mm-crown300mm"
    )


def test_the_first_preparation_at_a_speed_says_its_steps_and_that_it_goes_on():
    """The track's Green's functions first (once per track), then the run's set-up; while a step lasts, the
    status line repeats it with the seconds elapsed. The stand-in Green's functions wait until a repeat
    has been said (an event, not a time)."""
    ticked = threading.Event()

    class Listener(Recorder):
        def status(self, text):
            super().status(text)
            if text.endswith(" s") and "(1 of 2)" in text:
                ticked.set()

    listener = Listener()
    precomputed = []

    def precompute(params):
        precomputed.append(params.run.speed)
        assert ticked.wait(WAIT)

    runs = {"hertz": [FakeRun("hertz", 3000), FakeRun("hertz", 3000)]}
    controller = RunController(
        listener,
        prepare=lambda roughness, *, model, **kwargs: runs[model].pop(0),
        precompute=precompute,
        frame_interval=0.0,
        tick=0.01,
    )
    controller.start(_config("hertz"), roughness=None)
    assert listener.ended.wait(WAIT)
    assert precomputed == [pytest.approx(100 * KMH)]
    steps = [text for text in listener.statuses if text.startswith("Preparing the track for 100 km/h")]
    assert steps[0].startswith("Preparing the track for 100 km/h (1 of 2): its Green's functions")
    assert any(text.startswith("Preparing the track for 100 km/h (2 of 2)") for text in steps)
    # a second run at the same speed: no track step
    listener.ended.clear()
    listener.statuses.clear()
    controller.start(_config("hertz", line=1), roughness=None)
    assert listener.ended.wait(WAIT)
    assert precomputed == [pytest.approx(100 * KMH)]
    assert listener.statuses[0] == "Preparing hertz on corrugated-rail, line 1, 100 km/h, 65 kN, 1 m ..."


def test_a_new_tracks_precompute_says_its_phases_and_moves_the_bar():
    """A track not prepared yet (another pad, at a speed already prepared) is a first preparation again; the
    precompute's phases (core's track_progress, here a stand-in that reports as core does) reach the status
    line and the progress bar."""
    from wheelrail.core.track.progress import current_progress

    class Listener(Recorder):
        fractions = []

        def progress(self, fraction):
            self.fractions.append(fraction)

    listener = Listener()
    precomputed = []

    def precompute(params):
        precomputed.append(params.track.support.pad_stiffness)
        report = current_progress()
        report("assembling the FE track", 0, 1)
        for done in range(1, 5):
            report("integrating the impulse responses (about 20 s)", done, 4)

    runs = {"hertz": [FakeRun("hertz", 3000), FakeRun("hertz", 3000)]}
    controller = RunController(
        listener, prepare=lambda roughness, *, model, **kwargs: runs[model].pop(0), precompute=precompute, tick=10.0
    )
    soft = dataclasses.replace(_config("hertz"), inputs=(("pad_stiffness", 60e6),))
    for config in (_config("hertz"), soft):  # the same speed, two tracks: two first preparations
        listener.ended.clear()
        controller.start(config, roughness=None)
        assert listener.ended.wait(WAIT)
    assert precomputed == [120e6, 60e6]
    assert "Preparing the track for 100 km/h (1 of 2): integrating the impulse responses (about 20 s) (4 of 4) ..." in (
        listener.statuses
    )
    assert listener.fractions[:4] == [0.25, 0.5, 0.75, 1.0]


def test_a_first_run_during_the_warm_up_shows_the_warm_ups_progress():
    """A Run pressed while the warm-up computes the track shows the warm-up's phase, bar and estimate at once (its
    latest report) and then each report as it comes, until the warm-up ends; then its own preparation."""
    from wheelrail.core.track.progress import current_progress
    from wheelrail.explorer.controller import SOLVER_PHASE, WAITING

    seen, live, release = threading.Event(), threading.Event(), threading.Event()

    class Listener(Recorder):
        fractions = []

        def status(self, text):
            super().status(text)
            if WAITING in text and "(2 of 4)" in text:
                seen.set()  # the warm-up's latest report, shown as soon as the run waits
            if WAITING in text and "(3 of 4)" in text:
                live.set()

        def progress(self, fraction):
            self.fractions.append(fraction)

    def precompute(params):
        if release.is_set():
            return  # the run's own: the track is ready by then
        report = current_progress()
        report("assembling the FE track", 0, 1)
        for done in (1, 2):
            report("integrating the impulse responses (about 20 s)", done, 4)
        assert seen.wait(WAIT)  # a Run pressed meanwhile shows it
        report("integrating the impulse responses (about 20 s)", 3, 4)
        assert release.wait(WAIT)

    runs = {"hertz": [FakeRun("hertz", 10), FakeRun("hertz", 3000), FakeRun("hertz", 3000)]}
    listener = Listener()
    controller = RunController(
        listener, prepare=lambda roughness, *, model, **kwargs: runs[model].pop(0), precompute=precompute, tick=10.0
    )
    warm_up = controller.warm_up(_config("hertz"), roughness=None)
    controller.start(_config("hertz", line=1), roughness=None)
    assert live.wait(WAIT)  # the warm-up's next report reached the run while it waited
    assert listener.fractions[:2] == [0.5, 0.75] and not listener.outcomes
    waited = [text for text in listener.statuses if WAITING in text]
    assert waited[-1].startswith(
        f"Preparing the track for 100 km/h (1 of 2), {WAITING}: integrating the impulse responses (about 20 s) "
        "(3 of 4), about "
    ), waited
    release.set()
    assert listener.ended.wait(WAIT) and listener.outcomes[-1][1] == "done"
    warm_up.join(WAIT)
    # the warm-up's later phases too, while the run still waits: the solver loaded by the warm-up's first step
    assert any(
        text.startswith(f"Preparing the track for 100 km/h (1 of 2), {WAITING}: {SOLVER_PHASE}")
        for text in listener.statuses
    )


def test_a_warm_up_prepares_in_the_background_and_a_first_run_waits_for_it():
    """serve() warms up the default configuration; a Run pressed meanwhile waits for it instead of computing the
    same Green's functions beside it, and says so; afterwards runs at that speed skip the track step."""
    entered, release = threading.Event(), threading.Event()
    order = []

    def precompute(params):
        order.append("precompute")
        if len(order) == 1:  # the warm-up's: held until released
            entered.set()
            assert release.wait(WAIT)

    runs = {"hertz": [FakeRun("hertz", 10), FakeRun("hertz", 3000), FakeRun("hertz", 3000)]}
    warm_up_run = runs["hertz"][0]

    def prepare(roughness, *, model, **kwargs):
        order.append("prepare")
        return runs[model].pop(0)

    listener = Recorder()
    controller = RunController(listener, prepare=prepare, precompute=precompute, frame_interval=0.0, tick=0.01)
    warmed = []
    warm_up = controller.warm_up(_config("hertz"), roughness=None, done=warmed.append)
    assert entered.wait(WAIT)
    controller.start(_config("hertz", line=1), roughness=None)  # the first Run at 100 km/h, during the warm-up
    release.set()
    assert listener.ended.wait(WAIT)
    warm_up.join(WAIT)
    assert warmed and listener.outcomes[-1][1] == "done"
    assert warm_up_run.done == 1 and warm_up_run.cancelled  # its first step taken (the compiled loop loaded)
    # the warm-up's preparation first, whole; then the run's (its Green's functions now read back at once)
    assert order == ["precompute", "prepare", "precompute", "prepare"]
    assert listener.statuses[0].startswith("Preparing the track for 100 km/h (1 of 2)")
    listener.ended.clear()
    listener.statuses.clear()
    controller.start(_config("hertz", line=2), roughness=None)
    assert listener.ended.wait(WAIT)
    assert order[4:] == ["prepare"] and listener.statuses[0].startswith("Preparing hertz on")
