"""The run controller: one background run at a time, stop, replace, compare (no viser here).

:class:`RunController` runs a :class:`~wheelrail.explorer.config.RunConfig` (one model, or every model of a compare,
the reference first) in a daemon thread and reports to a :class:`RunListener` (the page, or a test): status lines,
progress, frames (thinned to ``frame_interval``), each model's result with its force spectrum, errors and the end of
the run. Each finished model also gets its rolling noise (``noise``: default
:func:`wheelrail.core.noise.run_noise.run_noise`, with the CNOSSOS-EU source beside it). A generation counter keeps
a replaced run from reporting anything once a new one has started; :meth:`stop` cancels the current run (the steps
done so far are kept). Results go to a :class:`~wheelrail.explorer.results.ResultStore` keyed by configuration. Runs
come from ``prepare`` (default :func:`wheelrail.core.engine.prepare.prepare_run`), spectra from
:func:`wheelrail.core.spectra.force.force_spectrum`. Every run and error is logged to the ``wheelrail.explorer`` logger
(the terminal, under ``wheelrail explore``).
"""

from __future__ import annotations

import contextlib
import logging
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import KMH
from wheelrail.core.spectra.force import force_spectrum
from wheelrail.core.track.progress import track_progress
from wheelrail.explorer.config import RunConfig, models_of, page_message
from wheelrail.explorer.results import Entry, ResultStore
from wheelrail.explorer.workers import Workers

__all__ = ["FRAME_INTERVAL", "Preparation", "RunController", "RunListener", "RunView", "TICK_INTERVAL"]

LOG = logging.getLogger("wheelrail.explorer")
FRAME_INTERVAL = 0.05  # s between live frames handed to the page (<= 20 per second)
PLOT_INTERVAL = 0.25  # s between live plot and progress updates
TICK_INTERVAL = 0.5  # s between the status lines of a long preparation (the seconds it has taken)
SOLVER_PHASE = "loading the contact solver (compiled once after installation)"
WAITING = "waiting for the preparation begun at start-up"  # a first Run during the warm-up: what it shows meanwhile


@dataclass
class Preparation:
    """What the runs of every page of one explorer share: the (track, speed) whose Green's functions this process
    has prepared (a later run on them is no first preparation) and one first preparation at a time (a warm-up or a
    run's). The prepared tracks themselves are core's cache, the compiled solver numba's."""

    tracks: set = field(default_factory=set)
    lock: threading.Lock = field(default_factory=threading.Lock)
    _watchers: list = field(default_factory=list)  # the progress callables of the runs waiting for the warm-up
    _latest: list = field(default_factory=list)  # the warm-up's latest (phase, done, total), while it goes on
    _guard: threading.Lock = field(default_factory=threading.Lock)
    began: dict = field(default_factory=dict)  # phase -> when the warm-up began it (time.perf_counter())

    def report(self, phase: str, done: int, total: int) -> None:
        """A warm-up's progress (``progress(phase, done, total)``, as a track precompute reports it), passed on to
        every run waiting for it and kept for a run that starts waiting later."""
        with self._guard:
            self.began.setdefault(phase, time.perf_counter())
            self._latest[:] = [(phase, done, total)]
            watchers = list(self._watchers)
        for progress in watchers:
            progress(phase, done, total)

    def warm_up_ended(self) -> None:
        """The warm-up is over: no progress of it is kept."""
        with self._guard:
            self._latest.clear()
            self.began.clear()

    @contextlib.contextmanager
    def watching(self, progress: Callable[[str, int, int], None]):
        """Pass the warm-up's progress to ``progress`` in this block, its latest at once (if a warm-up goes on)."""
        with self._guard:
            self._watchers.append(progress)
            latest = list(self._latest)
        for phase, done, total in latest:
            progress(phase, done, total)
        try:
            yield
        finally:
            with self._guard:
                self._watchers.remove(progress)


@dataclass(frozen=True)
class RunView:
    """What a listener needs to draw a state of a run: its configuration, roughness (and wheel roughness, when
    one is added) and window."""

    config: RunConfig
    roughness: object
    window_x: object = None
    window_y: object = None
    wheel_roughness: object = None


class RunListener(Protocol):
    """What the controller tells the page. Called from the run's thread."""

    def status(self, text: str) -> None: ...
    def progress(self, fraction: float) -> None: ...
    def frame(self, state, view: RunView) -> None: ...
    def live(self, result, view: RunView) -> None: ...
    def model_done(self, entry: Entry, view: RunView) -> None: ...
    def error(self, message: str) -> None: ...
    def finished(self, config: RunConfig, outcome: str) -> None: ...


class RunController:
    """Starts, stops and replaces runs; one at a time."""

    def __init__(
        self,
        listener: RunListener,
        store: ResultStore | None = None,
        *,
        prepare: Callable | None = None,
        precompute: Callable | None = None,
        noise: Callable | None = None,
        frame_interval: float = FRAME_INTERVAL,
        tick: float = TICK_INTERVAL,
        workers: Workers | None = None,
        preparation: Preparation | None = None,
    ) -> None:
        self._noise_transfer = None
        self._loads_solver = prepare is None  # core's runs: a first preparation loads the solver as a step of its own
        if prepare is None:
            from wheelrail.core.engine import prepare_run as prepare

            precompute = _track_green_functions if precompute is None else precompute
            noise = _rolling_noise if noise is None else noise
            self._noise_transfer = _noise_transfer_functions
        self._noise = noise  # result -> its RunNoise (None: runs get no rolling noise)
        self.listener = listener
        self.store = ResultStore() if store is None else store
        self._prepare = prepare
        self._precompute = precompute
        self._tick = float(tick)
        self._frame_interval = float(frame_interval)
        self._lock = threading.Lock()
        self._generation = 0
        self._stopped_generation = -1
        self._run = None
        self._worker: threading.Thread | None = None
        preparation = Preparation() if preparation is None else preparation  # shared by the explorer's pages
        self._prepared_tracks: set[tuple] = preparation.tracks  # (track, speed) whose Green's functions are prepared
        self._first_preparation = preparation.lock  # one first preparation at a time (a warm-up or a run's)
        self._preparation = preparation  # and the warm-up's progress, shown by a run that waits for it
        self.workers = Workers() if workers is None else workers  # its threads, joined by close()

    @property
    def running(self) -> bool:
        worker = self._worker
        return worker is not None and worker.is_alive()

    def start(self, config: RunConfig, roughness, wheel_roughness=None) -> int:
        """Run ``config`` on ``roughness`` (plus ``wheel_roughness``, the wheel set ``config`` names, if any) in
        the background, replacing any current run; its generation."""
        if (wheel_roughness is None) != (config.wheel_set_label is None):
            raise WheelrailError("the wheel roughness must be given exactly when the configuration names a wheel set")
        self.cancel_current()
        with self._lock:
            self._generation += 1
            generation = self._generation
            first = _track_case(config) not in self._prepared_tracks
            self._worker = self.workers.start(
                self._work,
                generation,
                config,
                (roughness, wheel_roughness),
                first,
                name=f"wheelrail-explorer-run-{generation}",
            )
        LOG.info("run %d: %s", generation, config.label())
        return generation

    def warm_up(
        self, config: RunConfig, roughness, done: Callable[[float], None] | None = None
    ) -> threading.Thread | None:
        """Prepare ``config`` in the background and take its first step only: the track's Green's functions at its
        speed (computed once, then kept on disk) and the compiled solver, so that a first Run finds them ready.
        A first Run at that speed started meanwhile waits for it (saying so); ``done(seconds)`` at the end."""

        def work() -> None:
            started = time.perf_counter()
            report = self._preparation.report  # to the runs that wait for it
            with self._first_preparation, track_progress(report):
                try:
                    if self._precompute is not None:
                        self._precompute(config.params(), **config.run_options())
                    report(SOLVER_PHASE, 0, 1)
                    run = self._prepare(
                        _source(roughness, config.set_label),
                        model=config.model,
                        line=config.line,
                        params=config.params(),
                        length=config.length,
                        **config.run_options(),
                    )
                    # its first step (after the run-in): the compiled chunk loop, which a run loads (or a fresh
                    # install compiles) on its first step, not when it is prepared
                    next(iter(run.steps()), None)
                    run.cancel()
                    self._prepared_tracks.add(_track_case(config))
                    if self._noise_transfer is not None:  # the Noise tab's track transfer functions
                        report("the Noise tab's track transfer functions", 0, 1)
                        self._noise_transfer(config.params())
                except Exception:  # a Run prepares again and says what is wrong
                    LOG.exception("warm-up of %s failed", config.label())
                    return
                finally:
                    self._preparation.warm_up_ended()
            LOG.info("warm-up done after %.1f s: %s", time.perf_counter() - started, config.label())
            if done is not None:
                done(time.perf_counter() - started)

        return self.workers.start(work, name="wheelrail-explorer-warm-up")

    def stop(self) -> None:
        """Cancel the current run, also one still being prepared (its steps so far are kept)."""
        with self._lock:
            self._stopped_generation = self._generation
            run = self._run
        if run is not None:
            run.cancel()

    def cancel_current(self) -> None:
        """Supersede the current run: it stops at its next step (or once prepared) and reports nothing more.

        Not joined: a run still being prepared (the one-off track precompute) would hold up the page.
        """
        with self._lock:
            self._generation += 1
            run = self._run
        if run is not None:
            run.cancel()

    def close(self) -> None:
        """Supersede the current run and join every thread of the controller (a run still being prepared ends
        once prepared): after it, nothing more is reported."""
        self.cancel_current()
        self.workers.close()

    def wait(self, timeout: float | None = None) -> bool:
        """Wait for the current run to end; True if it did within ``timeout`` s."""
        worker = self._worker
        if worker is not None:
            worker.join(timeout)
            return not worker.is_alive()
        return True

    def _current(self, generation: int) -> bool:
        return generation == self._generation

    def _work(self, generation: int, config: RunConfig, roughness: tuple, first: bool) -> None:
        started = time.perf_counter()
        models = models_of(config.model)
        outcome = "failed"
        try:
            for number, model in enumerate(models):
                outcome = self._one_model(
                    generation, config.for_model(model), roughness, (number, len(models)), first and number == 0
                )
                if outcome != "done":
                    break
                self._prepared_tracks.add(_track_case(config))
        except WheelrailError as error:
            outcome = self._failed(generation, page_message(error))
        except Exception as error:  # keep serving after anything: report it in the page
            LOG.exception("run %d failed", generation)
            outcome = self._failed(generation, f"unexpected error: {type(error).__name__}: {error}")
        finally:
            with self._lock:
                if self._current(generation):
                    self._run = None
        if self._current(generation):
            LOG.info("run %d %s after %.1f s: %s", generation, outcome, time.perf_counter() - started, config.label())
            self.listener.finished(config, outcome)

    def _failed(self, generation: int, message: str) -> str:
        LOG.error("run %d: %s", generation, message)
        if self._current(generation):
            self.listener.error(message)
        return "failed"

    def _ticking(self, generation: int, text):
        """Say ``text`` (or ``text()``: what is being done now) now and then again with the seconds elapsed, every
        ``tick`` s, until the block ends (or the run is replaced): a long preparation shows that it goes on."""
        done = threading.Event()
        started = time.perf_counter()
        words = text if callable(text) else (lambda: text)
        self.listener.status(f"{words()} ...")

        def tick() -> None:
            while not done.wait(self._tick) and self._current(generation):
                self.listener.status(f"{words()} ... {time.perf_counter() - started:.0f} s")

        thread = self.workers.start(tick, name=f"wheelrail-explorer-tick-{generation}")
        return _Stop(done, thread)

    def _prepared(self, generation: int, config: RunConfig, roughness: tuple, first: bool):
        """The run of one model, prepared in honest steps: the first run on a track and speed computes the track's
        Green's functions (once per track, then cached on disk; a new track's precompute says its phases, with
        the progress bar and an estimate of the time left) and loads the solver (compiled on a fresh install);
        later ones only set up."""
        roughness, wheel = roughness
        combined = {} if wheel is None else {"wheel_roughness": _source(wheel, config.wheel_set_label)}
        combined.update(config.run_options())  # prepare_run's other keywords: the track's numerics, if given
        source = _source(roughness, config.set_label)
        speed = f"Preparing the track for {config.speed / KMH:g} km/h"
        steps = 3 if self._loads_solver else 2
        if first:
            now = {"text": f"{speed} (1 of {steps}): its Green's functions, computed once per track and kept on disk"}
            progress = self._precompute_progress(generation, f"{speed} (1 of {steps})", now)
            waiting = self._precompute_progress(
                generation, f"{speed} (1 of {steps}), {WAITING}", now, began=self._preparation.began
            )
            with self._ticking(generation, lambda: now["text"]):
                with self._preparation.watching(waiting):  # a warm-up under way finishes first, its progress shown
                    self._first_preparation.acquire()
                try:
                    if self._precompute is not None and self._current(generation):
                        with track_progress(progress):
                            self._precompute(config.params(), **config.run_options())
                finally:
                    self._first_preparation.release()
            if not self._current(generation):
                return None
            if self._loads_solver:
                text = f"{speed} (2 of 3): loading the contact solver (compiled once after installation)"
                with self._ticking(generation, text):
                    self._load_solver(config, source, combined)
                if not self._current(generation):
                    return None
        text = (
            f"{speed} ({steps} of {steps}): roughness and run set-up"
            + ("" if self._loads_solver else ", and the contact solver, which the first run compiles")
            if first
            else f"Preparing {config.label()}"
        )
        with self._ticking(generation, text):
            return self._prepare(
                source,
                model=config.model,
                line=config.line,
                params=config.params(),
                length=config.length,
                **combined,
            )

    def _precompute_progress(self, generation: int, prefix: str, now: dict, began: dict | None = None):
        """The track precompute's ``progress(phase, done, total)`` for the page: the phase named, the bar, and
        once a part is done the time left, from the pace so far (``now["text"]``: the line the ticker repeats;
        ``began``: when each phase began, if known, else when it is first reported)."""
        began = {} if began is None else began

        def progress(phase: str, done: int, total: int) -> None:
            began.setdefault(phase, time.perf_counter())
            text = f"{prefix}: {phase}" + (f" ({done} of {total})" if total > 1 else "")
            if 0 < done < total:
                left = (time.perf_counter() - began[phase]) * (total - done) / done
                text += f", about {left:.0f} s left"
            now["text"] = text
            if self._current(generation):
                self.listener.status(f"{text} ...")
                if total > 1:
                    self.listener.progress(done / total)

        return progress

    def _load_solver(self, config: RunConfig, source, combined: dict) -> None:
        """The model's compiled stepping code loaded (compiled on a fresh install) by the first step of a
        throw-away run of this configuration, as :meth:`warm_up` does: so that the page names this wait."""
        run = self._prepare(
            source, model=config.model, line=config.line, params=config.params(), length=config.length, **combined
        )
        next(iter(run.steps()), None)
        run.cancel()

    def _one_model(
        self, generation: int, config: RunConfig, roughness: tuple, position: tuple[int, int], first: bool = False
    ) -> str:
        """Prepare, stream and finish one model on (rail or single set, wheel set or None); 'done', 'stopped',
        'failed' or 'replaced'."""
        number, count = position
        run = self._prepared(generation, config, roughness, first)
        roughness, wheel = roughness
        with self._lock:
            if run is None or not self._current(generation):
                return "replaced"
            self._run = run
            if self._stopped_generation == generation:
                run.cancel()
        view = RunView(
            config=config,
            roughness=roughness,
            window_x=getattr(run, "window_x", None),
            window_y=getattr(run, "window_y", None),
            wheel_roughness=wheel,
        )
        self.listener.status(f"Running {config.model} ({number + 1}/{count}) on {config.case_label()} ...")
        state = None
        last_frame = last_plot = -float("inf")
        for state in run.chunk_states():  # the last step of each chunk: what a frame shows
            if not self._current(generation):
                run.cancel()
                return "replaced"
            now = time.perf_counter()
            if now - last_frame >= self._frame_interval:
                self.listener.frame(state, view)
                last_frame = now
            if now - last_plot >= PLOT_INTERVAL:
                self.listener.live(run.result(), view)
                self.listener.progress((number + (state.step + 1) / run.n_steps) / count)
                last_plot = now
        result = run.result()
        if not self._current(generation):
            return "replaced"
        if state is not None:
            self.listener.frame(state, view)
        if run.cancelled:
            problem = f"stopped after {result.n_steps} of {run.n_steps} steps"
            self.store.add(Entry(config, result, None, problem, run.n_steps))
            self.listener.model_done(self.store.entries(config.case())[config.model], view)
            self.listener.status(
                f"Stopped {config.model} after {result.n_steps} of {run.n_steps} steps "
                f"({config.case_label()}); no spectrum for a stopped run."
            )
            return "stopped"
        try:
            spectrum = force_spectrum(result)
        except WheelrailError as error:
            message = f"{config.model}: no force spectrum: {page_message(error)}"
            self.store.add(Entry(config, result, None, message, run.n_steps))
            self.listener.model_done(self.store.entries(config.case())[config.model], view)
            self._failed(generation, message)
            return "failed"
        noise, noise_problem = self._rolling_noise(generation, config, result)
        if not self._current(generation):
            return "replaced"
        self.store.add(Entry(config, result, spectrum, None, run.n_steps, noise, noise_problem))
        self.listener.model_done(self.store.entries(config.case())[config.model], view)
        self.listener.progress((number + 1) / count)
        return "done"

    def _rolling_noise(self, generation: int, config: RunConfig, result) -> tuple[object, str | None]:
        """The run's rolling noise (sound power, pass-by, CNOSSOS-EU beside it) or why there is none; a failure
        here is said in the Noise tab and does not fail the run."""
        if self._noise is None:
            return None, "no rolling noise computed for these runs"
        text = f"Rolling noise of {config.model}: the track's transfer functions (computed once per track)"
        try:
            with self._ticking(generation, text):
                return self._noise(result), None
        except WheelrailError as error:
            message = page_message(error)
        except Exception as error:  # the run stands; the Noise tab says why it has no noise
            LOG.exception("rolling noise of %s failed", config.label())
            message = f"unexpected error: {type(error).__name__}: {error}"
        LOG.warning("no rolling noise for %s: %s", config.label(), message)
        return None, f"no rolling noise: {message}"


class _Stop:
    """Ends a :meth:`RunController._ticking` block."""

    def __init__(self, done: threading.Event, thread: threading.Thread | None) -> None:
        self._done, self._thread = done, thread

    def __enter__(self) -> None:
        return None

    def __exit__(self, *exc) -> None:
        self._done.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join()


def _track_case(config: RunConfig) -> tuple:
    """What a run's Green's functions depend on: its track, its numerics and speed (a new one: a first preparation)."""
    return config.params().track, config.track_numerics, round(config.speed, 6)


def _track_green_functions(params, track_numerics=None) -> None:
    """The track's moving Green's functions at the run's speed on its numerics (core computes them once and caches
    them)."""
    from wheelrail.core.track import moving_green_functions

    moving_green_functions(params.run.speed, params.track, track_numerics)


def _rolling_noise(result):
    """A run's rolling noise (:func:`wheelrail.core.noise.run_noise.run_noise`, the default train)."""
    from wheelrail.core.noise.run_noise import run_noise

    return run_noise(result)


def _noise_transfer_functions(params) -> None:
    """The model track's noise transfer functions for ``params`` (core keeps them for the process)."""
    from wheelrail.core.noise.twins import track_noise_model

    track_noise_model(params)


def _source(rough, label: str):
    """What a run is given for a set: a bundled set by its name (loaded again in milliseconds, so that the
    result's header records the name, as a command-line run does), any other set (an upload) as it is."""
    from wheelrail.core.roughness import bundled_names

    return label if label in bundled_names() else rough
