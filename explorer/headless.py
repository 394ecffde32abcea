"""A tab of the explorer without a browser, for scripts and tests: :class:`HeadlessTab` connects to the explorer's
server as a browser tab does, so that the explorer builds it a session of its own (driven from Python through its
controls), and reads what the server sends it until closed."""

from __future__ import annotations

import threading

__all__ = ["HeadlessTab"]


class HeadlessTab:
    """A browser tab without a browser: a websocket client of the explorer's server that reports a camera (viser
    counts a client as connected from its first camera message, and then builds its session) and reads every
    message sent to it until closed."""

    def __init__(self, port: int, host: str = "127.0.0.1") -> None:
        import msgspec
        import viser
        from viser import _messages
        from websockets.sync.client import connect

        self._socket = connect(
            f"ws://{host}:{port}", subprotocols=[f"viser-v{viser.__version__}"], max_size=None, open_timeout=60
        )
        camera = _messages.ViewerCameraMessage(
            wxyz=(1.0, 0.0, 0.0, 0.0),
            position=(0.0, 0.0, 1.0),
            fov=0.7,
            near=0.01,
            far=100.0,
            image_height=600,
            image_width=800,
            look_at=(0.0, 0.0, 0.0),
            up_direction=(0.0, 0.0, 1.0),
        )
        self._socket.send(msgspec.msgpack.encode(camera.as_serializable_dict()))
        self._reader = threading.Thread(target=self._read, daemon=True, name="headless-tab")
        self._reader.start()

    def _read(self) -> None:
        try:
            for _ in self._socket:
                pass
        except Exception:  # the connection closed (or broke): nothing more to read
            return

    def close(self) -> None:
        """Disconnect, as a closed browser tab does (the explorer closes its session)."""
        self._socket.close()
        self._reader.join()
