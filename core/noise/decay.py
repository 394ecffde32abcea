"""The track's vertical and lateral decay rates against the lower limits of the standard for type testing.

The decay rates are EN 15461's, computed on the noise model's lengthened FE track
(:func:`wheelrail.core.noise.twins.track_noise_model`: 240 bays, excitation at midspan) and on the lateral track of
the same layout (:mod:`wheelrail.core.track.lateral`). The limits are the lower limits of the vertical and lateral
track decay rates of EN ISO 3095:2013 (6.2.6, Figure 3, curves A and B), to which the TSI Noise (Regulation (EU)
No 1304/2014 as amended by (EU) 2019/774) refers for the reference track of a type test; their values and their
provenance are in ``data/iso3095_vertical_decay_limit.csv`` and ``data/iso3095_lateral_decay_limit.csv``. The
limits apply to the bands 250 Hz to 5 kHz.
"""

from __future__ import annotations

import csv
import functools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

LIMIT_FILE = Path(__file__).parent / "data" / "iso3095_vertical_decay_limit.csv"
LATERAL_LIMIT_FILE = Path(__file__).parent / "data" / "iso3095_lateral_decay_limit.csv"
LIMIT_SOURCES = {
    "vertical": "EN ISO 3095:2013, 6.2.6, Figure 3 curve A (vertical), 250 Hz-5 kHz",
    "lateral": "EN ISO 3095:2013, 6.2.6, Figure 3 curve B (lateral), 250 Hz-5 kHz",
}
"""Each limit's source in a few words, by direction (the JSON's ``limit_source``)."""


@dataclass(frozen=True, eq=False)
class DecayLimit:
    """The lower limit of a track decay rate (vertical or lateral): nominal band centres (Hz), limits (dB/m) and the
    data file's comment header (``source``)."""

    frequency_hz: np.ndarray
    limit_db_per_m: np.ndarray
    source: str

    def at(self, frequency_hz) -> np.ndarray:
        """The limit in the bands of ``frequency_hz`` (exact or nominal centres; NaN where it sets none)."""
        f = np.atleast_1d(np.asarray(frequency_hz, dtype=float))
        out = np.full(f.shape, np.nan)
        for centre, limit in zip(self.frequency_hz, self.limit_db_per_m, strict=True):
            out[np.abs(10 * np.log10(f / centre)) < 0.5] = limit  # the same one-third octave band
        return out


@functools.cache
def vertical_decay_limit() -> DecayLimit:
    """EN ISO 3095:2013's lower limit of the vertical track decay rate, from its data file."""
    return _read_limit(LIMIT_FILE)


@functools.cache
def lateral_decay_limit() -> DecayLimit:
    """EN ISO 3095:2013's lower limit of the lateral track decay rate (Figure 3, curve B), from its data file."""
    return _read_limit(LATERAL_LIMIT_FILE)


def _read_limit(path: Path) -> DecayLimit:
    comments, rows = [], []
    with path.open(encoding="utf-8", newline="") as handle:
        for line in handle:
            if line.startswith("#"):
                comments.append(line[1:].strip())
            elif line.strip():
                rows.append(line)
    _, *body = list(csv.reader(rows))
    values = np.array([[float(cell) for cell in row] for row in body])
    return DecayLimit(frequency_hz=values[:, 0], limit_db_per_m=values[:, 1], source=" ".join(comments))


def decay_against_limit(frequency_hz, decay_rate_db_per_m, direction: str = "vertical") -> dict:
    """Decay rates per band beside the limit of their ``direction`` ("vertical" or "lateral"): the JSON layout of
    ``wheelrail track`` (keys ``decay_rate`` and ``lateral_decay_rate``).

    Returns
    -------
    dict
        ``frequency_hz``, ``decay_rate_dB_per_m``, ``limit_dB_per_m`` (None where the standard sets none),
        ``below_limit_hz`` (the bands where the decay rate is below the limit), ``meets_limit`` and
        ``limit_source``.
    """
    limit = {"vertical": vertical_decay_limit, "lateral": lateral_decay_limit}[direction]()
    f = np.asarray(frequency_hz, dtype=float)
    decay = np.asarray(decay_rate_db_per_m, dtype=float)
    bound = limit.at(f)
    below = np.isfinite(bound) & (decay < bound)
    return {
        "frequency_hz": f,
        "decay_rate_dB_per_m": decay,
        "limit_dB_per_m": [None if np.isnan(b) else float(b) for b in bound],
        "below_limit_hz": [float(x) for x in f[below]],
        "meets_limit": not bool(np.any(below)),
        "limit_source": LIMIT_SOURCES[direction],
    }


def decay_verdict(decay: dict) -> str:
    """The decay rate against the limit in words, for a title or a line of text: "meets EN ISO 3095:2013's lower
    limit in every band 250 Hz-5 kHz" or "is below EN ISO 3095:2013's lower limit at 400, 500 and 630 Hz" (the
    bands by their nominal names); ``decay`` in :func:`decay_against_limit`'s layout."""
    from wheelrail.core.spectra.bands import nominal_band_label

    if decay["meets_limit"]:
        return "meets EN ISO 3095:2013's lower limit in every band 250 Hz-5 kHz"
    names = [nominal_band_label(f) for f in decay["below_limit_hz"]]
    bands = names[0] if len(names) == 1 else f"{', '.join(names[:-1])} and {names[-1]}"
    return f"is below EN ISO 3095:2013's lower limit at {bands} Hz"


def track_decay(track) -> dict:
    """The vertical decay rate per band (EN 15461 on the noise model's 240-bay track) of ``track``
    (``TrackParameters``) beside the EN ISO 3095 limit (:func:`decay_against_limit`'s layout, with
    ``free_wave_decay_dB_per_m`` and ``method``), kept in the disk cache (a few seconds of FE solves); the key
    holds the source of the modules that compute it."""
    import hashlib
    import inspect
    from dataclasses import asdict

    import numpy as np

    from wheelrail.core.files import cache
    from wheelrail.core.noise import twins
    from wheelrail.core.track import fe

    _check_track(track, "track_decay")
    numerics = twins.NoiseNumerics()
    code = inspect.getsource(twins) + inspect.getsource(fe)  # whole modules: their private helpers included
    vertical = {name: value for name, value in asdict(track).items() if name != "lateral"}  # not its inputs
    key = cache.cache_key(
        "track-decay",
        {"track": vertical, "numerics": asdict(numerics), "code": hashlib.sha256(code.encode()).hexdigest()},
    )
    names = ("frequency_hz", "decay_rate", "free_wave_decay")
    arrays = cache.load_entry("track-decay", key, names)
    if arrays is None or not all(np.all(np.isfinite(arrays[name])) for name in names):
        f, decay, free = twins.track_decay_rates(track, numerics)
        arrays = {"frequency_hz": f, "decay_rate": decay, "free_wave_decay": free}
        cache.save_entry("track-decay", key, arrays)
    out = decay_against_limit(arrays["frequency_hz"], arrays["decay_rate"])
    out["free_wave_decay_dB_per_m"] = arrays["free_wave_decay"]
    out["method"] = (
        f"EN 15461 formula on the FE track lengthened to {numerics.track_bays} bays, excited at midspan, "
        f"{numerics.points_per_band} frequencies per band"
    )
    return out


def track_lateral_decay(track) -> dict:
    """The lateral decay rate of the railhead per band (EN 15461 on the lateral track,
    :func:`wheelrail.core.track.lateral.lateral_decay_rate`) of ``track`` (``TrackParameters``) beside the
    EN ISO 3095 lateral limit (:func:`decay_against_limit`'s layout, with ``method``), kept in the disk cache."""
    from wheelrail.core.track.lateral import LateralNumerics

    numerics = LateralNumerics()
    arrays = _lateral_arrays(track, "track_lateral_decay")
    out = decay_against_limit(arrays["frequency_hz"], arrays["decay_rate"], "lateral")
    out["method"] = (
        f"EN 15461 formula on the railhead's lateral response of the lateral track ({numerics.track_bays} bays, "
        f"{numerics.absorbing_bays} absorbing at each end; a lateral force at the railhead at midspan), "
        f"{numerics.points_per_band} frequencies per band"
    )
    return out


def lateral_band_receptances(track) -> dict:
    """The railhead's lateral receptances of ``track`` at midspan at the exact band centres 50 Hz-10 kHz, kept in
    the disk cache with the lateral decay rate: ``frequency_hz``, ``lateral_point_m_per_n`` (|.|, per lateral force
    at the railhead) and ``vertical_to_lateral_m_per_n`` (|.|, per vertical force ``LATERAL_CROSS_OFFSET`` from
    the rail's centreline, :mod:`wheelrail.core.noise.rail_lateral`; proportional to the offset),
    ``contact_offset_m``."""
    from wheelrail.core.noise.rail_lateral import LATERAL_CROSS_OFFSET

    arrays = _lateral_arrays(track, "lateral_band_receptances")
    return {
        "frequency_hz": arrays["frequency_hz"],
        "lateral_point_m_per_n": arrays["lateral_point"],
        "vertical_to_lateral_m_per_n": arrays["vertical_to_lateral"],
        "contact_offset_m": LATERAL_CROSS_OFFSET,
    }


def _lateral_arrays(track, where: str) -> dict:
    """The lateral decay rate and receptances at the band centres (a few seconds of FE solves), from the disk
    cache or computed; the key holds the source of the modules that compute them."""
    import hashlib
    import inspect
    from dataclasses import asdict

    from wheelrail.core.files import cache
    from wheelrail.core.noise.rail_lateral import LATERAL_CROSS_OFFSET
    from wheelrail.core.spectra.bands import noise_bands
    from wheelrail.core.track import fe, lateral

    _check_track(track, where)
    numerics = lateral.LateralNumerics()
    code = inspect.getsource(lateral) + inspect.getsource(fe)
    key = cache.cache_key(
        "track-lateral",
        {
            "track": asdict(track),
            "numerics": asdict(numerics),
            "offset": LATERAL_CROSS_OFFSET,
            "code": hashlib.sha256(code.encode()).hexdigest(),
        },
    )
    names = ("frequency_hz", "decay_rate", "lateral_point", "vertical_to_lateral")
    arrays = cache.load_entry("track-lateral", key, names)
    if arrays is None or not all(np.all(np.isfinite(arrays[name])) for name in names):
        f = noise_bands()
        receptances = lateral.lateral_receptances(track, f, contact_offset=LATERAL_CROSS_OFFSET, numerics=numerics)
        arrays = {
            "frequency_hz": f,
            "decay_rate": lateral.lateral_decay_rate(track, numerics=numerics),
            "lateral_point": np.abs(receptances.lateral_point),
            "vertical_to_lateral": np.abs(receptances.vertical_to_lateral),
        }
        cache.save_entry("track-lateral", key, arrays)
    return arrays


def band_receptances(track, elements_per_bay: int = 16) -> dict:
    """The point receptance magnitudes (m/N) of ``track`` above its central sleeper and at midspan at the exact
    band centres 50 Hz-5 kHz (the decay rate's bands up to the limit's last), on ``elements_per_bay`` elements."""
    import numpy as np

    from wheelrail.core.spectra.bands import noise_bands
    from wheelrail.core.track import assemble_track, track_receptance

    _check_track(track, "band_receptances")
    f = noise_bands()
    f = f[f < 5100]
    L = track.support.sleeper_spacing
    x_sleeper = (track.n_bays // 2) * L
    model = assemble_track(track, elements_per_bay)
    return {
        "frequency_hz": f,
        "above_sleeper_m_per_n": np.abs(track_receptance(model, f, x_sleeper)),
        "midspan_m_per_n": np.abs(track_receptance(model, f, x_sleeper + L / 2)),
    }


def _check_track(track, where: str) -> None:
    from wheelrail.core.errors import WheelrailError
    from wheelrail.core.parameters import TrackParameters

    if not isinstance(track, TrackParameters):
        raise WheelrailError(f"{where}: track must be TrackParameters, got {type(track).__name__}")
