"""The run form, docked left: the roughness set and wheel set (bundled or uploaded), the model, the line, every
declared input of :mod:`wheelrail.core.inputs.declared` (one field each, grouped as declared), the Irregularity
folder (:mod:`wheelrail.explorer.irregularity`), the check line, Run, Stop, the progress bar and the status line.

A :class:`RunForm` is handed the :class:`~wheelrail.explorer.page.Page` and what Run, Stop and a new
configuration do; it reads its fields into a :class:`~wheelrail.explorer.config.RunConfig` (or the check line
says why not) and keeps the Line menu to the lines the model can run on (core's rule).
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable

import viser

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.declared import GROUPS, by_key, inputs_of, model_parameters
from wheelrail.core.models import HALFSPACE_MODEL
from wheelrail.core.parameters import KMH, ContactParameters
from wheelrail.core.roughness import bundled_names, load_roughness
from wheelrail.explorer.config import (
    COMPARE,
    MODEL_CHOICES,
    NO_LINE_FITS,
    NO_WHEEL_SET,
    NUMERICS_LABEL,
    RunConfig,
    field_hint,
    field_text,
    length_range,
    numerics_hint,
    offered_lines,
    page_message,
    read_config,
    read_inputs,
)
from wheelrail.explorer.irregularity import IrregularityFolder
from wheelrail.explorer.page import Page
from wheelrail.explorer.uploads import read_upload, size_text

__all__ = ["DEFAULT_LENGTH", "DEFAULT_MODEL", "DEFAULT_SET", "RunForm"]

LOG = logging.getLogger("wheelrail.explorer")
DEFAULT_SET = "corrugated-rail"
DEFAULT_LENGTH = 3.0  # m
DEFAULT_MODEL = HALFSPACE_MODEL  # the page opens on the model with pressure maps


class RunForm:
    """The controls of one run and what they describe; ``changed(config)`` is called after any of them changed
    (``config`` None: the check line says what is wrong), ``run(client)`` and ``stop()`` by the buttons."""

    def __init__(
        self,
        page: Page,
        *,
        changed: Callable[[RunConfig | None], None],
        run: Callable[[object], object],
        stop: Callable[[], None],
        roughness: str = DEFAULT_SET,
        length: float = DEFAULT_LENGTH,
    ) -> None:
        self.page, self._changed = page, changed
        self.sets: dict[str, object] = {}  # every set opened or uploaded, by its label
        self.roughness = None
        self.roughness_label = ""
        self.length_note = ""  # what the last change of set did to the run length, if anything
        self._lock = threading.RLock()
        gui = page.gui
        self.folder = gui.add_folder(GROUPS["run"])  # the run group's fields in it, the other groups folded
        with self.folder:
            self._add_sets(roughness)
            self.model_dropdown = gui.add_dropdown(
                "Contact model",
                MODEL_CHOICES,
                initial_value=DEFAULT_MODEL,
                hint=f"{COMPARE}: every model one after another",
            )
            self.line_dropdown = gui.add_dropdown(
                "Line", ("0",), initial_value="0", hint="Only the lines this model can run on are offered."
            )
            self.fields = self._input_fields("run")
            self.length_text = gui.add_text("Run length (m)", f"{length:g}")
            for group in GROUPS:
                if group != "run":
                    with gui.add_folder(GROUPS[group], expand_by_default=False):
                        self.fields.update(self._input_fields(group))
                        if group == "track":
                            self.numerics_text = gui.add_text(NUMERICS_LABEL, "", hint=numerics_hint())
            self.irregularity = IrregularityFolder(gui)
            controls = (self.model_dropdown, self.line_dropdown, self.length_text, self.numerics_text,
                        *self.fields.values())  # fmt: skip
            for handle in (*controls, *self.irregularity.handles):
                handle.on_update(lambda event: page.guarded(self.refresh))
            self.check_md = gui.add_markdown("")
            self.run_button = gui.add_button("Run", icon=viser.Icon.PLAYER_PLAY, color="green")
            self.run_button.on_click(lambda event: run(event.client))
            self._stop_button = gui.add_button("Stop", icon=viser.Icon.PLAYER_STOP, color="red", disabled=True)
            self._stop_button.on_click(lambda event: stop())
            self._progress_bar = gui.add_progress_bar(0.0, animated=False)
            page.add_status()

    def _add_sets(self, roughness: str) -> None:
        """The rail set, wheel set and upload controls."""
        gui, page = self.page.gui, self.page
        names = bundled_names()
        self.set_dropdown = gui.add_dropdown(
            "Roughness set", names, initial_value=roughness if roughness in names else names[0]
        )
        self.set_dropdown.on_update(
            lambda event: page.guarded(self.select_set, self.set_dropdown.value, client=event.client)
        )
        self.wheel_set_dropdown = gui.add_dropdown(
            "Wheel roughness",
            (NO_WHEEL_SET, *self.wheel_set_names()),
            initial_value=NO_WHEEL_SET,
            hint="A wheel set added to the rail set (combined roughness); none: a smooth wheel.",
        )
        self.wheel_set_dropdown.on_update(lambda event: page.guarded(self.select_wheel_set, client=event.client))
        self.upload_button = page.add_upload(
            f"Upload CSV/NPZ (<= {size_text(page.max_upload_bytes)})",
            "A roughness file in the CSV or NPZ format of the user guide (Roughness data); read in memory.",
            self.load_upload,
        )

    def _input_fields(self, group: str) -> dict:
        """The fields of the declared inputs of ``group`` (wheelrail.core.inputs.declared), by key: labelled with their
        unit, hinted with their range and default, showing the default (empty where unset means one)."""
        gui = self.page.gui
        fields = {}
        for entry in inputs_of(group):
            unit = f" ({entry.shown.name})" if entry.shown.name else ""
            fields[entry.key] = gui.add_text(f"{entry.label}{unit}", field_text(entry), hint=field_hint(entry))
        return fields

    # ------------------------------------------------------------------ sets
    def select_set(self, name: str) -> None:
        """Make ``name`` (a bundled set or an uploaded file's label) the current roughness set; a run length
        outside what it holds is brought into range, saying so."""
        if name in self.sets:
            rough = self.sets[name]
        elif name in bundled_names():  # only names: a value sent by a browser is never opened as a path
            rough = self.sets[name] = load_roughness(name)
        else:
            self.set_dropdown.value = self.roughness_label
            raise WheelrailError(f"unknown roughness set {name!r}; choose a bundled set or upload a file")
        self.roughness, self.roughness_label = rough, name
        self._bound_length()
        self.refresh()

    def load_upload(self, name: str, content: bytes, client=None) -> str:
        """A roughness file from the browser becomes a set of the menu, chosen; one WheelrailError if it cannot."""
        label, rough = read_upload(name, content, self.page.max_upload_bytes)
        slowest = by_key("speed").accepted.minimum  # the shortest run with a force spectrum is the slowest's
        shortest, longest = length_range(rough, slowest)  # a set too short for any run: a one-line error
        if longest < shortest:
            raise WheelrailError(
                f"{label}: {rough.length:.3g} m of data, too short for a force spectrum at any accepted speed "
                f"(a run of at least {shortest:g} m at {slowest / KMH:g} km/h); the set is not loaded"
            )
        self.sets[label] = rough
        options = tuple(self.set_dropdown.options)
        if label not in options:
            self.set_dropdown.options = (*options, label)
        self.set_dropdown.value = label  # its callback selects it (a new name)
        if self.roughness_label != label or self.roughness is not rough:  # the same name again: the new content
            self.select_set(label)
        message = f"Loaded {label}: {rough.kind}, {rough.n_lines} lines, {rough.length:.3g} m. {self.length_note}"
        self.page.status(message.strip())
        self.page.notify("File loaded", message, client, colour="green")
        LOG.info("uploaded %s", label)
        return label

    def _bound_length(self) -> None:
        """A run length the new set cannot hold (or too short for a spectrum) moves to the nearest allowed."""
        speed = self.field_value("speed")
        try:
            length = float(self.length_text.value)
        except ValueError:
            return
        if speed is None or not math.isfinite(length):
            return
        shortest, longest = length_range(self.roughness, speed, self.element_size())
        bounded = min(max(length, shortest), longest)
        self.length_note = ""
        if abs(bounded - length) > 1e-9:
            with self.page.quietly():
                self.length_text.value = f"{bounded:g}"
            self.length_note = (
                f"Run length {length:g} m is not possible on {self.roughness_label} at "
                f"{speed / KMH:g} km/h ({shortest:g} to {longest:g} m): {bounded:g} m is set."
            )
            self.page.status(self.length_note)

    def wheel_set_names(self) -> tuple[str, ...]:
        """The bundled wheel sets (the wheel-set picker's choices besides none)."""
        names = []
        for name in bundled_names():
            if name not in self.sets:
                self.sets[name] = load_roughness(name)
            if self.sets[name].kind == "wheel":
                names.append(name)
        return tuple(names)

    def select_wheel_set(self) -> None:
        """After the wheel-set picker changed: a name that is no bundled wheel set is refused (back to none)."""
        try:
            self._wheel()
        finally:
            self.refresh()

    def _wheel(self) -> tuple[object, str | None]:
        """The chosen wheel set and its name, or (None, None); only a bundled wheel set is ever opened."""
        name = self.wheel_set_dropdown.value
        if name == NO_WHEEL_SET:
            return None, None
        if name not in self.wheel_set_names():
            self.wheel_set_dropdown.value = NO_WHEEL_SET
            raise WheelrailError(f"unknown wheel set {name!r}; choose a bundled wheel set or {NO_WHEEL_SET}")
        return self.sets[name], name

    def wheel_or_none(self) -> tuple[object, str | None]:
        """The wheel set that applies to the set shown (a rail set), or (None, None)."""
        try:
            return self._wheel() if self.roughness.kind == "rail" else (None, None)
        except WheelrailError:
            return None, None

    # ------------------------------------------------------------------ fields
    def typed(self) -> dict[str, str]:
        """The declared inputs' fields as typed, by their ``dest`` (``speed_kmh``: "100"), for read_config."""
        return {entry.dest: self.fields[entry.key].value for entry in inputs_of()}

    def field_value(self, key: str) -> float | None:
        """One declared input's field, SI, when it holds a number within its range (else None: the check line
        says what is wrong)."""
        entry = by_key(key)
        try:
            given = dict(read_inputs(**{entry.dest: self.fields[key].value}))
        except WheelrailError:
            return None
        return given.get(key, entry.default())

    def contact(self) -> ContactParameters:
        """The contact the fields describe; a field not valid yet counts as its default (the check line says)."""
        try:
            return model_parameters(dict(read_inputs(**self.typed()))).contact
        except WheelrailError:  # an input refused (e.g. a patch too wide at this preload): the preload's alone
            preload = self.field_value("preload")
            return ContactParameters() if preload is None else ContactParameters(preload=preload)

    def element_size(self) -> float:
        """The element size typed, m; one not valid yet counts as its default (the check line says)."""
        return self.field_value("element_size") or by_key("element_size").default()

    def line(self) -> int | None:
        """The line chosen (None: no line fits)."""
        try:
            return int(self.line_dropdown.value)
        except ValueError:
            return None

    def _offer_lines(self) -> None:
        """The Line menu: the lines the model can run on with the sets loaded (core's rule), or 'no line
        fits'; a line no longer offered moves to the nearest one offered, and the page says so."""
        lines = offered_lines(
            self.roughness, self.model_dropdown.value, self.contact(), self.wheel_or_none()[0], self.element_size()
        )
        options = tuple(str(n) for n in lines) or (NO_LINE_FITS,)
        current = self.line_dropdown.value
        if tuple(self.line_dropdown.options) != options:
            self.line_dropdown.options = options
        if not lines:
            if self.line_dropdown.value != NO_LINE_FITS:
                self.line_dropdown.value = NO_LINE_FITS
            return
        try:
            wanted = int(current)
        except ValueError:
            wanted = 0
        if str(wanted) not in options:
            nearest = min(lines, key=lambda n: (abs(n - wanted), n))
            self.line_dropdown.value = str(nearest)
            if current in ("", "0", NO_LINE_FITS) or wanted == 0:
                return
            self.page.status(
                f"Line {wanted} is not offered for {self.model_dropdown.value} on "
                f"{self.roughness_label}; line {nearest} is chosen."
            )
        elif self.line_dropdown.value != str(wanted):
            self.line_dropdown.value = str(wanted)

    def read_config(self) -> RunConfig:
        """The configuration the controls describe, or one WheelrailError in the page's words."""
        wheel, wheel_label = self._wheel()
        return read_config(
            self.roughness,
            self.roughness_label,
            line=self.line_dropdown.value,
            model=self.model_dropdown.value,
            length_m=self.length_text.value,
            **self.typed(),
            wheel=wheel,
            wheel_label=wheel_label,
            irregular=self.irregularity.read(),
            track_numerics=self.numerics_text.value,
        )

    def show_running(self, running: bool) -> None:
        """A run started (progress 0, the bar animated, Stop enabled) or ended (the bar still, Stop disabled)."""
        if running:
            self._progress_bar.value = 0.0
        self._progress_bar.animated = running
        self._stop_button.disabled = not running

    def show_progress(self, fraction: float) -> None:
        """The progress bar at ``fraction`` of the run (clipped to 0 to 1; shown in percent to 0.1)."""
        self._progress_bar.value = round(100.0 * min(max(fraction, 0.0), 1.0), 1)

    @property
    def progress(self) -> float:
        """The progress shown, percent."""
        return self._progress_bar.value

    def show_session(self, session: dict) -> None:
        """Set every control from a checked session document (``wheelrail.explorer.config.read_session``): the set,
        the wheel set, the model, the length, the inputs and the Irregularity folder as typed, then the line if the
        model can run on it."""
        with self.page.quietly():
            self.set_dropdown.value = session["set"]
            self.wheel_set_dropdown.value = session["wheel_set"]
            self.model_dropdown.value = session["model"]
            self.length_text.value = session["length_m"]
            for entry in inputs_of():
                self.fields[entry.key].value = session["inputs"].get(entry.dest, field_text(entry))
            self.numerics_text.value = session.get("track_numerics", "")
            self.irregularity.show_session(session.get("irregularity", {}))
        self.select_set(session["set"])
        with self.page.quietly():
            if session["line"] in self.line_dropdown.options:
                self.line_dropdown.value = session["line"]
        self.refresh()

    def refresh(self) -> None:
        """After any control changed: offered lines, the check line, and the configuration handed on."""
        if self.page.is_quiet():
            return
        with self._lock:
            self._offer_lines()
            speed = self.field_value("speed") or by_key("speed").default()
            shortest, longest = length_range(self.roughness, speed, self.element_size())
            try:
                config = self.read_config()
            except WheelrailError as error:
                config = None
                self.check_md.content = f"**Cannot run:** {page_message(error)}"
            else:
                self.check_md.content = (
                    f"Run length {shortest:g} to {longest:g} m on this set at {config.speed / KMH:g} km/h."
                )
            self._changed(config)
