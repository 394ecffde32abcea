"""Roughness files uploaded from a browser: read in memory, checked, labelled (the read part has no viser).

The bytes go to a temporary file of our own naming; the browser's file name is only a display label, never a
path. :func:`refuse_large_uploads_early` drops an upload announced larger than the limit before viser buffers
its bytes.
"""

from __future__ import annotations

import re
import tempfile
from collections.abc import Callable
from pathlib import Path

from wheelrail.core.errors import WheelrailError
from wheelrail.core.roughness import RoughnessSet, read_roughness

__all__ = [
    "MAX_UPLOAD_BYTES",
    "UPLOAD_SUFFIXES",
    "read_upload",
    "refuse_large_uploads_early",
    "safe_label",
    "size_text",
]

MAX_UPLOAD_BYTES = 20 * 1024 * 1024  # largest roughness file accepted from a browser
UPLOAD_SUFFIXES = (".csv", ".npz")


def size_text(n_bytes: int) -> str:
    """A file size for people: kB below 1 MB, else MB (binary units)."""
    return f"{n_bytes / 1024:.0f} kB" if n_bytes < 2**20 else f"{n_bytes / 2**20:.3g} MB"


def safe_label(name: str) -> str:
    """A file name from a browser, reduced to a harmless display label (never used as a path)."""
    base = re.split(r"[\\/]", str(name))[-1]
    return re.sub(r"[^A-Za-z0-9._ -]", "_", base)[:60] or "upload"


def read_upload(name: str, content: bytes, max_bytes: int) -> tuple[str, RoughnessSet]:
    """An uploaded roughness file's label ('upload: NAME') and set, or one WheelrailError."""
    if len(content) > max_bytes:
        raise WheelrailError(
            f"upload {safe_label(name)!r} ({size_text(len(content))}) is over the {size_text(max_bytes)} limit"
        )
    suffix = Path(str(name)).suffix.lower()
    if suffix not in UPLOAD_SUFFIXES:
        raise WheelrailError(f"upload {safe_label(name)!r}: expected a .csv or .npz roughness file")
    with tempfile.TemporaryDirectory(prefix="wheelrail-upload-") as folder:
        path = Path(folder) / f"roughness{suffix}"
        path.write_bytes(content)
        # messages name the upload, never the temporary path the user did not see
        rough = read_roughness(path, label=f"upload {safe_label(name)!r}")
    return f"upload: {safe_label(name)}", rough


def refuse_large_uploads_early(client, max_bytes: Callable[[], int], report: Callable[[str, object], None]) -> None:
    """Drop an upload announced larger than ``max_bytes()`` before its bytes are buffered.

    viser 1.1 has no public size limit; its upload state lives in ``GuiApi._current_file_upload_states``,
    and this handler runs after viser's for the same start message. If these private names change, the
    size is still checked when the upload completes (:func:`read_upload`), after viser has buffered it.
    """
    from viser import _messages

    states = getattr(client.gui, "_current_file_upload_states", None)  # the client's own upload buttons'
    websock = getattr(client, "_websock_connection", None)
    if states is None or websock is None or not hasattr(_messages, "FileTransferStartUpload"):
        return

    def refuse(client_id, message) -> None:
        limit = max_bytes()
        if message.size_bytes <= limit:
            return
        states.pop(message.transfer_uuid, None)  # its parts are now ignored by viser
        # tell the page the transfer is over, so that its upload button works again
        websock.queue_message(
            _messages.FileTransferPartAck(
                source_component_uuid=message.source_component_uuid,
                transfer_uuid=message.transfer_uuid,
                transferred_bytes=message.size_bytes,
                total_bytes=message.size_bytes,
            )
        )
        report(
            f"upload {safe_label(message.filename)!r} ({size_text(message.size_bytes)}) is over the "
            f"{size_text(limit)} limit; refused before sending",
            client,
        )

    websock.register_handler(_messages.FileTransferStartUpload, refuse)
