"""The wheelrail explorer: a viser browser GUI over ``wheelrail.core``, one session per browser tab.

:class:`ExplorerApp` runs the :class:`viser.ViserServer` and gives each client that connects (a browser tab) its own
:class:`~wheelrail.explorer.browser_session.BrowserSession`, built on that client's own GUI and 3D view (viser's
``client.gui`` and ``client.scene``): its own form, run, results and downloads. A run in one tab never changes what
another shows; a tab that closes has its run stopped and its results let go. What the tabs share is what is safe to
share: the tracks' Green's functions (core's cache, on disk), the compiled solver, and which tracks this process has
prepared (:class:`~wheelrail.explorer.controller.Preparation`: one first preparation at a time). :func:`serve`
creates the app and waits.
"""

from __future__ import annotations

import logging
import threading

import viser

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.declared import inputs_of
from wheelrail.core.parameters import ContactParameters
from wheelrail.explorer.browser_session import BrowserSession
from wheelrail.explorer.config import RunConfig, field_text, offered_lines, read_config
from wheelrail.explorer.controller import Preparation, RunController
from wheelrail.explorer.form import DEFAULT_LENGTH, DEFAULT_SET
from wheelrail.explorer.scene import set_initial_camera
from wheelrail.explorer.uploads import MAX_UPLOAD_BYTES

__all__ = ["BrowserSession", "ExplorerApp", "main", "serve"]

LOG = logging.getLogger("wheelrail.explorer")


class ExplorerApp:
    """The explorer's server and its browser sessions (``sessions``: client id -> its session)."""

    def __init__(
        self,
        host: str = "127.0.0.1",
        port: int = 8080,
        *,
        roughness: str = DEFAULT_SET,
        length: float = DEFAULT_LENGTH,
        max_upload_bytes: int = MAX_UPLOAD_BYTES,
        verbose: bool = False,
        warm_up: bool = False,
    ) -> None:
        """``warm_up``: prepare the default configuration's track and solver in the background at once."""
        self.server = viser.ViserServer(host=host, port=port, label="wheelrail explorer", verbose=verbose)
        self.port = self.server.get_port()
        self.preparation = Preparation()  # shared by every tab's runs
        self.sessions: dict[int, BrowserSession] = {}
        self._settings = {"roughness": roughness, "length": length, "max_upload_bytes": max_upload_bytes}
        self._changed = threading.Condition()  # notified when a session opens or closes
        self._gone: set[int] = set()  # clients that disconnected (a session built meanwhile is closed at once)
        self._closed = False
        self._warming: RunConfig | None = None  # the configuration being warmed up, until it is
        self.warmed_up = threading.Event()  # set once the warm-up has prepared its configuration
        self._warm_up = RunController(None, preparation=self.preparation)  # prepares only: it runs nothing
        set_initial_camera(self.server)
        self.server.on_client_connect(self._connect)
        self.server.on_client_disconnect(self._disconnect)
        if warm_up:
            found = _default_config(roughness, length)
            if found is not None:
                self._warming, rough = found
                self._warm_up.warm_up(self._warming, rough, done=self._warmed_up)

    def _warmed_up(self, seconds: float) -> None:
        self._warming = None
        self.warmed_up.set()
        for session in list(self.sessions.values()):
            session.warmed_up(seconds)

    def _connect(self, client: viser.ClientHandle) -> None:
        """A new browser tab: its own session on its own GUI."""
        with self._changed:
            if self._closed:
                return
        session = BrowserSession(self.server, client, preparation=self.preparation, **self._settings)
        with self._changed:
            gone = self._closed or client.client_id in self._gone
            if not gone:
                self.sessions[client.client_id] = session
                self._changed.notify_all()
        if gone:  # the tab closed while its page was being built
            session.close()
            return
        LOG.info("browser tab %d opened (%d open)", client.client_id, len(self.sessions))
        warming = self._warming
        if warming is not None:
            session.warming_up(warming)

    def _disconnect(self, client: viser.ClientHandle) -> None:
        """A browser tab closed: its run stops, its threads end and its results are let go."""
        with self._changed:
            self._gone.add(client.client_id)
            session = self.sessions.get(client.client_id)
        if session is not None:
            session.close()  # listed until closed: wait_for's callers see it gone only once its threads are joined
        with self._changed:
            self.sessions.pop(client.client_id, None)
            self._changed.notify_all()
        if session is not None:
            LOG.info("browser tab %d closed (%d open)", client.client_id, len(self.sessions))

    def wait_for(self, condition, timeout: float | None = None) -> bool:
        """Wait until ``condition()`` holds (checked whenever a session opens or closes); True if it did within
        ``timeout`` s."""
        with self._changed:
            return self._changed.wait_for(condition, timeout)

    def close(self) -> None:
        """Close every session (their runs stopped, their threads joined), end the warm-up, stop the server."""
        with self._changed:
            self._closed = True
            sessions = list(self.sessions.values())
            self.sessions.clear()
            self._changed.notify_all()
        for session in sessions:
            session.close()
        self._warm_up.close()
        self.server.stop()


def _default_config(roughness: str, length: float) -> tuple[RunConfig, object] | None:
    """The configuration a new tab's form starts with (the set, the 3d model on the line nearest 0, the declared
    defaults) and its roughness, for the warm-up; None if it is not a run."""
    from wheelrail.core.roughness import bundled_names, load_roughness

    names = bundled_names()
    name = roughness if roughness in names else names[0]
    rough = load_roughness(name)
    lines = offered_lines(rough, "3d", ContactParameters())
    try:
        config = read_config(
            rough,
            name,
            line=str(min(lines, key=lambda n: (abs(n), n))) if lines else "0",
            model="3d",
            length_m=f"{length:g}",
            **{entry.dest: field_text(entry) for entry in inputs_of()},
        )
    except WheelrailError:
        return None
    return config, rough


def serve(
    host: str = "127.0.0.1", port: int = 8080, *, roughness: str = DEFAULT_SET, length: float = DEFAULT_LENGTH
) -> int:
    """Start the explorer and serve until interrupted (Ctrl-C); runs and errors are logged to the terminal."""
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(name)s: %(message)s", datefmt="%H:%M:%S")
    app = ExplorerApp(host, port, roughness=roughness, length=length, verbose=False, warm_up=True)
    shown = "127.0.0.1" if host in ("0.0.0.0", "") else host
    print(f"wheelrail explorer: http://{shown}:{app.port}  (Ctrl-C to stop)", flush=True)
    try:
        threading.Event().wait()
    except KeyboardInterrupt:
        pass
    finally:
        app.close()
    return 0


main = serve
