"""The Patch tab: the colour bar of the contact pressure, the readout, the Step slider and Play (the
:class:`~wheelrail.explorer.replay.Replay`), the model shown, force and displacement histories (over
irregularities: each impact's peak marked and the impacts said below the force), the run's download and the 3D
view's options."""

from __future__ import annotations

import numpy as np
import viser

from wheelrail.core.engine.impacts import impact_summary
from wheelrail.explorer.config import COMPARE, RunConfig
from wheelrail.explorer.form import DEFAULT_MODEL, RunForm
from wheelrail.explorer.panel import NO_RUN, ResultsTab, Shown, TabParts
from wheelrail.explorer.plots import MAX_POINTS, POINTS, SOLID, Plot, model_colour
from wheelrail.explorer.scene import PRESSURE_TOP, colour_bar_image

__all__ = ["PatchTab", "impact_markers", "impact_text"]


def impact_markers(x: np.ndarray, summary) -> np.ndarray:
    """A markers-only curve (kN) over the plotted positions ``x`` (m): each impact's peak force at the plotted
    position nearest its own, NaN elsewhere."""
    markers = np.full(np.shape(x), np.nan)
    if np.size(x):
        for impact in summary.impacts:
            markers[int(np.argmin(np.abs(x - impact.position)))] = impact.peak / 1e3
    return markers


def impact_text(summaries: dict, config: RunConfig) -> str:
    """The impacts of each model (core's ``ImpactSummary.lines``, as ``wheelrail run`` prints them) under the run's
    irregularities, as markdown."""
    parts = [f"**Impacts** over {config.irregularity_words()}:"]
    for model, summary in summaries.items():
        first, *rest = summary.lines()
        parts.append(f"- **{model}**: {first}" + "".join(f"<br>{line.strip()}" for line in rest))
    return "\n".join(parts)


class PatchTab(ResultsTab):
    """The patch shown in the 3D view: colour bar, readout, Step slider and replay, the model shown, force and
    displacement histories, the run's download and the view's options."""

    title, icon = "Patch", viser.Icon.CIRCLE

    def __init__(self, parts: TabParts, tab) -> None:
        super().__init__(parts, tab)
        gui, page, replay = self.gui, self.page, parts.replay
        self._colour_bar_key = None  # the peak pressure the colour bar shows
        with tab:
            self.colour_bar = gui.add_image(
                np.full((10, 10, 3), 255, np.uint8), label="contact pressure (MPa)", format="png"
            )
            self.readout_md = gui.add_markdown("")
            self.time_slider = gui.add_slider("Step", min=0, max=1, step=1, initial_value=0, disabled=True)
            self.time_slider.on_update(lambda event: page.guarded(replay.scrub, self.time_slider.value))
            self.play_button = gui.add_button("Play", icon=viser.Icon.PLAYER_PLAY, disabled=True)
            self.play_button.on_click(lambda event: page.guarded(replay.toggle_play))
            self.model_shown = gui.add_dropdown(
                "Model shown",
                (DEFAULT_MODEL,),
                initial_value=DEFAULT_MODEL,
                disabled=True,
                hint="After compare: the model replayed, plotted as displacement and downloaded",
            )
            self.model_shown.on_update(
                lambda event: None if page.is_quiet() else page.guarded(parts.choose_model, self.model_shown.value)
            )
        self.force = Plot(gui, tab, "Contact force", "position (m)", "force (kN)")
        with tab:
            self.impacts_md = gui.add_markdown("", visible=False)  # a run over irregularities: its impacts
        self.displacement = Plot(
            gui, tab, "Wheel and rail displacement (downwards)", "position (m)", "displacement (µm)"
        )
        with tab:
            self.rrd_button = gui.add_button("Download run (.rrd)", icon=viser.Icon.DOWNLOAD, disabled=True)
            self.rrd_button.on_click(lambda event: page.guarded(parts.downloads.rrd, event.client, client=event.client))
            self.replay_speed = gui.add_dropdown("Replay speed", tuple(replay.speeds), initial_value="0.02x")
            self.view_buttons = gui.add_button_group("3D view", ("Top view", "Oblique view"))
            self.view_buttons.on_click(lambda event: page.guarded(page.set_view, event.target.value, event.client))
            self.surfaces_box = gui.add_checkbox(
                "Rail and wheel surfaces",
                False,
                hint="Roughness drawn 200 times its size: the rail below the patch, the wheel as lines above it",
            )
            self.surfaces_box.on_update(lambda event: page.guarded(replay.draw_surfaces))
            self.raised_box = gui.add_checkbox("Raised pressure surface", False, hint="3 mm per GPa")
            self.raised_box.on_update(lambda event: page.guarded(replay.scene.set_raised, bool(self.raised_box.value)))
            self._plot_export()
        replay.show_in(self)

    def plots(self) -> dict[str, Plot]:
        return {"contact force": self.force, "displacement": self.displacement}

    def show_form(self, form: RunForm) -> None:
        """The colour bar of the contact the fields describe (drawn again only when its peak pressure changed:
        a matplotlib figure costs far more than a frame)."""
        p0 = form.contact().hertz_peak_pressure() / 1e6
        if self._colour_bar_key != round(p0, 1):
            self._colour_bar_key = round(p0, 1)
            self.colour_bar.image = colour_bar_image(round(PRESSURE_TOP * p0), p0)

    def show(self, shown: Shown) -> None:
        """Force history of every model of the case overlaid; displacement of the model shown."""
        self._show_models(shown)
        config = shown.config
        self.impacts_md.visible = False
        if config is None:
            for plot in (self.force, self.displacement):
                plot.clear("fix the settings on the left")
            return
        label = config.title_label()
        finished = {m: e for m, e in shown.store.entries(config.case()).items() if e.result.n_steps}
        if not finished:
            self.force.clear(NO_RUN, title=f"Contact force: {label}")
            self.displacement.clear(NO_RUN, title=f"Displacement: {label}")
            return
        n = min(e.result.n_steps for e in finished.values())
        step = max(1, n // MAX_POINTS)
        first = next(iter(finished.values())).result
        x = first.x[:n:step]
        curves = [e.result.force[:n:step] / 1e3 for e in finished.values()]
        series = [(m, model_colour(m), SOLID) for m in finished]
        if config.irregularities:  # each model's impacts marked at their peaks, and said below the plot
            summaries = {m: impact_summary(e.result) for m, e in finished.items()}
            curves += [impact_markers(x, summary) for summary in summaries.values()]
            series += [(f"{m} impacts", model_colour(m), POINTS) for m in summaries]
            self.impacts_md.content = impact_text(summaries, config)
            self.impacts_md.visible = True
        self.force.show((x, *curves), tuple(series), title=f"Contact force: {label}")
        shown_result = finished[shown.model].result if shown.model in finished else first
        self._displacement(shown_result, label)

    def _show_models(self, shown: Shown) -> None:
        """The Model shown menu: the models with a run (else the model of the controls), the one shown chosen;
        a choice only when there are two or more."""
        config, menu = shown.config, self.model_shown
        options = shown.models or ((config.model if config is not None and config.model != COMPARE else DEFAULT_MODEL),)
        with self.page.quietly():
            if tuple(menu.options) != options:
                menu.options = options
            if menu.value != (shown.model or options[0]):
                menu.value = shown.model or options[0]
        menu.disabled = len(shown.models) < 2

    def _displacement(self, result, label: str, running: bool = False) -> None:
        step = max(1, result.n_steps // MAX_POINTS)
        self.displacement.show(
            (result.x[::step], result.xi_wheel[::step] * 1e6, result.xi_rail[::step] * 1e6),
            (("wheel", "#1f77b4", SOLID), ("rail", "#d62728", SOLID)),
            title=f"Displacement, {result.model}{' (running)' if running else ''}: {label}",
        )

    def live(self, result, config: RunConfig) -> None:
        """A running model's force and displacement so far."""
        step = max(1, result.n_steps // MAX_POINTS)
        x, force = result.x[::step], result.force[::step] / 1e3
        curves, series = [force], [(f"{result.model} (running)", model_colour(result.model), SOLID)]
        if config.irregularities and force.size:  # the peak so far marked
            peak = np.full(force.shape, np.nan)
            peak[int(np.argmax(force))] = float(np.max(force))
            curves.append(peak)
            series.append((f"{result.model} peak so far", model_colour(result.model), POINTS))
        self.impacts_md.visible = False
        self.force.show((x, *curves), tuple(series), title=f"Contact force: {config.title_label()}")
        self._displacement(result, config.title_label(), running=True)
