"""The explorer's first Run during its warm-up, in a real headless Chromium: the page shows the warm-up's phase,
a bar above zero and an estimate from the moment Run is pressed, while the warm-up is still held (on an event)."""

from __future__ import annotations

import threading
from types import SimpleNamespace

from wheelrail.core.track.progress import current_progress
from wheelrail.explorer.controller import WAITING, RunController

WAIT = 120.0  # s: only a bound on a hung thread, never reached when the code works
PHASE = "integrating the impulse responses (about 20 s)"


class _OneStep:
    """The warm-up's throw-away run: one step, then cancelled."""

    def steps(self):
        yield SimpleNamespace(step=0)

    def cancel(self):
        pass


def test_a_first_run_during_the_warm_up_shows_its_phase_bar_and_estimate(open_page, explorer):
    page, session, errors = open_page()
    entered, release = threading.Event(), threading.Event()

    def precompute(params):  # the warm-up's track precompute, reporting as core's does, held until released
        report = current_progress()
        report("assembling the FE track", 0, 1)
        for done in (1, 2):
            report(PHASE, done, 4)
        entered.set()
        assert release.wait(WAIT)

    # the explorer's preparation: its pages' runs wait for this warm-up, as for the one `wheelrail explore` starts
    warm_up = RunController(
        None, prepare=lambda *args, **kwargs: _OneStep(), precompute=precompute, preparation=explorer.preparation
    )
    thread = warm_up.warm_up(session.form.read_config(), roughness=None)
    try:
        assert entered.wait(WAIT)
        page.get_by_role("button", name="Run", exact=True).click()
        page.get_by_text(f"{WAITING}: {PHASE} (2 of 4), about").first.wait_for(timeout=60_000)
        page.wait_for_function(
            "() => [...document.querySelectorAll('[role=progressbar]')]"
            ".some(bar => Number(bar.getAttribute('aria-valuenow')) > 0)",
            timeout=60_000,
        )
        assert thread.is_alive() and session.form.progress == 50.0
    finally:
        session.controller.cancel_current()  # the run, superseded, computes nothing once the warm-up ends
        release.set()
        thread.join(WAIT)
    assert not errors, errors
