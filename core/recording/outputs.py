"""Where a recording goes: a ``.rrd`` file (written under a temporary name, renamed when complete), a
spawned rerun viewer and/or a running viewer reached over gRPC. Paths and addresses are checked before a
run starts, so a bad one never wastes a run.

The temporary file is ``.<name>.<host>-<pid>-<random>.partial`` beside the target. A writer killed outright
(``kill -9``, a power cut) cannot remove its own; the next recording into that folder removes such files
whose host is this one and whose process no longer runs (:func:`remove_stale_partials`), and never a file
named otherwise, written on another host, or of a process still running.

A file that cannot be written (a full disk) fails the recording, not the run's other files' checks: rerun's
file writer stops, and :meth:`Outputs.file_failure` finds why by writing where it wrote ("no space left on
device writing r.rrd"); the partial file is removed and no viewer is blamed. Inside an
:func:`~wheelrail.core.files.atomic.all_or_none` block the completed file is renamed with the block's other files.
"""

from __future__ import annotations

import contextlib
import os
import re
import secrets
import shutil
import socket
import sys
import tempfile
import uuid
import weakref
from pathlib import Path
from urllib.parse import urlsplit

from wheelrail.core.errors import Blame, WheelrailError
from wheelrail.core.files.atomic import stage, write_failed
from wheelrail.core.recording.schema import APPLICATION_ID, default_blueprint, rerun_module

__all__ = ["Outputs", "ViewerUnreachable", "check_recording_path", "check_viewer", "grpc_url", "viewer_executable"]

_PROBE_BYTES = 1 << 20  # written where a stopped file writer wrote, to learn why it stopped


class ViewerUnreachable(WheelrailError):
    """A rerun viewer the recording streamed to could not be reached at the end (the file, if any, is written)."""


DEFAULT_VIEWER_PORT = 9876  # rerun's default gRPC port
VIEWER_CHECK_TIMEOUT_S = 2.0  # a viewer on this host or a LAN answers a TCP connect well within this


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
                "not a viewer address; use HOST:PORT or a rerun+http://HOST:PORT/proxy URL", Blame("connect", address)
            )
        return address
    host, _, port = address.rpartition(":")
    if not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise WheelrailError("not a viewer address; use HOST:PORT (e.g. 127.0.0.1:9876)", Blame("connect", address))
    return f"rerun+http://{host}:{int(port)}/proxy"


def _listening(host: str, port: int) -> str:
    """'' when something accepts a TCP connection at ``host:port``, else why not (a plain socket: no rerun log)."""
    try:
        with socket.create_connection((host, port), timeout=VIEWER_CHECK_TIMEOUT_S):
            return ""
    except OSError as error:
        return error.strerror or str(error) or type(error).__name__


def check_viewer(url: str, address: str) -> None:
    """Check, before a run starts, that a viewer listens at ``url`` (:func:`grpc_url` of ``address``).

    A TCP connection with a short timeout (:data:`VIEWER_CHECK_TIMEOUT_S`), not rerun's client, which would
    retry for many seconds and log over the terminal before giving up at the end of the run.

    Raises
    ------
    WheelrailError
        One line naming ``address`` (parameter ``connect``) and the reason.
    """
    parts = urlsplit(url)
    default = 443 if parts.scheme == "rerun+https" else DEFAULT_VIEWER_PORT
    try:
        host, port = parts.hostname or "127.0.0.1", parts.port or default
    except ValueError:
        raise WheelrailError("not a viewer address", Blame("connect", address)) from None
    problem = _listening(host, port)
    if problem:
        raise WheelrailError(
            f"no rerun viewer answers there ({problem.lower()}); start one (`rerun`) first, or record to a "
            ".rrd file and open it later",
            Blame("connect", address),
        )


def viewer_executable() -> Path:
    """The rerun viewer to spawn: the ``rerun`` installed with rerun-sdk beside the running Python (its bin
    or Scripts folder, found whether or not that folder is on PATH), else ``rerun`` on PATH."""
    name = "rerun.exe" if sys.platform == "win32" else "rerun"
    beside = Path(sys.executable).parent / name
    if beside.is_file():
        return beside
    on_path = shutil.which("rerun")
    if on_path is not None:
        return Path(on_path)
    raise WheelrailError(
        f"the rerun viewer executable is missing: no {name} in {beside.parent} (where rerun-sdk installs it "
        "beside this Python) nor on PATH; reinstall rerun-sdk in this environment, or record to a .rrd file instead",
        Blame("spawn"),
    )


def _check_desktop() -> None:
    """A spawned viewer opens a window: on Linux and BSD it needs an X11 or Wayland session."""
    if sys.platform.startswith(("linux", "freebsd", "openbsd", "netbsd")) and not any(
        os.environ.get(name) for name in ("DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET")
    ):
        raise WheelrailError(
            "no desktop for the viewer's window (neither DISPLAY nor WAYLAND_DISPLAY is set); record to a "
            ".rrd file and open it with `rerun FILE.rrd` where there is one, or connect to a running viewer",
            Blame("spawn"),
        )


@contextlib.contextmanager
def _quiet_stderr():
    """Standard error (file descriptor 2) to the null device meanwhile: rerun's own log lines while it waits for
    a spawned viewer, and the viewer's (which inherits it), stay off the terminal; the outcome is one line."""
    sys.stderr.flush()
    saved = os.dup(2)
    try:
        with open(os.devnull, "wb") as null:
            os.dup2(null.fileno(), 2)
        yield
    finally:
        sys.stderr.flush()
        os.dup2(saved, 2)
        os.close(saved)


def _spawn_viewer(stream) -> None:
    """Start a viewer listening at :data:`DEFAULT_VIEWER_PORT` (or use the one already there), checked first."""
    if _listening("127.0.0.1", DEFAULT_VIEWER_PORT):  # no viewer open yet: one must be started
        _check_desktop()
        executable = viewer_executable()
        try:
            from rerun.sinks import spawn  # noqa: PLC0415 - rerun is imported only when recording

            with _quiet_stderr():
                spawn(port=DEFAULT_VIEWER_PORT, connect=False, executable_path=str(executable), recording=stream)
        except Exception as error:  # noqa: BLE001 - rerun raises several types; report one line
            first = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
            raise WheelrailError(f"could not start the rerun viewer {executable}: {first}", Blame("spawn")) from None
    problem = _listening("127.0.0.1", DEFAULT_VIEWER_PORT)
    if problem:
        raise WheelrailError(
            f"the rerun viewer did not open its port {DEFAULT_VIEWER_PORT} ({problem.lower()}); record to a "
            ".rrd file and open it with `rerun FILE.rrd` instead",
            Blame("spawn"),
        )


def _remove(path: Path) -> None:
    path.unlink(missing_ok=True)


def _host() -> str:
    """This host's name as it goes into a partial file's name (letters, digits, '.', '_' and '-' only)."""
    return re.sub(r"[^A-Za-z0-9._-]", "_", socket.gethostname()) or "host"


def partial_beside(path: Path) -> Path:
    """Create the empty hidden ``.partial`` file of a recording to ``path``, named after this host and
    process (module docstring)."""
    for _ in range(100):
        temporary = path.parent / f".{path.name}.{_host()}-{os.getpid()}-{secrets.token_hex(4)}.partial"
        try:
            fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        except FileExistsError:
            continue
        os.close(fd)
        return temporary
    raise FileExistsError(f"no free temporary name beside {path}")


def _running(pid: int) -> bool:
    """Whether a process ``pid`` runs on this host (one we may not signal still runs)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def remove_stale_partials(folder: Path) -> list[Path]:
    """Remove the ``.partial`` recordings in ``folder`` left by killed writers of this host: named
    ``.<name>.rrd.<this host>-<pid>-<8 hex>.partial`` with no process ``pid`` running. Returns them."""
    pattern = re.compile(rf"\..+\.rrd\.{re.escape(_host())}-([0-9]+)-[0-9a-f]{{8}}\.partial")
    removed = []
    try:
        entries = list(folder.iterdir())
    except OSError:
        return removed
    for entry in entries:
        match = pattern.fullmatch(entry.name)
        if match is None or int(match.group(1)) == os.getpid() or _running(int(match.group(1))):
            continue
        try:
            if entry.is_file() and not entry.is_symlink():
                entry.unlink()
                removed.append(entry)
        except OSError:
            pass  # another process removed it first, or the folder is read-only: nothing to do
    return removed


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
    blueprint : rerun.blueprint.Blueprint, optional
        The layout the viewer opens with (default: :func:`~.schema.default_blueprint`).
    """

    def __init__(
        self, *, rrd=None, spawn: bool = False, connect: str | None = None, description: str = "", blueprint=None
    ) -> None:
        if rrd is None and not spawn and connect is None:
            raise WheelrailError("a recording needs a .rrd file, a viewer to spawn or an address to connect to")
        self.path = None if rrd is None else check_recording_path(rrd)
        url = None if connect is None else grpc_url(connect)
        if url is not None:
            check_viewer(url, connect)
        rr = rerun_module()
        self.recording_id = str(uuid.uuid4())
        self.stream = rr.RecordingStream(APPLICATION_ID, recording_id=self.recording_id)
        sinks = []
        self._temporary = None
        if self.path is not None:
            remove_stale_partials(self.path.parent)
            self._temporary = partial_beside(self.path)
            # dropped without close() or discard() (e.g. the run raised): no partial file is left behind
            self._finalizer = weakref.finalize(self, _remove, self._temporary)
            sinks.append(rr.FileSink(str(self._temporary)))
        self.spawned = bool(spawn)
        self.viewers = bool(spawn) or url is not None
        if spawn:
            try:
                _spawn_viewer(self.stream)
            except WheelrailError:
                self.discard()
                raise
            spawned = f"rerun+http://127.0.0.1:{DEFAULT_VIEWER_PORT}/proxy"
            if spawned != url:
                sinks.append(rr.GrpcSink(spawned))
        if url is not None:
            try:
                sinks.append(rr.GrpcSink(url))
            except Exception as error:  # noqa: BLE001
                self.discard()
                raise WheelrailError(str(error), Blame("connect", connect)) from None
        try:
            self.stream.set_sinks(*sinks, default_blueprint=default_blueprint() if blueprint is None else blueprint)
        except RuntimeError as error:  # the file's first bytes could not be written (e.g. a full disk)
            failure = self.file_failure(str(error)) or WheelrailError(
                f"could not start the recording: {str(error).splitlines()[0] if str(error) else 'rerun failed'}"
            )
            with _quiet_stderr(), contextlib.suppress(Exception):  # rerun's line about the data it drops
                self.stream.disconnect()
            self.discard()
            raise failure from None
        if description:
            self.stream.send_recording_name(description)

    def disconnect(self) -> str:
        """Flush and close every sink; returns why a viewer could not be reached ('' if all went out)."""
        problem = ""
        with _quiet_stderr():  # rerun's log lines about a lost viewer: the caller says it in one line
            try:
                self.stream.flush()
            except RuntimeError as error:  # rerun gives up on an unreachable viewer after ~7 s
                problem = str(error).splitlines()[0] if str(error) else type(error).__name__
            finally:
                self.stream.disconnect()  # drops the file sink: the file is completed (footer) and closed
        return problem

    def file_failure(self, problem: str) -> WheelrailError | None:
        """The error of a file sink that stopped (``problem``: what rerun said, '' if nothing), or None when the
        file was written. rerun names a file writer that stopped, and with no viewer any problem is the file's;
        why it stopped is found by writing where it wrote (a full disk: "no space left on device writing r.rrd")."""
        if self._temporary is None or not problem:
            return None
        if self.viewers and "file" not in problem.lower():
            return None  # a viewer's problem: the file is complete
        try:
            with open(self._temporary, "ab") as handle:
                handle.write(bytes(_PROBE_BYTES))
                handle.flush()
                os.fsync(handle.fileno())
        except OSError as error:
            return write_failed(error, self.path)
        first = problem.splitlines()[0]
        return WheelrailError(f"could not complete the recording {self.path}: rerun's file writer stopped ({first})")

    def publish(self) -> None:
        """Rename the completed temporary file to the final path (after :meth:`disconnect`); inside an
        :func:`~wheelrail.core.files.atomic.all_or_none` block, with its other files at its end."""
        if self._temporary is not None:
            self._finalizer.detach()
            stage(self._temporary, self.path)
            self._temporary = None

    def discard(self) -> None:
        """Delete the partial file (after a failure)."""
        if self._temporary is not None:
            self._temporary.unlink(missing_ok=True)
            self._temporary = None
