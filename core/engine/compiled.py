"""numba's on-disk cache for compiled code that calls compiled code of other modules.

numba keys a cached function by the file it is defined in only: a change to a function it calls from
another module does not invalidate it, and the stale machine code would run on (numba's documentation,
"Cache invalidation"). It does include the values a function closes over in the key, so a compiled entry
point that calls into other modules is defined inside a factory that passes it :func:`sources_stamp` of
those modules, and names the stamp in its body::

    def _define(stamp):
        @njit(cache=True)
        def entry(...):
            stamp  # noqa: B018 - keys numba's cache on the sources of the modules called
            ...
        return entry

    entry = _define(sources_stamp(other_module))

Functions inlined with ``inline="always"`` are compiled from their source each time the caller is, so only
entry points called from Python and functions called without inlining need this.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

__all__ = ["sources_stamp"]


def sources_stamp(*modules) -> str:
    """SHA-256 of the source files of ``modules`` (module objects), hex."""
    digest = hashlib.sha256()
    for module in modules:
        digest.update(Path(module.__file__).read_bytes())
    return digest.hexdigest()
