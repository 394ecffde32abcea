"""``wheelrail track``: receptance peaks of the track, its point receptances and vertical decay rate (against the
lower limit of EN ISO 3095:2013) and its cached moving Green's functions."""

from __future__ import annotations

import csv
import math
import time
from pathlib import Path

from wheelrail.cli.commands._common import (
    Files,
    Output,
    add_input_options,
    add_speed_option,
    add_track_numerics_option,
    params_from_args,
    print_json,
    print_track_numerics,
    speed_from_kmh,
    track_numerics_from_args,
)
from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.declared import describe
from wheelrail.core.noise.decay import (
    band_receptances,
    decay_verdict,
    lateral_band_receptances,
    track_decay,
    track_lateral_decay,
)

FILES = Files(
    writes=(
        Output("csv", "--csv", beside=lambda path: (_decay_csv_path(path),)),
        Output("plot", "--plot", ".png"),
    )
)
"""The files written (checked by the dispatcher: ``_common.check_files``)."""

MIN_DF_HZ = 0.05
"""Finest --df-hz: 99 601 frequencies over 20 Hz-5 kHz, a few minutes of FE solves (1e-9 Hz asked
for 5e12 frequencies and ended in MemoryError)."""


def add_parser(sub):
    parser = sub.add_parser(
        "track",
        help="track receptances, resonances, decay rate against the type-test limit, and Green's function cache",
        description=(
            "Print the resonances of the discretely supported track (paper section 2.2), its point receptance "
            "above a sleeper and at midspan and its vertical decay rate per one-third octave band (EN 15461, on "
            "the noise model's 240-bay track) beside the lower limit of EN ISO 3095:2013 (Figure 3, the TSI "
            "Noise's reference track), prepare its moving Green's functions for a speed (computed once, then "
            "cached on disk) and say where they are cached."
        ),
    )
    add_speed_option(parser)
    parser.add_argument("--json", action="store_true", help="print a machine-readable summary (SI units)")
    parser.add_argument(
        "--csv",
        metavar="FILE",
        help="write the point receptance above a sleeper and at midspan, 20 Hz-5 kHz, and the decay rate per "
        "band beside the limit to FILE's stem + _decay (FILE r.csv: r_decay.csv)",
    )
    parser.add_argument(
        "--df-hz",
        type=float,
        default=5.0,
        help=f"frequency step of --csv and --plot, Hz ({MIN_DF_HZ:g}-100, default 5)",
    )
    parser.add_argument(
        "--plot", metavar="FILE.png", help="plot receptances, decay rate and moving Green's functions (Fig. 4)"
    )
    add_input_options(parser, "track")
    add_track_numerics_option(parser)
    return parser


def _peaks(track, numerics) -> dict:
    """``track_resonances`` of the track (kind -> ``Resonance``), kept in the disk cache: several hundred FE solves
    and importing scipy.signal made most of a cached ``wheelrail track``'s time. The key holds the source of the
    modules that compute them, so a change of method recomputes."""
    import hashlib
    import inspect
    from dataclasses import asdict

    import numpy as np

    from wheelrail.core.files import cache
    from wheelrail.core.track import fe, resonances

    code = "".join(inspect.getsource(module) for module in (fe, resonances))
    key = cache.cache_key(
        "track-peaks",
        {
            "track": {name: value for name, value in asdict(track).items() if name != "lateral"},  # vertical peaks
            "elements_per_bay": numerics.elements_per_bay,
            "code": hashlib.sha256(code.encode()).hexdigest(),
        },
    )
    names = [f"{kind}_{part}" for kind in resonances.RESONANCE_KINDS for part in ("hz", "band_edge_hz")]
    arrays = cache.load_entry("track-peaks", key, names)
    if arrays is not None and all(arrays[name].shape == () for name in names):
        found = {name: float(arrays[name]) for name in names}
        if all(math.isfinite(found[f"{kind}_band_edge_hz"]) for kind in resonances.RESONANCE_KINDS):
            return {
                kind: resonances.Resonance(
                    kind,
                    found[f"{kind}_band_edge_hz"],
                    found[f"{kind}_hz"] if math.isfinite(found[f"{kind}_hz"]) else None,
                )
                for kind in resonances.RESONANCE_KINDS
            }
    peaks = resonances.track_resonances(track, numerics.elements_per_bay)
    entry = {}
    for kind, peak in peaks.items():  # NaN: no peak of this kind
        entry[f"{kind}_hz"] = np.array(np.nan if peak.frequency_hz is None else peak.frequency_hz)
        entry[f"{kind}_band_edge_hz"] = np.array(peak.band_edge_hz)
    cache.save_entry("track-peaks", key, entry)
    return peaks


def _receptances(track, numerics, df_hz):
    """Point receptance above the central sleeper and at midspan (m/N, complex), 20 Hz-5 kHz every ``df_hz``."""
    import numpy as np

    from wheelrail.core.track import assemble_track, track_receptance

    L = track.support.sleeper_spacing
    x_sleeper = (track.n_bays // 2) * L
    model = assemble_track(track, numerics.elements_per_bay)
    freq = np.arange(20.0, 5000.0 + 1e-9, df_hz)
    return freq, track_receptance(model, freq, x_sleeper), track_receptance(model, freq, x_sleeper + L / 2)


def _decay_csv_path(csv_path: Path) -> Path:
    return csv_path.with_name(f"{csv_path.stem}_decay{csv_path.suffix or '.csv'}")


def _write_decay_csv(path: Path, decay: dict, lateral: dict) -> None:
    """The vertical and lateral decay rates per band beside their limits (``decay_against_limit``'s layouts)."""
    from wheelrail.core.files.atomic import atomic_write

    def cells(table: dict, i: int) -> list:
        f, rate, limit = (table[key][i] for key in ("frequency_hz", "decay_rate_dB_per_m", "limit_dB_per_m"))
        return [f"{rate:.6g}", "" if limit is None else f"{limit:g}", int(f in set(table["below_limit_hz"]))]

    def write(handle) -> None:
        writer = csv.writer(handle)
        writer.writerow(
            ["frequency_hz", "decay_rate_dB_per_m", "iso3095_vertical_limit_dB_per_m", "below_limit"]
            + ["lateral_decay_rate_dB_per_m", "iso3095_lateral_limit_dB_per_m", "lateral_below_limit"]
        )
        for i, f in enumerate(decay["frequency_hz"]):
            writer.writerow([f"{f:.6g}", *cells(decay, i), *cells(lateral, i)])

    atomic_write(path, write, mode="w", newline="")


def _receptance_outputs(receptances, csv_path, plot_path, response, peaks, decay, params, lateral) -> None:
    """``--csv`` and ``--plot``: the point receptance above a sleeper and at midspan, 20 Hz-5 kHz, and the
    decay rate per band beside the limit."""
    import numpy as np

    freq, above, midspan = receptances
    if csv_path:
        _write_decay_csv(_decay_csv_path(csv_path), decay, lateral)
        from wheelrail.core.files.atomic import atomic_write

        def write_csv(handle) -> None:
            writer = csv.writer(handle)
            writer.writerow(
                [
                    "frequency_hz",
                    "above_sleeper_abs_m_per_n",
                    "above_sleeper_phase_rad",
                    "midspan_abs_m_per_n",
                    "midspan_phase_rad",
                ]
            )
            for row in zip(freq, np.abs(above), np.angle(above), np.abs(midspan), np.angle(midspan), strict=True):
                writer.writerow([f"{row[0]:.6g}"] + [f"{v:.9e}" for v in row[1:]])

        atomic_write(csv_path, write_csv, mode="w", newline="")
    if plot_path:
        _plot(plot_path, receptances, response, peaks, decay, params, lateral)


def _green_functions(track, numerics, speed: float) -> dict:
    """The stationary responses (from the cache or computed) and the moving Green's functions at ``speed``."""
    from wheelrail.core.track import moving_from_stationary, stationary_track_response, track_cache_path

    cached_before = track_cache_path(track, numerics).exists()
    start = time.perf_counter()
    from wheelrail.cli.commands._progress import announce_track_precompute

    with announce_track_precompute("track"):  # a track not yet cached: its phases and progress on a terminal
        response = stationary_track_response(track, numerics)
    t_stationary = time.perf_counter() - start
    start = time.perf_counter()
    green = moving_from_stationary(response, speed)
    t_speed = time.perf_counter() - start
    return {
        "response": response,
        "green": green,
        "static": green.weights(1e-3 / speed).sum(axis=1),
        "cache": {
            "was_cached": bool(cached_before),
            "stationary_time_s": t_stationary,
            "speed_time_s": t_speed,
        },
    }


def _print_resonances(track, peaks: dict) -> None:
    """One line per resonance: its receptance peak or why there is none, and the undamped track's band edge."""
    from wheelrail.core.parameters import TrackParameters

    for peak in peaks.values():
        name = f"{peak.label} resonance"
        if peak.frequency_hz is None:
            print(f"  {name:<29} {peak.in_words()}")
            continue
        paper = "; paper: 943 Hz" if peak.kind == "pinned_pinned" and track == TrackParameters() else ""
        print(
            f"  {name:<29} {peak.frequency_hz:7.1f} Hz  (receptance {peak.receptance}; undamped track "
            f"{peak.band_edge_hz:.0f} Hz{paper})"
        )


def _print_summary(track, summary: dict, peaks: dict) -> None:
    cache = summary["cache"]
    green, static = summary["green_functions"], summary["static_moving_compliance_m_per_n"]
    speed_kmh = summary["speed_kmh"]
    sup = track.support
    print(
        f"Track: UIC60 Rayleigh-Timoshenko rail (loss factor {track.rail.loss_factor:g}), {track.n_bays} bays of "
        f"{sup.sleeper_spacing} m; pads {sup.pad_stiffness / 1e6:g} MN/m, {sup.pad_damping / 1e3:g} kN s/m, "
        + (f"{sup.pad_width * 1e3:g} mm wide" if sup.pad_width else "point supports")
        + f"; sleepers {sup.sleeper_mass:g} kg; ballast {sup.ballast_stiffness / 1e6:g} MN/m, "
        f"{sup.ballast_damping / 1e3:g} kN s/m (paper section 2.2)"
    )
    lat = track.lateral
    print(
        f"  lateral: {lat.section.name} rail in bending and torsion; pads {lat.pad_lateral_stiffness / 1e6:g} MN/m "
        f"laterally, {lat.pad_rotational_stiffness / 1e3:g} kNm/rad in roll, loss factor "
        f"{lat.pad_lateral_loss_factor:g}; ballast {lat.ballast_lateral_stiffness / 1e6:g} MN/m laterally"
    )
    print_track_numerics(summary["track_numerics"])
    _print_resonances(track, peaks)
    print(f"  sleeper-passing frequency     {summary['sleeper_passing_frequency_hz']:7.1f} Hz  at {speed_kmh:g} km/h")
    print(
        f"Moving Green's functions at {speed_kmh:g} km/h: {green['duration_s'] * 1e3:.0f} ms, "
        f"{green['excitation_positions_per_bay']} excitation positions per bay, read at {green['rows_per_bay']} rows"
    )
    print(
        f"  static compliance {static['above_sleeper'] * 1e9:.3f} nm/N above a sleeper, "
        f"{static['midspan'] * 1e9:.3f} nm/N at midspan"
    )
    how = "loaded from cache" if cache["was_cached"] else "computed and cached"
    print(
        f"  stationary responses {how} in {cache['stationary_time_s']:.2f} s; this speed in "
        f"{cache['speed_time_s'] * 1e3:.1f} ms"
    )
    print(f"  cache: {cache['path']} ({cache['size_bytes'] / 1e6:.1f} MB)")
    lateral = {"decay": summary["lateral_decay_rate"], "receptance": summary["lateral_receptance"]}
    _print_bands(summary["bands"], summary["decay_rate"], lateral)
    if "csv" in summary:
        print(f"  receptance written to {summary['csv']}, decay rate to {summary['decay_csv']}")
    if "plot" in summary:
        print(f"  plot written to {summary['plot']}")


def _print_bands(bands: dict, decay: dict, lateral: dict | None = None) -> None:
    """The table per one-third octave band, each named by its nominal centre (``spectra.bands.nominal_band_label``);
    with ``lateral`` (``{"decay": ..., "receptance": ...}``: the lateral decay rate in ``decay_against_limit``'s
    layout and ``lateral_band_receptances``) the railhead's lateral point receptance and decay rate beside."""
    from wheelrail.core.spectra.bands import band_labels

    print(
        "Point receptance at the band centres (m/N) and vertical decay rate (dB/m, EN 15461) against "
        "EN ISO 3095:2013's lower limit"
        + (
            ":"
            if lateral is None
            else "; the railhead's lateral point receptance and lateral decay rate against its limit:"
        )
    )
    print("    band Hz   above sleeper     midspan   decay   limit" + ("" if lateral is None else LATERAL_COLUMNS))
    limits = dict(zip(decay["frequency_hz"], decay["limit_dB_per_m"], strict=True))
    rates = dict(zip(decay["frequency_hz"], decay["decay_rate_dB_per_m"], strict=True))
    for f, label, above, mid in zip(
        bands["frequency_hz"],
        band_labels(bands["frequency_hz"]),
        bands["above_sleeper_m_per_n"],
        bands["midspan_m_per_n"],
        strict=True,
    ):
        limit = limits.get(f)
        mark = "" if limit is None else f"  {limit:6.2f}" + ("  below" if rates[f] < limit else "")
        if lateral is not None:
            mark = f"{mark:<15}" + _lateral_cells(lateral, f)
        print(f"  {label:>9}   {above:11.3e} {mid:11.3e}  {rates[f]:6.2f}{mark}".rstrip())
    print(f"  the decay rate {decay_verdict(decay)} ({decay['limit_source']})")
    if lateral is not None:
        print(f"  the lateral decay rate {decay_verdict(lateral['decay'])} ({lateral['decay']['limit_source']})")


LATERAL_COLUMNS = "          lateral   decay   limit"


def _lateral_cells(lateral: dict, f: float) -> str:
    """The lateral point receptance, decay rate and limit of the band ``f`` (its exact centre), as table cells."""
    import numpy as np

    decay, receptance = lateral["decay"], lateral["receptance"]
    i = int(np.argmin(np.abs(np.asarray(decay["frequency_hz"]) - f)))
    rate, limit = decay["decay_rate_dB_per_m"][i], decay["limit_dB_per_m"][i]
    cells = f"  {receptance['lateral_point_m_per_n'][i]:11.3e}  {rate:6.2f}"
    return cells + ("" if limit is None else f"  {limit:6.2f}" + ("  below" if rate < limit else ""))


def run(args) -> int:
    from wheelrail.core.inputs.numerics import numerics_changes
    from wheelrail.core.parameters import as_dict

    speed = speed_from_kmh(args.speed_kmh)
    if not math.isfinite(args.df_hz) or not MIN_DF_HZ <= args.df_hz <= 100:
        raise WheelrailError(f"--df-hz must be in [{MIN_DF_HZ:g}, 100] Hz, got {args.df_hz:g}")
    csv_path = Path(args.csv) if args.csv is not None else None  # checked by the dispatcher: FILES
    plot_path = Path(args.plot) if args.plot is not None else None

    track = params_from_args(args, "track").track
    numerics = track_numerics_from_args(args)
    changed = numerics_changes(numerics)
    peaks = _peaks(track, numerics)
    if speed > numerics.max_speed:
        from dataclasses import replace

        numerics = replace(numerics, max_speed=speed)
    built = _green_functions(track, numerics, speed)
    green, static = built["green"], built["static"]
    decay = track_decay(track)
    lateral = {"decay": track_lateral_decay(track), "receptance": lateral_band_receptances(track)}
    receptances = _receptances(track, numerics, args.df_hz) if (csv_path or plot_path or args.json) else None
    if csv_path or plot_path:
        from wheelrail.core.files.atomic import all_or_none

        with all_or_none():  # the tables and the figure appear together or not at all
            _receptance_outputs(
                receptances,
                csv_path,
                plot_path,
                built["response"],
                peaks,
                decay,
                params_from_args(args, "track"),
                lateral["decay"],
            )
    summary = {
        **describe(params_from_args(args, "track"), "track"),
        "track_parameters": as_dict(track),
        # the track's numerics that differ from the default, as --track-numerics names them ({}: the default)
        "track_numerics": changed,
        "speed_m_per_s": speed,
        "speed_kmh": args.speed_kmh,
        "resonances_hz": {f"{kind}_hz": peak.frequency_hz for kind, peak in peaks.items()},
        "resonances": {kind: peak.as_dict() for kind, peak in peaks.items()},
        "sleeper_passing_frequency_hz": speed / track.support.sleeper_spacing,
        "static_moving_compliance_m_per_n": {
            "above_sleeper": float(static[0]),
            "midspan": float(static[len(static) // 2]),
        },
        "green_functions": {
            "duration_s": green.duration,
            "time_step_s": green.time_step,
            "excitation_positions_per_bay": numerics.positions_per_bay,
            "rows_per_bay": len(green.excitation_positions),
            "max_speed_m_per_s": numerics.max_speed,
        },
        # read last: a new track's entry is written in the background while the tables above are worked out
        "cache": _cache_summary(built),
        "decay_rate": decay,
        "bands": band_receptances(track, numerics.elements_per_bay),
        "lateral_decay_rate": lateral["decay"],
        "lateral_receptance": lateral["receptance"],
    }
    _outputs_named(summary, receptances, csv_path, plot_path)
    if args.json:
        print_json(summary)
        return 0
    _print_summary(track, summary, peaks)
    return 0


def _cache_summary(built: dict) -> dict:
    """The track's cache entry: its path and size (both wait for a background write of a new track's entry to
    finish, hence asked for last), whether it was cached and the times taken."""
    path = built["response"].cache_path
    return {"path": path, "size_bytes": Path(path).stat().st_size if path else 0, **built["cache"]}


def _outputs_named(summary: dict, receptances, csv_path, plot_path) -> None:
    """The summary's band names beside the exact centres (as every JSON gives them), the point receptance when
    computed, and the files written."""
    import numpy as np

    from wheelrail.core.spectra.bands import band_labels

    for table in ("bands", "decay_rate", "lateral_decay_rate", "lateral_receptance"):
        summary[table]["band_labels"] = band_labels(summary[table]["frequency_hz"])
    if receptances is not None:
        freq, above, midspan = receptances
        summary["point_receptance"] = {
            "frequency_hz": freq,
            "above_sleeper_m_per_n": np.abs(above),
            "midspan_m_per_n": np.abs(midspan),
        }
    if csv_path:
        summary["csv"] = str(csv_path)
        summary["decay_csv"] = str(_decay_csv_path(csv_path))
    if plot_path:
        summary["plot"] = str(plot_path)


def _plot(path, receptances, response, peaks, decay, params, lateral) -> None:
    from wheelrail.core.files.atomic import atomic_write

    fig = track_figure(receptances, response, peaks, decay, params, lateral)
    atomic_write(path, lambda handle: fig.savefig(handle, format="png", dpi=110))


def track_figure(receptances, response, peaks, decay, params, lateral=None):
    """``--plot``'s figure (a matplotlib Figure, Agg): the point receptances, the moving Green's functions (Fig. 4)
    and the vertical decay rate against its limit, then the lateral one (``lateral``, in ``decay_against_limit``'s
    layout) against its own, titled with the track (core's ``describe_track``)."""
    import textwrap

    import numpy as np
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from wheelrail.core.inputs.declared import describe_track
    from wheelrail.core.noise.decay import decay_verdict
    from wheelrail.core.track import moving_from_stationary

    freq, above, midspan = receptances
    fig = Figure(figsize=(20 if lateral is None else 25, 4.6), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, 4 if lateral is None else 5)
    ax = axes[0]
    ax.loglog(freq, np.abs(above), label="above sleeper")
    ax.loglog(freq, np.abs(midspan), label="midspan")
    if peaks["pinned_pinned"].frequency_hz is not None:
        ax.axvline(peaks["pinned_pinned"].frequency_hz, color="grey", lw=0.8, ls=":")
    ax.set(xlabel="frequency (Hz)", ylabel="|receptance| (m/N)", title="Rail point receptance")
    ax.legend()
    for ax, midspan, title in (
        (axes[1], False, "(a) excitation above a sleeper"),
        (axes[2], True, "(b) excitation at midspan"),
    ):
        for kmh, style in ((50, "--"), (100, "-."), (150, "-")):
            if kmh / 3.6 > response.numerics.max_speed:
                continue
            green = moving_from_stationary(response, kmh / 3.6)
            index = len(green.excitation_positions) // 2 if midspan else 0
            keep = green.time <= 0.02
            ax.plot(green.time[keep] * 1e3, green.values[index, keep], style, label=f"{kmh} km/h")
        ax.set(xlabel="time (ms)", ylabel="g (m/(N s))", title=f"Moving Green's function {title}")
        ax.legend()
    for ax, table, name in ((axes[3], decay, "Vertical"), (axes[4] if lateral else None, lateral, "Lateral")):
        if ax is None:
            continue
        ax.loglog(table["frequency_hz"], table["decay_rate_dB_per_m"], "o-", label="track (EN 15461)")
        limit = np.array([np.nan if v is None else v for v in table["limit_dB_per_m"]])
        ax.loglog(table["frequency_hz"], limit, "k--", label="EN ISO 3095:2013 lower limit")
        verdict = f"{name} track decay rate: it {decay_verdict(table)}"
        ax.set(xlabel="frequency (Hz)", ylabel="decay rate (dB/m)", title="\n".join(textwrap.wrap(verdict, 52)))
        ax.title.set_fontsize(9)
        ax.legend()
    fig.suptitle(f"wheelrail track: {describe_track(params)}", fontsize=11)
    return fig
