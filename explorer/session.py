"""Save and load the page's settings: the Session folder of the run form.

A session document (:meth:`SessionFiles.session`) holds the set, the wheel set, the model, the line, the run length
and every declared input's field as typed; it downloads as a .json file and loads back
(:func:`wheelrail.explorer.config.read_session` checks it).
"""

from __future__ import annotations

import viser

from wheelrail.core.roughness import load_roughness
from wheelrail.explorer.config import NO_WHEEL_SET, RunConfig, read_session, session_config
from wheelrail.explorer.form import RunForm
from wheelrail.explorer.page import Page

__all__ = ["SESSION_VERSION", "SessionFiles"]

SESSION_VERSION = 1  # of the session document


class SessionFiles:
    """The Session folder: Save session (.json) and Load session (.json), built where it is made."""

    def __init__(self, page: Page, form: RunForm, shown) -> None:
        """``shown()``: the configuration the page shows (None: not valid), which names the file."""
        self.page, self.form, self._shown = page, form, shown
        gui = page.gui
        with gui.add_folder("Session", expand_by_default=False):
            self.save_button = gui.add_button("Save session (.json)", icon=viser.Icon.DOWNLOAD)
            self.save_button.on_click(lambda event: page.guarded(self.download, event.client, client=event.client))
            self.load_button = page.add_upload(
                "Load session (.json)",
                "A session saved here: its set, wheel set, model, line, run length and every input.",
                lambda name, content, client: self.load(content),
            )

    def session(self) -> dict:
        """The page's settings as a session document (JSON-able): set, wheel set, model, line, run length and
        every declared input's field as typed (by its option's name: ``speed_kmh``, ``pad_stiffness_mn_m``), and the
        Irregularity folder as typed when it holds anything."""
        form = self.form
        irregularity = form.irregularity.session()  # the Irregularity folder, when not as a new page has it
        return {
            "wheelrail_session": SESSION_VERSION,
            "set": form.roughness_label,
            "wheel_set": form.wheel_set_dropdown.value,
            "model": form.model_dropdown.value,
            "line": form.line_dropdown.value,
            "length_m": form.length_text.value,
            "inputs": form.typed(),
            **({} if irregularity is None else {"irregularity": irregularity}),
            **({"track_numerics": form.numerics_text.value} if form.numerics_text.value.strip() else {}),
        }

    def download(self, client=None) -> tuple[str, bytes]:
        """The session (:meth:`session`) as a .json download, named after the configuration when it is valid."""
        from wheelrail.core.files.jsonready import strict_json

        shown: RunConfig | None = self._shown()
        stem = shown.for_model(shown.model).file_stem() if shown is not None else "wheelrail"
        return self.page.send(f"{stem}-session.json", strict_json(self.session(), indent=2).encode(), client)

    def load(self, content: bytes) -> None:
        """Set the page from a session document (:meth:`session`); one WheelrailError, and nothing changed, if it
        is not one or names a set this page does not have (upload the set first)."""
        form, page = self.form, self.page
        session = read_session(content, tuple(form.set_dropdown.options), tuple(form.wheel_set_dropdown.options))
        wheel_label = None if session["wheel_set"] == NO_WHEEL_SET else session["wheel_set"]
        name = session["set"]  # one of the menu's: an uploaded set's label or a bundled set's name
        session_config(
            session,
            form.sets[name] if name in form.sets else load_roughness(name),
            None if wheel_label is None else form.sets[wheel_label],
            wheel_label,
        )  # every value checked before any field is set
        form.show_session(session)
        shown = self._shown()
        page.status(f"Session loaded: {shown.label() if shown is not None else 'not a valid run yet'}.")
