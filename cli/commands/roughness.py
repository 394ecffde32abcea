"""``wheelrail roughness``: third-octave roughness spectra and lateral coherence of a set.

Spectra as in the paper's Fig. 6 (single Hann FFT per line, third-octave bands, energetic average over the
chosen lines, dB re 1 µm) against frequency at the given speed and against wavelength (EN 15610 bands);
coherence parameter γ² of eqs. (15)-(18) as in Fig. 9. For rail sets the wavelength spectrum is compared
with the ISO 3095:2013 rail roughness limit (:mod:`wheelrail.core.roughness.iso3095`): the limit and the
margin to it per band (limit - level; negative where the rail exceeds it) in ``--json`` and the table,
and the limit as a reference line in ``--plot``.
"""

from __future__ import annotations

import math

import numpy as np

from wheelrail.cli.commands._common import (
    Files,
    Output,
    add_speed_option,
    print_json,
    speed_from_kmh,
)
from wheelrail.core.errors import WheelrailError
from wheelrail.core.roughness import (
    DEFAULT_LINES,
    lateral_coherence,
    load_roughness,
    roughness_spectrum,
)
from wheelrail.core.roughness.iso3095 import iso3095_limit, iso3095_margin
from wheelrail.core.spectra.bands import Bands, nominal_band_label

FILES = Files(reads=("set",), writes=(Output("plot", "--plot", ".png"),))
"""The set read and the figure written (checked by the dispatcher: ``_common.check_files``)."""


def add_parser(sub):
    parser = sub.add_parser(
        "roughness",
        help="third-octave roughness spectra and lateral coherence of a roughness set",
        description=(
            "Third-octave roughness spectra (dB re 1 µm, Hann window, averaged over lines) against "
            "frequency and wavelength, and the lateral coherence parameter of eqs. (15)-(18)."
        ),
    )
    parser.add_argument("--set", required=True, metavar="SET", help="bundled set name or a .csv/.npz file")
    add_speed_option(parser, "train speed for the frequency axis, km/h")
    parser.add_argument(
        "--lines",
        type=int,
        nargs="+",
        default=list(DEFAULT_LINES),
        metavar="K",
        help="line numbers to average (default -3 -2 -1 0 1 2 3, as the paper)",
    )
    parser.add_argument("--m", type=int, default=3, dest="half_lines", help="coherence: lines -M..M (default 3)")
    parser.add_argument("--blocks", type=int, default=20, help="coherence: blocks B per line (default 20)")
    parser.add_argument("--json", action="store_true", help="print a machine-readable summary on stdout")
    parser.add_argument("--plot", metavar="FILE.png", help="save a figure of spectra and coherence")
    return parser


def _nan_to_none(values) -> list:
    return [None if not math.isfinite(v) else float(v) for v in np.asarray(values, dtype=float)]


def analyse(set_name: str, speed: float, lines, half_lines: int, blocks: int) -> dict:
    """Spectra and coherence of a set as a JSON-ready dict (SI units; keys carry non-SI units)."""
    roughness = load_roughness(set_name)
    by_frequency = roughness_spectrum(roughness, speed=speed, lines=lines)
    by_wavelength = roughness_spectrum(roughness, lines=lines)
    centres, gamma2 = lateral_coherence(roughness, speed, half_lines=half_lines, blocks=blocks)
    wavelength_bands = {
        "band_centres_m": by_wavelength.band_centres.tolist(),
        "band_labels_mm": [nominal_band_label(c * 1e3) for c in by_wavelength.band_centres],
        "levels_db": _nan_to_none(by_wavelength.levels_db),
    }
    if roughness.kind == "rail":
        bands = Bands(centres=by_wavelength.band_centres, axis="wavelength")
        wavelength_bands["iso3095_limit_db"] = _nan_to_none(iso3095_limit(bands)[1])
        wavelength_bands["iso3095_margin_db"] = _nan_to_none(iso3095_margin(by_wavelength.levels_db, bands))
    return {
        "set": set_name,
        "kind": roughness.kind,
        "description": roughness.description,
        "lines_available": [int(roughness.line_numbers[0]), int(roughness.line_numbers[-1])],
        "lines_averaged": list(by_frequency.lines),
        "speed_m_s": speed,
        "coherence_m": half_lines,
        "coherence_blocks": blocks,
        "band_centres_hz": centres.tolist(),
        "band_labels": [nominal_band_label(c) for c in centres],
        "wavelengths_m": by_frequency.wavelengths.tolist(),
        "levels_db": _nan_to_none(by_frequency.levels_db),
        "coherence": _nan_to_none(gamma2),
        "wavelength_bands": wavelength_bands,
        "reference": (
            "levels in dB re 1 µm; coherence is gamma^2 of eqs. (15)-(18), null where unresolved; rail sets: "
            "ISO 3095:2013 rail roughness limit (400-3.15 mm) and margin = limit - level per band"
        ),
    }


def _cell(value, fmt: str) -> str:
    return "-" if value is None else format(value, fmt)


def _print_table(result: dict) -> None:
    speed_kmh = result["speed_m_s"] * 3.6
    print(
        f"roughness set {result['set']} ({result['kind']}); lines {result['lines_averaged']} averaged; "
        f"speed {speed_kmh:g} km/h"
    )
    print(
        f"{'band Hz':>8} {'wavelength mm':>14} {'level dB re 1um':>16} "
        f"{'coherence (M=' + str(result['coherence_m']) + ', B=' + str(result['coherence_blocks']) + ')':>22}"
    )
    for label, wavelength, level, gamma2 in zip(
        result["band_labels"], result["wavelengths_m"], result["levels_db"], result["coherence"], strict=True
    ):
        print(f"{label:>8} {wavelength * 1e3:>14.3g} {_cell(level, '.1f'):>16} {_cell(gamma2, '.3f'):>22}")
    print()
    print("EN 15610 wavelength bands")
    bands = result["wavelength_bands"]
    margins = bands.get("iso3095_margin_db")
    print(f"{'wavelength mm':>14} {'level dB re 1um':>16}" + (f" {'ISO 3095 margin dB':>19}" if margins else ""))
    for i, (label, level) in enumerate(zip(bands["band_labels_mm"], bands["levels_db"], strict=True)):
        margin = f" {_cell(margins[i], '.1f'):>19}" if margins else ""
        print(f"{label:>14} {_cell(level, '.1f'):>16}{margin}")
    if margins:
        print("(ISO 3095 margin = ISO 3095:2013 limit - level: negative where the rail exceeds the limit)")
    print("('-': band not resolved by the record length or block length)")


def _plot(result: dict, path: str) -> None:
    import matplotlib  # noqa: PLC0415 - plotting is optional, keep the CLI import light

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: PLC0415

    def arr(values):
        return np.array([np.nan if v is None else v for v in values], dtype=float)

    fig, (ax_level, ax_coh, ax_wl) = plt.subplots(3, 1, figsize=(7, 9), constrained_layout=True)
    centres = np.array(result["band_centres_hz"])
    ax_level.semilogx(centres, arr(result["levels_db"]), "o-")
    ax_level.set(xlabel="frequency (Hz)", ylabel="roughness level (dB re 1 µm)")
    ax_level.set_title(f"{result['set']} at {result['speed_m_s'] * 3.6:g} km/h, lines {result['lines_averaged']}")
    ax_coh.semilogx(centres, arr(result["coherence"]), "s-")
    ax_coh.set(xlabel="frequency (Hz)", ylabel="γ² (eqs. 15-18)", ylim=(0, 1.05))
    bands = result["wavelength_bands"]
    ax_wl.semilogx(np.array(bands["band_centres_m"]) * 1e3, arr(bands["levels_db"]), "o-", label=result["set"])
    if "iso3095_limit_db" in bands:
        ax_wl.semilogx(
            np.array(bands["band_centres_m"]) * 1e3, arr(bands["iso3095_limit_db"]), "k--", label="ISO 3095:2013 limit"
        )
        ax_wl.legend(fontsize=8)
    ax_wl.invert_xaxis()
    ax_wl.set(xlabel="wavelength (mm)", ylabel="roughness level (dB re 1 µm)")
    for ax in (ax_level, ax_coh, ax_wl):
        ax.grid(True, which="both", alpha=0.3)
    from wheelrail.core.files.atomic import atomic_write

    try:
        atomic_write(path, lambda handle: fig.savefig(handle, format="png", dpi=100))  # a disk's failure: named
    except WheelrailError:
        raise
    except ValueError as error:
        raise WheelrailError(f"--plot {path}: cannot draw the figure ({error})") from None
    finally:
        plt.close(fig)


def run(args) -> int:
    speed = speed_from_kmh(args.speed_kmh)
    if args.blocks < 1:
        raise WheelrailError(f"--blocks must be a positive integer, got {args.blocks}")
    if args.half_lines < 1:
        raise WheelrailError(f"--m must be a positive integer, got {args.half_lines}")
    result = analyse(args.set, speed, args.lines, args.half_lines, args.blocks)
    if args.plot is not None:
        _plot(result, args.plot)
    if args.json:
        print_json(result)
    else:
        _print_table(result)
        if args.plot is not None:
            print(f"figure written to {args.plot}")
    return 0
