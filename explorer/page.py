"""The page around every control: its status line, its notices, callbacks guarded, the camera fitted, files sent
and received.

A :class:`Page` is one browser tab's: its controls are built on that client's own GUI (``client.gui``), its
notices, files and camera go to that client only. It is handed to every part of the explorer that builds a
control: a callback's work runs through
:meth:`Page.guarded` (a :class:`~wheelrail.core.errors.WheelrailError` becomes a notice in the page's words, any
other error is logged and the page keeps serving); :meth:`Page.quietly` marks controls set by the page itself, so
that their callbacks do not act as if a user had chosen; :meth:`Page.send` downloads a file to the page;
:meth:`Page.add_upload` builds an upload button whose bytes go to a reader; the page's 3D view gets the top view
fitted to its size (:meth:`Page.fit_camera`).
"""

from __future__ import annotations

import contextlib
import logging
import threading

import numpy as np
import viser

from wheelrail.core.errors import WheelrailError
from wheelrail.explorer.config import page_message
from wheelrail.explorer.scene import oblique_view, top_view
from wheelrail.explorer.uploads import MAX_UPLOAD_BYTES, refuse_large_uploads_early

__all__ = ["ASPECT_CHANGE", "NOTICE_SECONDS", "Page"]

LOG = logging.getLogger("wheelrail.explorer")
ASPECT_CHANGE = 0.02  # the 3D view is fitted again when its width / height changes by more than this share
NOTICE_SECONDS = 10.0  # a notice (error toast) closes by itself after this; a new one replaces it


class Page:
    """What every control of one browser tab shares: its client (its GUI, 3D view and camera), the status line,
    notices, guarded callbacks."""

    def __init__(
        self, server: viser.ViserServer, client: viser.ClientHandle, max_upload_bytes: int = MAX_UPLOAD_BYTES
    ) -> None:
        self.server, self.client = server, client
        self.gui = client.gui  # the controls of this tab alone
        self.max_upload_bytes = int(max_upload_bytes)
        self.status_md = None  # the status line, once the run form has placed it (add_status)
        self.last_error: str | None = None
        self.last_download: tuple[str, int] | None = None
        self.notices: dict[int, object] = {}  # client id -> its notice on screen
        self.notice_seconds = NOTICE_SECONDS
        self._local = threading.local()  # .quiet: this thread is setting a control (its callback is not a user's)
        refuse_large_uploads_early(client, lambda: self.max_upload_bytes, self.report_error)
        self.fit_camera(client)

    def atomic(self):
        """A block whose updates this tab applies together."""
        return self.client.atomic()

    # ------------------------------------------------------------------ status and notices
    def add_status(self) -> None:
        """The status line, here in the page."""
        self.status_md = self.gui.add_markdown("")

    def status(self, text: str) -> None:
        self.status_md.content = text

    def guarded(self, function, *args, client=None):
        """Run a callback's work; a WheelrailError (bad input) becomes a message in the page."""
        try:
            return function(*args)
        except WheelrailError as error:
            self.report_error(page_message(error), client)
        except Exception as error:  # keep serving after anything
            LOG.exception("callback failed")
            self.report_error(f"unexpected error: {type(error).__name__}: {error}", client)
        return None

    def report_error(self, message: str, client=None, title: str = "Cannot do that") -> None:
        self.last_error = message
        LOG.warning("error shown in the page: %s", message)
        self.status(f"**Error:** {message}")
        self.notify(title, message, client, colour="red")

    def notify(self, title: str, message: str, client=None, *, colour: str) -> None:
        """One notice on the page, replacing the one before; it closes by itself after ``notice_seconds``."""
        for target in [self.client if client is None else client]:
            try:
                old = self.notices.pop(target.client_id, None)
                if old is not None:
                    old.remove()
                self.notices[target.client_id] = target.add_notification(
                    title, message, color=colour, auto_close_seconds=self.notice_seconds
                )
            except Exception:  # a tab that closed meanwhile
                pass

    # ------------------------------------------------------------------ controls set by the page itself
    @contextlib.contextmanager
    def quietly(self):
        """A block in which this thread sets controls without their callbacks acting (not a user's choice)."""
        before = self.is_quiet()
        self._local.quiet = True
        try:
            yield
        finally:
            self._local.quiet = before

    def is_quiet(self) -> bool:
        return getattr(self._local, "quiet", False)

    # ------------------------------------------------------------------ files
    def send(self, name: str, content: bytes, client) -> tuple[str, bytes]:
        """Download ``content`` as ``name`` to the page (``client``: the event's, which is the page's)."""
        self.last_download = (name, len(content))
        target = client if client is not None else self.client
        target.send_file_download(name, content, save_immediately=True)
        return name, content

    def add_upload(self, label: str, hint: str, read) -> viser.GuiUploadButtonHandle:
        """An upload button whose file goes to ``read(name, content, client)``; a refused file is said in a notice
        titled "File not loaded"."""
        button = self.gui.add_upload_button(label, icon=viser.Icon.UPLOAD, hint=hint)
        button.on_upload(lambda event: self.upload(event, read))
        return button

    def upload(self, event, read) -> None:
        """An upload button's event: its file to ``read(name, content, client)``, a refusal in a notice."""
        file = event.target.value
        try:
            read(file.name, file.content, event.client)
        except WheelrailError as error:
            self.report_error(page_message(error), event.client, title="File not loaded")
        except Exception as error:  # keep serving after anything
            LOG.exception("upload failed")
            self.report_error(f"unexpected error: {type(error).__name__}: {error}", event.client)

    # ------------------------------------------------------------------ the 3D view's camera
    def set_view(self, which: str, client=None) -> None:
        """Top view (the default) or an oblique view of the page, fitted to its 3D view."""
        clients = [self.client if client is None else client]
        for target in clients:
            camera = target.camera
            aspect = camera.image_width / camera.image_height if camera.image_height > 0 else None
            view = (top_view if which == "Top view" else oblique_view)(*(() if aspect is None else (aspect,)))
            with target.atomic():
                camera.up_direction = view["up"]
                camera.position, camera.look_at = view["position"], view["look_at"]

    def fit_camera(self, client) -> None:
        """The page's camera: once it reports the size of its 3D view, the top view is fitted to it, and fitted again
        while the view changes size (the panels dock after the first report, so a first fit may be for the whole
        window) until the user moves the camera."""
        lock = threading.Lock()
        fit = {"aspect": None, "ours": []}  # the aspect fitted and the camera positions the page was given

        def report(camera) -> None:
            if camera.image_height <= 0:
                return
            aspect = camera.image_width / camera.image_height
            position = np.asarray(camera.position, dtype=float)
            with lock:
                if fit["aspect"] is not None:
                    if fit["ours"] is None:  # the user's camera now
                        return
                    if not any(np.allclose(position, p, rtol=1e-3, atol=1e-3) for p in fit["ours"]):
                        fit["ours"] = None  # moved by the user: never fitted again
                        return
                    if abs(aspect / fit["aspect"] - 1.0) < ASPECT_CHANGE:
                        return
                else:
                    fit["ours"].append(position)  # the page's own start
                fit["aspect"] = aspect
                self.guarded(self.set_view, "Top view", client, client=client)
                fit["ours"].append(np.asarray(client.camera.position, dtype=float))

        client.camera.on_update(report)
