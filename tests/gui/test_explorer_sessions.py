"""Each browser tab its own session: every client of the explorer gets its own form, run, results and downloads
(viser's per-client GUI); a run in one tab never changes what another shows; a closed tab's run stops and its
results are let go.

Tabs are opened without a browser (:class:`~wheelrail.explorer.headless.HeadlessTab`) and, in the slow test at the
end, as two real pages of headless Chromium at once. A run that must still be going when its tab closes is held
after its first chunk (:class:`Held`) until it is cancelled: "still running" never depends on the machine's speed.
"""

from __future__ import annotations

import gc
import threading
import weakref

import pytest

from wheelrail.explorer.headless import HeadlessTab
from wheelrail.explorer.panel import NO_OVERLAY
from wheelrail.explorer.tabs import PatchTab, SpectraTab

pytestmark = pytest.mark.slow  # a server, its tabs and short runs of core: seconds
WAIT = 120.0  # s: only a bound on a hung thread, never reached when the code works


class Held:
    """A run of core whose chunks stop after the first until the run is cancelled (``reached``: the first chunk
    was handed on)."""

    def __init__(self, run, reached: threading.Event) -> None:
        self.run, self.reached = run, reached
        self._cancelled = threading.Event()

    def __getattr__(self, name):
        return getattr(self.run, name)

    def cancel(self) -> None:
        self.run.cancel()
        self._cancelled.set()

    def chunk_states(self):
        for number, state in enumerate(self.run.chunk_states()):
            yield state
            if number == 0:
                self.reached.set()
                assert self._cancelled.wait(WAIT), "the held run was never cancelled"


def hold_runs(session) -> tuple[list[Held], threading.Event]:
    """Make the session's controller hold every run it starts; the runs held, in order, and the event set when one
    has handed on its first chunk."""
    held, reached = [], threading.Event()
    prepare = session.controller._prepare

    def holding(*args, **kwargs):
        run = Held(prepare(*args, **kwargs), reached)
        held.append(run)
        return run

    session.controller._prepare = holding
    return held, reached


def _tab(explorer):
    """A tab opened without a browser and its session."""
    from conftest import new_session

    return new_session(explorer, lambda: HeadlessTab(explorer.port))


def _short(session, speed="100") -> None:
    form = session.form
    form.model_dropdown.value = "hertz"
    form.line_dropdown.value = "0"
    form.fields["speed"].value = speed
    form.length_text.value = "0.6"


def test_two_tabs_have_their_own_forms_runs_and_results(explorer, finish_run):
    tab_a, a = _tab(explorer)
    tab_b, b = _tab(explorer)
    try:
        assert a is not b and a.client.client_id != b.client.client_id
        assert a.form.fields["speed"] is not b.form.fields["speed"]  # a control of each tab's own GUI
        assert a.controller is not b.controller and a.store is not b.store
        assert a.controller._first_preparation is b.controller._first_preparation  # shared: one first preparation
        b_status, b_readout = b.page.status_md.content, b.tab(PatchTab).readout_md.content
        _short(a, speed="90")
        assert b.form.model_dropdown.value == "3d" and b.form.fields["speed"].value == "100"
        finish_run(a)
        assert a.store.run_list() and a.page.status_md.content.startswith("Done: hertz")
        # B: its form, its status line, its (empty) results and its overlay menus as they were
        assert b.form.model_dropdown.value == "3d" and b.form.fields["speed"].value == "100"
        assert b.page.status_md.content == b_status and b.tab(PatchTab).readout_md.content == b_readout
        assert not b.store.run_list() and b.replay.entry is None
        assert tuple(b.tab(SpectraTab).overlay_dropdown.options) == (NO_OVERLAY,)
        # B runs the same configuration: its own run, A's results unchanged
        a_entry = a.replay.entry
        _short(b, speed="90")
        assert "no run of this configuration yet" in b.tab(PatchTab).readout_md.content.lower()
        finish_run(b)
        assert b.replay.entry is not a_entry and a.replay.entry is a_entry
    finally:
        tab_a.close()
        tab_b.close()
    assert explorer.wait_for(lambda: not ({a.client.client_id, b.client.client_id} & set(explorer.sessions)), WAIT)


def test_a_closed_tabs_run_stops_and_its_results_go(explorer):
    tab_a, a = _tab(explorer)
    tab_b, b = _tab(explorer)
    try:
        _short(a, speed="95")
        held, reached = hold_runs(a)
        assert a.start_run(), a.page.last_error
        assert reached.wait(WAIT), "the run never took its first chunk"
        assert a.controller.running
        a_id = a.client.client_id
        tab_a.close()  # the tab closes mid-run
        assert explorer.wait_for(lambda: a_id not in explorer.sessions, WAIT)
        assert held[-1].run.cancelled and not a.controller.running  # stopped, its thread joined
        assert a.workers.closed.is_set() and not a.workers.alive()
        assert not a.store.run_list() and a.replay.entry is None  # its results let go
        gone = weakref.ref(a)
        del a
        gc.collect()
        assert gone() is None  # nothing of the explorer holds the closed tab's session: its memory is freed
        # B is untouched and still works
        assert b.client.client_id in explorer.sessions and b.form.fields["speed"].value == "100"
        assert not b.store.run_list()
    finally:
        tab_b.close()


def _text_field(page, label):
    """viser 1.1's text inputs carry no label element: the input nearest the label's text."""
    return page.get_by_text(label, exact=True).first.locator("xpath=following::input[1]")


def test_two_pages_at_once_hold_two_sessions(explorer, open_page):
    """Two real pages: page A runs, page B's form and results are unchanged; closing page A mid-run stops its run."""
    page_a, a, errors_a = open_page(1280, 800)
    page_b, b, errors_b = open_page(1280, 800)
    assert a is not b
    _short(a, speed="90")
    _text_field(page_a, "Speed (km/h)").wait_for()
    page_a.get_by_role("button", name="Run", exact=True).click()
    page_a.get_by_text("Done: hertz on corrugated-rail, line 0, 90 km/h", exact=False).wait_for(timeout=300_000)
    assert a.store.run_list()
    # page B: its own form (the defaults), its own status line, no result
    assert _text_field(page_b, "Speed (km/h)").input_value() == "100"
    assert page_b.get_by_text("Done: hertz", exact=False).count() == 0
    page_b.get_by_text("No run of this configuration yet", exact=False).first.wait_for(state="attached")
    assert not b.store.run_list() and b.replay.entry is None and b.form.model_dropdown.value == "3d"
    # page A closes while its next run goes on: the run stops, its session goes; page B stays
    held, reached = hold_runs(a)
    _short(a, speed="95")
    page_a.get_by_role("button", name="Run", exact=True).click()
    assert reached.wait(WAIT), "the run never took its first chunk"
    page_a.close()
    assert explorer.wait_for(lambda: a.client.client_id not in explorer.sessions, WAIT)
    assert held[-1].run.cancelled and not a.controller.running and not a.workers.alive()
    assert b.client.client_id in explorer.sessions and _text_field(page_b, "Speed (km/h)").input_value() == "100"
    assert not errors_a and not errors_b, (errors_a, errors_b)
