"""Convergence of the contact force in the track's discretisation across the sleeper bay.

The moving Green's functions are computed at ``positions_per_bay`` excitation positions on an FE mesh of
``elements_per_bay`` elements and read in between at ``rows_per_position`` rows per position
(``wheelrail.core.track.bay_rows``). This script runs the ``hertz`` model on the default 70-bay track (its Green's
functions' FE model has 71: ``stationary.model_bays``) for each discretisation and prints

- on a smooth rail: the amplitudes (N) of the force at the sleeper-passing harmonics k v / L_S (the
  parametric excitation of the discrete supports) and its peak-to-peak;
- on a rough rail (``corrugated-rail``, lines -3..3, levels averaged over the lines as in the paper): the
  third-octave force levels (dB re 1 N, ``spectra.force.force_spectrum``) from 100 Hz to 2 kHz, and their change
  against the next finer discretisation (the largest absolute change per band is the convergence figure).

Run (each configuration is a one-off precompute of its own; a private cache directory is used unless
``--cache`` is given):

    python3 validation/bay_convergence.py --configs default doubled --speeds 100 200
    python3 validation/bay_convergence.py --configs default positions_per_bay=64,refined_elements_per_bay=64
    python3 validation/bay_convergence.py --configs default rows_per_position=8 --speeds 50 300
    python3 validation/bay_convergence.py --configs default doubled --speeds 100 --pad-width-mm 150

A configuration is ``default`` (``TrackNumerics()``), ``doubled`` (every per-bay resolution of the default
doubled: positions, elements in and outside the refined bays, refined bays, near field, rows) or
comma-separated ``TrackNumerics`` fields, e.g. ``positions_per_bay=64``. ``--pad-width-mm`` and
``--rail-loss-factor`` run another track than the paper's (pads of a width, a damped rail).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

import numpy as np
from sleeper_harmonics import harmonics, whole_bays  # validation/sleeper_harmonics.py

HARMONICS = (1, 2, 4, 8, 10, 12, 15, 17, 22, 29, 30, 40, 47, 64, 128)


def _parse(config: str):
    """``default`` or comma-separated TrackNumerics fields, e.g. ``positions_per_bay=64,rows_per_position=8``."""
    from dataclasses import fields, replace

    from wheelrail.core.parameters import TrackNumerics

    numerics = TrackNumerics()  # the default reach (400 km/h): the default's cache entry is the one runs use
    if config == "default":
        return numerics
    if config == "doubled":  # every per-bay resolution of the default doubled
        return replace(numerics, **{name: 2 * getattr(numerics, name) for name in DOUBLED})
    types = {f.name: f.type for f in fields(TrackNumerics)}
    changes = {}
    for item in config.split(","):
        name, value = item.split("=")
        changes[name] = float(value) if types[name] in (float, "float") else int(value)
    return replace(numerics, **changes)


DOUBLED = (
    "positions_per_bay",
    "refined_elements_per_bay",
    "elements_per_bay",
    "refined_bays",
    "near_field",
    "rows_per_position",
)


def _track():
    """The track of ``--pad-width-mm`` and ``--rail-loss-factor`` (default the paper's)."""
    from wheelrail.core.parameters import RailParameters, SupportParameters, TrackParameters

    return TrackParameters(
        rail=RailParameters(loss_factor=ARGS.rail_loss_factor),
        support=SupportParameters(pad_width=ARGS.pad_width_mm * 1e-3),
    )


def _levels(numerics, kmh: float):
    from wheelrail.core.engine import simulate
    from wheelrail.core.parameters import ModelParameters, RunParameters
    from wheelrail.core.roughness import RoughnessSet
    from wheelrail.core.spectra.force import FORCE_SKIP, force_spectrum

    params = ModelParameters(track=_track(), run=RunParameters(speed=kmh / 3.6))
    smooth = simulate(
        RoughnessSet.smooth(ARGS.length), model="hertz", params=params, track_numerics=numerics, keep_pressure=False
    )
    spacing = params.track.support.sleeper_spacing
    amps = harmonics(smooth, spacing, HARMONICS, skip=FORCE_SKIP)  # after the first 0.02 s
    ptp = float(np.ptp(whole_bays(smooth, spacing, skip=FORCE_SKIP)[0]))
    per_line = []
    for line in range(-3, 4):
        result = simulate(
            "corrugated-rail",
            model="hertz",
            line=line,
            params=params,
            length=ARGS.length,
            track_numerics=numerics,
            keep_pressure=False,
        )
        centres, levels = force_spectrum(result, band_range=(100.0, 2000.0))
        per_line.append(10 ** (levels / 10))
    return centres, 10 * np.log10(np.mean(per_line, axis=0)), amps, ptp


def main() -> None:
    global ARGS
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--configs", nargs="+", default=["default", "doubled"])
    parser.add_argument("--speeds", nargs="+", type=float, default=[100.0, 200.0], help="km/h")
    parser.add_argument("--length", type=float, default=7.0, help="run length, m")
    parser.add_argument("--cache", action="store_true", help="use the user cache instead of a private one")
    parser.add_argument("--pad-width-mm", type=float, default=0.0, help="pad width (default 0: point supports)")
    parser.add_argument("--rail-loss-factor", type=float, default=0.0, help="rail loss factor (default 0)")
    ARGS = parser.parse_args()
    if not ARGS.cache:
        os.environ["WHEELRAIL_CACHE_DIR"] = tempfile.mkdtemp(prefix="wheelrail-bay-")
    from wheelrail.core import track

    table = {}
    for config in ARGS.configs:
        numerics = _parse(config)
        start = time.perf_counter()
        track.stationary_track_response(_track(), numerics)
        build = time.perf_counter() - start
        for kmh in ARGS.speeds:
            table[config, kmh] = _levels(numerics, kmh)
        reach = f"{_track().n_bays} bays, up to {numerics.max_speed * 3.6:g} km/h"
        print(f"# {config}: precompute {build:.1f} s ({reach})", flush=True)
        track.clear_memory()
    for kmh in ARGS.speeds:
        print(f"\n## {kmh:g} km/h, smooth rail: force amplitude at k v/L_S (N), k = {HARMONICS}; peak-to-peak (N)")
        for config in ARGS.configs:
            amps, ptp = table[config, kmh][2:]
            print(" ".join(f"{a:7.1f}" for a in amps) + f"   p-p {ptp:7.1f}  ({config})")
        centres = table[ARGS.configs[0], kmh][0]
        print(f"\n## {kmh:g} km/h, corrugated-rail lines -3..3: force level (dB re 1 N) per band")
        print(f"{'Hz':>10} " + " ".join(f"{c:6.0f}" for c in centres))
        for config in ARGS.configs:
            print(f"{'':>10} " + " ".join(f"{v:6.2f}" for v in table[config, kmh][1]) + f"  ({config})")
        first = ARGS.configs[0]
        for other in ARGS.configs[1:]:
            diff = table[other, kmh][1] - table[first, kmh][1]
            print(
                f"{'minus ' + first + ':':>10} "
                + " ".join(f"{v:6.2f}" for v in diff)
                + f"   max |d| = {np.max(np.abs(diff)):.2f} dB  ({other})"
            )
    sys.stdout.flush()


ARGS = None

if __name__ == "__main__":
    main()
