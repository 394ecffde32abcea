"""Replay of a finished run in the 3D view: the Step slider, Play at a fraction of real time, the readout.

A :class:`Replay` draws one run's steps (a state and a :class:`~wheelrail.explorer.controller.RunView`) into the
:class:`~wheelrail.explorer.scene.PatchScene` and the Patch tab's readout; :meth:`Replay.show` makes an
:class:`~wheelrail.explorer.results.Entry` the run replayed (its last step) or clears the view. The Patch tab
builds the controls and hands itself over (:meth:`Replay.show_in`). While the configuration shown is being run,
its live frames own the view (``running()``).
"""

from __future__ import annotations

from collections.abc import Callable

from wheelrail.explorer.config import RunConfig
from wheelrail.explorer.controller import RunView
from wheelrail.explorer.form import RunForm
from wheelrail.explorer.page import Page
from wheelrail.explorer.results import Entry
from wheelrail.explorer.scene import PatchScene
from wheelrail.explorer.workers import Workers

__all__ = ["NO_RUN_READOUT", "REPLAY_FPS", "REPLAY_SPEEDS", "Replay"]

REPLAY_SPEEDS = {"0.01x": 0.01, "0.02x": 0.02, "0.05x": 0.05, "0.1x": 0.1}  # of real time
REPLAY_FPS = 20.0
NO_RUN_READOUT = "No run of this configuration yet: press **Run**."


class Replay:
    """The run the 3D view, readout, Step slider and Play show (``entry``; None: none)."""

    speeds = REPLAY_SPEEDS

    def __init__(
        self,
        page: Page,
        scene: PatchScene,
        form: RunForm,
        running: Callable[[], RunConfig | None],
        workers: Workers | None = None,
    ) -> None:
        """``running()``: the configuration being run when the page shows it (its live frames own the view);
        ``workers``: where Play's thread is started (joined when the page closes)."""
        self.page, self.scene, self.form, self._running = page, scene, form, running
        self.workers = Workers() if workers is None else workers
        self.entry: Entry | None = None
        self.patch = None  # the Patch tab, which holds the controls (show_in)
        self.playing = False

    def show_in(self, patch) -> None:
        """The tab whose readout, Step slider, Play button, replay speed and .rrd button this replay drives."""
        self.patch = patch

    def show(self, entry: Entry | None) -> None:
        """Make ``entry`` the run the 3D view, readout, slider and progress show (its last step), or clear them;
        while this configuration is being run, its live frames own the view."""
        patch, running = self.patch, self._running()
        self.entry = entry if entry is not None and entry.result.n_steps else None
        patch.rrd_button.disabled = patch.play_button.disabled = self.entry is None
        if running is not None:
            if self.entry is None or self.entry.config.model != running.model:
                self.scene.clear()  # until the run's next frame: nothing of another run
                patch.readout_md.content = f"Running {running.label()} ..."
            patch.time_slider.disabled = True
            return
        if self.entry is None:
            self.playing = False
            self.scene.clear()
            patch.readout_md.content = NO_RUN_READOUT
            patch.time_slider.disabled = True
            self._set_slider(0, 1)
            self.form.show_progress(0.0)
            self.draw_surfaces()
            return
        last = self.entry.result.n_steps - 1
        self._set_slider(last, max(1, last))
        patch.time_slider.disabled = False
        self.form.show_progress(self.entry.done_fraction)
        self.scrub(last)

    def _set_slider(self, value: int, maximum: int) -> None:
        """Set the Step slider without its callback drawing (the caller draws)."""
        slider = self.patch.time_slider
        with self.page.quietly():
            if slider.max != maximum:
                slider.max = maximum
            if slider.value != value:
                slider.value = value

    def scrub(self, step: int) -> None:
        """Show step ``step`` of the replayed run (the Step slider)."""
        entry = self.entry
        if self.page.is_quiet() or entry is None or self._running() is not None:
            return
        result = entry.result
        step = int(min(max(step, 0), result.n_steps - 1))
        self.draw(result.state(step), self.view_of(entry))

    def draw(self, state, view: RunView) -> None:
        """One step of a run in the 3D view and the readout."""
        with self.page.atomic():
            self.scene.draw(state, view)
            config = view.config
            contact = config.contact()
            a, b = (v * 1e3 for v in contact.hertz_semi_axes())
            self.patch.readout_md.content = (
                f"**{config.model}** step {state.step}: x = {state.position:.4f} m, F = {state.force / 1e3:.2f} kN, "
                f"contact length {state.contact_length * 1e3:.1f} mm  \n"
                f"Hertz at {config.preload / 1e3:g} kN: a = {a:.2f} mm along, b = {b:.2f} mm across, "
                f"p0 = {contact.hertz_peak_pressure() / 1e6:.0f} MPa"
            )

    def view_of(self, entry: Entry) -> RunView:
        """What drawing a step of ``entry`` needs: its roughness (and wheel roughness) and window."""
        sets, wheel, result = self.form.sets, entry.config.wheel_set_label, entry.result
        return RunView(
            config=entry.config,
            roughness=sets.get(entry.config.set_label, self.form.roughness),
            window_x=result.window_x,
            window_y=result.window_y,
            wheel_roughness=None if wheel is None else sets[wheel],
        )

    def toggle_play(self) -> None:
        """Play/pause the replayed run at the chosen fraction of real time (as viser's record3d example); not while
        the configuration shown is being run."""
        if self.playing:
            self.playing = False
            return
        if self.entry is None or self._running() is not None:
            return
        self.playing = True
        self.patch.play_button.label = "Pause"
        if self.workers.start(self._play, name="wheelrail-explorer-replay") is None:
            self.playing = False

    def _play(self) -> None:
        entry = self.entry
        result = entry.result
        slider = self.patch.time_slider
        steps_per_frame = max(1, round(REPLAY_SPEEDS[self.patch.replay_speed.value] / REPLAY_FPS / result.time_step))
        step = int(slider.value)
        if step >= result.n_steps - 1:
            step = 0
        while self.playing and self.entry is entry and step < result.n_steps:
            slider.value = step  # its callback draws the step
            step += steps_per_frame
            if self.workers.closed.wait(1.0 / REPLAY_FPS):  # the frame's time, or at once when the page closes
                return
        self.playing = False
        self.patch.play_button.label = "Play"

    def draw_surfaces(self) -> None:
        """Rail and wheel surfaces of the configuration shown, at the step shown (its start without a run)."""
        form, scene = self.form, self.scene
        scene.show_surfaces = bool(self.patch.surfaces_box.value)
        position = None
        if self.entry is not None:
            step = int(min(max(self.patch.time_slider.value, 0), self.entry.result.n_steps - 1))
            position = float(self.entry.result.x[step])
        line = form.line()
        if line is None:
            line = int(form.roughness.line_numbers[len(form.roughness.line_numbers) // 2])
        scene.draw_surfaces(form.roughness, position, line, form.contact(), form.wheel_or_none()[0])
