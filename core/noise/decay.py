"""The track's vertical decay rate against the lower limit of the standard for type testing.

The decay rate is EN 15461's, computed on the noise model's lengthened FE track
(:func:`wheelrail.core.noise.twins.track_noise_model`: 240 bays, excitation at midspan). The limit is the lower
limit of the vertical track decay rate of EN ISO 3095:2013 (6.2.6, Figure 3, curve A), to which the TSI Noise
(Regulation (EU) No 1304/2014 as amended by (EU) 2019/774) refers for the reference track of a type test; its
values and their provenance are in ``data/iso3095_vertical_decay_limit.csv``. The limit applies to the bands
250 Hz to 5 kHz.
"""

from __future__ import annotations

import csv
import functools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

LIMIT_FILE = Path(__file__).parent / "data" / "iso3095_vertical_decay_limit.csv"


@dataclass(frozen=True, eq=False)
class DecayLimit:
    """The lower limit of the vertical track decay rate: nominal band centres (Hz), limits (dB/m) and the data
    file's comment header (``source``)."""

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
    comments, rows = [], []
    with LIMIT_FILE.open(encoding="utf-8", newline="") as handle:
        for line in handle:
            if line.startswith("#"):
                comments.append(line[1:].strip())
            elif line.strip():
                rows.append(line)
    _, *body = list(csv.reader(rows))
    values = np.array([[float(cell) for cell in row] for row in body])
    return DecayLimit(frequency_hz=values[:, 0], limit_db_per_m=values[:, 1], source=" ".join(comments))


def decay_against_limit(frequency_hz, decay_rate_db_per_m) -> dict:
    """Decay rates per band beside the limit: the JSON layout of ``wheelrail track`` (key ``decay_rate``).

    Returns
    -------
    dict
        ``frequency_hz``, ``decay_rate_dB_per_m``, ``limit_dB_per_m`` (None where the standard sets none),
        ``below_limit_hz`` (the bands where the decay rate is below the limit), ``meets_limit`` and
        ``limit_source``.
    """
    limit = vertical_decay_limit()
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
        "limit_source": "EN ISO 3095:2013, 6.2.6, Figure 3 curve A (vertical), 250 Hz-5 kHz",
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
    key = cache.cache_key(
        "track-decay",
        {"track": asdict(track), "numerics": asdict(numerics), "code": hashlib.sha256(code.encode()).hexdigest()},
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
