"""The SHA-256 digest a finished recording carries in its parameters document, checked when it is read back.

Rerun's ``.rrd`` format has no checksum of its own (``rerun rrd verify`` checks that a file decodes, not that its
values are the ones written), so a flipped byte in a stored value reads back as another value. The sink hashes
every series the reader reads back as it sends them, in step order: the times (whole nanoseconds), each scalar
series of ``STEP_FIELDS`` (float64; a step left out because its value is not finite counts as NaN, as it reads
back) and the pressure maps (float32); the digest of these and of the final parameters document (without the
digest) is written into that document under :data:`DIGEST_KEY`. The reader computes the same from what it
decoded and refuses the file when they differ.
"""

from __future__ import annotations

import hashlib

import numpy as np

from wheelrail.core.files.jsonready import strict_json
from wheelrail.core.recording.schema import STEP_FIELDS

__all__ = ["DIGEST_KEY", "RecordingDigest"]

DIGEST_KEY = "digest_sha256"
PARTS = ("time_ns", *(field.name for field in STEP_FIELDS), "pressure")


class RecordingDigest:
    """Running SHA-256 of each series of a recording (module docstring), fed block by block in step order."""

    def __init__(self) -> None:
        self._parts = {name: hashlib.sha256() for name in PARTS}

    def add(self, name: str, values) -> None:
        """Add the next values of series ``name``: ``time_ns`` (int64 ns), a ``STEP_FIELDS`` name (float64, SI) or
        ``pressure`` (maps, float32, Pa)."""
        if name == "time_ns":
            data = np.ascontiguousarray(values, dtype=np.int64)
        elif name == "pressure":
            data = np.ascontiguousarray(values, dtype=np.float32)
        else:
            values = np.asarray(values, dtype=np.float64)
            data = np.ascontiguousarray(np.where(np.isfinite(values), values, np.nan))
        self._parts[name].update(data.tobytes())

    def seal(self, document: dict) -> str:
        """The digest (hex) of the series added and of ``document`` (the parameters, without the digest)."""
        digest = hashlib.sha256(strict_json({key: v for key, v in document.items() if key != DIGEST_KEY}).encode())
        for name in PARTS:
            digest.update(f"|{name}|{self._parts[name].hexdigest()}".encode())
        return digest.hexdigest()
