"""The noise chain's track part kept in the disk cache: a new process reads it instead of computing it again.

The track part of the TWINS-like chain (:func:`wheelrail.core.noise.track_vibration.track_vibration`: the
lengthened FE track solved at every frequency of the bands for both excitation positions, the rail's radiation in
the wavenumber domain, the transfer along the rail) depends on the track, the contact's stiffness, the chain's
numerics and the components it drives, not on the wheel, the speed or the roughness. A process keeps it in memory
(``twins._track_part``); this module keeps it on disk as well (:mod:`wheelrail.core.files.cache`, kind
``noise-track``), so that every ``wheelrail noise`` and study after the first on a track reads it.

The entry's key holds the track's parameters, the contact stiffness, the numerics, the frequencies (bit for bit),
the driven components' names and the source of the modules the computation runs (the track's vibration, the FE
track, the components, the radiation), so that a change of any of them computes it afresh. A component whose
``response`` is not a plain function of wheelrail's own (a plug-in's, a lambda or a closure: its code or captured
values are not in the key) keeps the part in memory only.
"""

from __future__ import annotations

import functools
import hashlib
import inspect
from dataclasses import asdict

import numpy as np

KIND = "noise-track"
"""The cache entries' kind."""

_SCALARS = ("contact_stiffness", "dx")
_ARRAYS = ("rail", "rail_radiated", "alpha_track", "transfer_sq", "free_sq", "free_distance")


@functools.cache
def _code_digest() -> str:
    """SHA-256 of the modules the track part's computation runs (whole modules: their private helpers too)."""
    from wheelrail.core.noise import components, radiation, track_vibration
    from wheelrail.core.track import fe

    code = "".join(inspect.getsource(module) for module in (track_vibration, fe, components, radiation))
    return hashlib.sha256(code.encode()).hexdigest()


def _storable(driven: tuple) -> bool:
    """Whether every driven component's response is a plain function of wheelrail's own (its code in the key)."""
    return all(
        inspect.isfunction(entry.response)
        and entry.response.__closure__ is None
        and entry.response.__module__.startswith("wheelrail.")
        for entry in driven
    )


def stored_track_part(track, k_hertz: float, numerics, freqs: np.ndarray, driven: tuple, compute) -> dict:
    """The track part of the chain (:func:`~wheelrail.core.noise.track_vibration.track_vibration`) from the disk
    cache, or ``compute()`` and kept there.

    Parameters
    ----------
    track : TrackParameters
        The track.
    k_hertz : float
        The contact's stiffness at the preload, dF/d delta (eq. 12), N/m: alpha_C = 1 / ``k_hertz``.
    numerics : NoiseNumerics
        The chain's numerics.
    freqs : numpy.ndarray
        The frequencies it is solved at, (bands, points), Hz (``twins.band_frequencies``), in the key bit for bit.
    driven : tuple of NoiseComponent
        The track's parts the chain drives (their ``response`` read at every frequency).
    compute : callable
        ``compute()`` -> the part, called where no valid entry is found.

    Returns
    -------
    dict
        The part: ``responses`` (name -> (bands, points, 2)), the arrays of ``_ARRAYS`` and the scalars of
        ``_SCALARS``, equal to the bit to ``compute()``'s.
    """
    from wheelrail.core.files import cache

    if not _storable(driven):
        return compute()
    names = [entry.name for entry in driven]
    key = cache.cache_key(
        KIND,
        {
            "track": asdict(track),
            "contact_stiffness": float(k_hertz),
            "numerics": asdict(numerics),
            "frequencies": hashlib.sha256(np.ascontiguousarray(freqs, dtype=np.float64).tobytes()).hexdigest(),
            "components": names,
            "code": _code_digest(),
        },
    )
    required = (*_ARRAYS, *_SCALARS, *(f"response_{i}" for i in range(len(names))))
    arrays = cache.load_entry(KIND, key, required)
    if arrays is not None and all(np.all(np.isfinite(arrays[name])) for name in required):
        part = {name: arrays[name] for name in _ARRAYS}
        part |= {name: float(arrays[name]) for name in _SCALARS}
        part["responses"] = {name: arrays[f"response_{i}"] for i, name in enumerate(names)}
        return part
    part = compute()
    stored = {name: np.asarray(part[name]) for name in (*_ARRAYS, *_SCALARS)}
    stored |= {f"response_{i}": part["responses"][name] for i, name in enumerate(names)}
    cache.save_entry(KIND, key, stored)
    return part
