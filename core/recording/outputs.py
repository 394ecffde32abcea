"""Where a recording goes: a ``.rrd`` file (written under a temporary name, renamed when complete), a
spawned rerun viewer and/or a running viewer reached over gRPC. Paths and addresses are checked before a
run starts, so a bad one never wastes a run.
"""

from __future__ import annotations

import os
import tempfile
import uuid
import weakref
from pathlib import Path

from wheelrail.core.atomic import publish, temporary_beside
from wheelrail.core.errors import WheelrailError
from wheelrail.core.recording.schema import APPLICATION_ID, _rr, default_blueprint

__all__ = ["Outputs", "check_recording_path", "grpc_url"]

DEFAULT_VIEWER_PORT = 9876  # rerun's default gRPC port


def check_recording_path(path: str | os.PathLike) -> Path:
    """Check, before a run starts, that a ``.rrd`` recording can be written at ``path``.

    The folder must exist and accept a new file (probed by creating and removing a temporary file, which
    also catches read-only file systems and permissions that ``os.access`` misjudges for root); the path
    must end in ``.rrd`` and must not be a folder. An existing file is replaced at the end of the run.

    Returns
    -------
    pathlib.Path
        The path, unchanged.

    Raises
    ------
    WheelrailError
        One line naming the path and the reason.
    """
    target = Path(path)
    if target.suffix.lower() != ".rrd":
        raise WheelrailError(f"recording file {str(target)!r} must end in .rrd")
    if target.is_dir():
        raise WheelrailError(f"cannot write recording {target}: it is a folder")
    folder = target.parent
    if not folder.is_dir():
        raise WheelrailError(f"cannot write recording {target}: folder {folder} does not exist")
    try:
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".wheelrail-probe-", suffix=".tmp"):
            pass
    except OSError as error:
        reason = error.strerror or type(error).__name__
        raise WheelrailError(f"cannot write recording {target}: folder {folder} is not writable ({reason})") from None
    return target


def grpc_url(address: str) -> str:
    """``HOST:PORT`` or a ``rerun+http(s)://`` / ``rerun://`` URL -> the viewer's proxy URL."""
    address = address.strip()
    if "://" in address:
        if not address.startswith(("rerun://", "rerun+http://", "rerun+https://")):
            raise WheelrailError(
                "not a viewer address; use HOST:PORT or a rerun+http://HOST:PORT/proxy URL",
                parameter="connect",
                value=address,
            )
        return address
    host, _, port = address.rpartition(":")
    if not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise WheelrailError(
            "not a viewer address; use HOST:PORT (e.g. 127.0.0.1:9876)", parameter="connect", value=address
        )
    return f"rerun+http://{host}:{int(port)}/proxy"


def _remove(path: Path) -> None:
    path.unlink(missing_ok=True)


class Outputs:
    """One rerun recording stream and the places it goes (file, spawned viewer, connected viewer).

    Parameters
    ----------
    rrd : str or path, optional
        ``.rrd`` file; written as a hidden ``.partial`` file beside it and renamed by :meth:`close`.
    spawn : bool
        Start a rerun viewer (``rerun`` executable of rerun-sdk) and stream to it.
    connect : str, optional
        Address of a running viewer, ``HOST:PORT`` or a ``rerun+http://HOST:PORT/proxy`` URL.
    description : str
        Name of the recording shown by the viewer.
    """

    def __init__(self, *, rrd=None, spawn: bool = False, connect: str | None = None, description: str = "") -> None:
        if rrd is None and not spawn and connect is None:
            raise WheelrailError("a recording needs a .rrd file, a viewer to spawn or an address to connect to")
        self.path = None if rrd is None else check_recording_path(rrd)
        url = None if connect is None else grpc_url(connect)
        rr = _rr()
        self.recording_id = str(uuid.uuid4())
        self.stream = rr.RecordingStream(APPLICATION_ID, recording_id=self.recording_id)
        sinks = []
        self._temporary = None
        if self.path is not None:
            self._temporary = temporary_beside(self.path, suffix=".partial")
            # dropped without close() or discard() (e.g. the run raised): no partial file is left behind
            self._finalizer = weakref.finalize(self, _remove, self._temporary)
            sinks.append(rr.FileSink(str(self._temporary)))
        self.spawned = bool(spawn)
        if spawn:
            try:
                self.stream.spawn(port=DEFAULT_VIEWER_PORT, connect=False)
            except Exception as error:  # noqa: BLE001 - rerun raises several types; report one line
                self.discard()
                raise WheelrailError(f"could not start the rerun viewer: {error}") from None
            spawned = f"rerun+http://127.0.0.1:{DEFAULT_VIEWER_PORT}/proxy"
            if spawned != url:
                sinks.append(rr.GrpcSink(spawned))
        if url is not None:
            try:
                sinks.append(rr.GrpcSink(url))
            except Exception as error:  # noqa: BLE001
                self.discard()
                raise WheelrailError(str(error), parameter="connect", value=connect) from None
        self.stream.set_sinks(*sinks, default_blueprint=default_blueprint())
        if description:
            self.stream.send_recording_name(description)

    def disconnect(self) -> str:
        """Flush and close every sink; returns why a viewer could not be reached ('' if all went out)."""
        problem = ""
        try:
            self.stream.flush()
        except RuntimeError as error:  # rerun gives up on an unreachable viewer after ~7 s
            problem = str(error).splitlines()[0] if str(error) else type(error).__name__
        finally:
            self.stream.disconnect()  # drops the file sink: the file is completed (footer) and closed
        return problem

    def publish(self) -> None:
        """Rename the completed temporary file to the final path (after :meth:`disconnect`)."""
        if self._temporary is not None:
            self._finalizer.detach()
            publish(self._temporary, self.path)
            self._temporary = None

    def discard(self) -> None:
        """Delete the partial file (after a failure)."""
        if self._temporary is not None:
            self._temporary.unlink(missing_ok=True)
            self._temporary = None
