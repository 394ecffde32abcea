"""The sleeper-passing harmonics of the contact force with a point support and a wide pad, and their convergence.

On a smooth rail the force on a wheel rolling over discrete supports varies with its place in the bay: the
parametric excitation, at the sleeper-passing harmonics k v / L_S. A pad of width b spreads each support over b
along the rail; to first order in the support's coupling (one scattering of the rail's response at each support)
the variation of the rail's receptance along the bay is the point support's smoothed by the pad's box of width b,
so its k-th harmonic, and the force's, is the point support's times |sinc(k b / L_S)| (sinc(x) = sin(pi x) /
(pi x)): 20-30 dB lower than the point support's for k = 14-20 with a 150 mm pad on 0.65 m sleepers.

This script runs ``hertz`` on a smooth rail (a run starting in the moving load's steady state, so a short record
suffices) for a point support and for pads of a width, at the default track numerics and at refined ones, and
prints the amplitudes of the force (N) at k = 1-20 from the force record (a whole number of bays), the
first-order estimate from the point support's at the same numerics, and each refinement's change. The default
configurations refine one length of the default numerics each (elements outside and inside the refined bays,
positions, rows, near field, integration step); docs/validation.md gives the table and what it converges.

Run (each track and numerics is a one-off precompute; a private cache directory is used unless ``--cache``):

    python3 validation/pad_harmonics.py
    python3 validation/pad_harmonics.py --configs default elements_per_bay=32 --pad-width-mm 0 150

A configuration is ``default`` (``TrackNumerics()``) or comma-separated ``TrackNumerics`` fields, as
``wheelrail run --track-numerics`` takes them (``core.inputs.numerics.parse_track_numerics``).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

import numpy as np
from sleeper_harmonics import harmonics  # validation/sleeper_harmonics.py

HARMONICS = np.arange(1, 21)
DEFAULT_CONFIGS = (
    "default",
    "elements_per_bay=32",
    "refined_elements_per_bay=128",
    "positions_per_bay=128,refined_elements_per_bay=128",
    "rows_per_position=8",
    "near_field_m=0.2",
    "time_step_us=2.5",
)


def first_order_estimate(point: np.ndarray, width: float, sleeper_spacing: float, orders=HARMONICS) -> np.ndarray:
    """The point support's harmonics times |sinc(k b / L_S)|: a pad of width b to first order (module docstring)."""
    return point * np.abs(np.sinc(np.asarray(orders) * width / sleeper_spacing))


def smooth_rail_harmonics(width: float, kmh: float, length: float, numerics) -> np.ndarray:
    """k = 1-20 of a ``hertz`` run on a smooth rail, pads ``width`` m wide (0: point supports), at ``kmh``."""
    from wheelrail.core.engine import simulate
    from wheelrail.core.parameters import ModelParameters, RunParameters, SupportParameters, TrackParameters
    from wheelrail.core.roughness import RoughnessSet

    params = ModelParameters(
        track=TrackParameters(support=SupportParameters(pad_width=width)), run=RunParameters(speed=kmh / 3.6)
    )
    result = simulate(
        RoughnessSet.smooth(length + 1.0), model="hertz", params=params, length=length, track_numerics=numerics,
        keep_pressure=False,
    )  # fmt: skip
    return harmonics(result, params.track.support.sleeper_spacing, HARMONICS)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--configs", nargs="+", default=list(DEFAULT_CONFIGS))
    parser.add_argument("--pad-width-mm", nargs="+", type=float, default=[0.0, 150.0])
    parser.add_argument("--speed-kmh", type=float, default=100.0)
    parser.add_argument("--length", type=float, default=1.3, help="record length, m (whole bays are analysed)")
    parser.add_argument("--cache", action="store_true", help="use the user cache instead of a private one")
    args = parser.parse_args()
    if not args.cache and "WHEELRAIL_CACHE_DIR" not in os.environ:
        os.environ["WHEELRAIL_CACHE_DIR"] = tempfile.mkdtemp(prefix="wheelrail-pad-")
    from wheelrail.core.inputs.numerics import parse_track_numerics
    from wheelrail.core.track import clear_memory

    table = {}
    for config in args.configs:
        numerics = parse_track_numerics("" if config == "default" else config)
        for width_mm in args.pad_width_mm:
            start = time.perf_counter()
            table[config, width_mm] = smooth_rail_harmonics(width_mm * 1e-3, args.speed_kmh, args.length, numerics)
            clear_memory()
            print(f"# {config}, pad {width_mm:g} mm: {time.perf_counter() - start:.1f} s", file=sys.stderr, flush=True)
    spacing = 0.65
    print(f"## smooth rail, hertz, {args.speed_kmh:g} km/h: force amplitude (N) at k v / L_S")
    print(f"{'k':>4} " + " ".join(f"{k:7d}" for k in HARMONICS))
    for width_mm in args.pad_width_mm:
        for config in args.configs:
            row = table[config, width_mm]
            print(f"{width_mm:4g} " + " ".join(f"{a:7.3f}" for a in row) + f"  ({config})")
            if config != args.configs[0]:
                ref = table[args.configs[0], width_mm]
                change = 100 * (row - ref) / np.maximum(ref, 1e-30)
                print(f"{'':4} " + " ".join(f"{c:+6.0f}%" for c in change) + f"  (change against {args.configs[0]})")
            if width_mm > 0 and (config, 0.0) in table:
                estimate = first_order_estimate(table[config, 0.0], width_mm * 1e-3, spacing)
                print(f"{'est':>4} " + " ".join(f"{a:7.3f}" for a in estimate) + "  (first-order estimate)")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
