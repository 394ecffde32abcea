"""``wheelrail filters``: the reference contact filters (CNOSSOS-EU A3 and the analytic ones) by band.

Every filter of :func:`wheelrail.core.reference_filters.reference_filters` for a wheel load, wheel radius
and speed, by the 35 wavelength bands 2000 .. 0.8 mm and by frequency band (50 Hz .. 8 kHz) at the speed;
levels in dB, null where a filter is undefined.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from wheelrail.cli.commands._common import (
    Files,
    Output,
    add_input_options,
    given_inputs,
    print_json,
    speed_from_kmh,
)
from wheelrail.core.errors import WheelrailError
from wheelrail.core.files.atomic import all_or_none, atomic_write
from wheelrail.core.inputs.declared import describe, describe_contact
from wheelrail.core.parameters import ContactParameters, ModelParameters
from wheelrail.core.reference_filters import REFERENCE_FILTERS, reference_filters

FILES = Files(writes=(Output("csv", "--csv", ".csv"), Output("plot", "--plot", ".png")))
"""The files written (checked by the dispatcher: ``_common.check_files``)."""


def add_parser(sub):
    parser = sub.add_parser(
        "filters",
        help="reference contact filters (CNOSSOS-EU A3, analytic) by wavelength and frequency band",
        description=(
            "Reference contact filters in dB by wavelength band (2000-0.8 mm) and by frequency band (50 Hz-8 kHz) "
            "at the speed: CNOSSOS-EU A3 (Directive 2015/996 Table G-2 as replaced by 2021/1226), averaging over "
            "the contact length, circular patch with roughness correlated across its width, and incoherent across "
            "it (this project's construction, not a filter of the literature)."
        ),
    )
    add_input_options(parser, "run", "geometry", leave_out=("element_size",))  # analytic filters: no run, no grid
    parser.add_argument("--json", action="store_true", help="print a machine-readable summary on stdout")
    parser.add_argument("--csv", metavar="FILE.csv", help="write the bands and levels as a CSV table")
    parser.add_argument("--plot", metavar="FILE.png", help="save a figure of the filters")
    return parser


def summary(contact: ContactParameters, speed: float) -> dict:
    """The filters for ``contact``'s load and geometry at ``speed`` as a JSON-ready dict (SI except keys that carry
    their unit), with the geometry as ``run --json`` states it (``geometry``: the radii in use). The analytic
    filters use the semi-axis a along the rail, the CNOSSOS columns stay the table's (circles of the wheel
    diameter)."""
    load, wheel_radius = contact.preload, contact.radius_along
    filters = reference_filters(load, wheel_radius, speed, contact=contact)
    params = ModelParameters(contact=contact)
    return {
        "wavelength_mm": filters.wavelength_bands.centres * 1e3,
        "wavelength_labels_mm": filters.wavelength_bands.labels(),
        "by_wavelength": filters.by_wavelength,
        "band_centres_hz": filters.frequency_bands.centres,
        "band_labels_hz": filters.frequency_bands.labels(),
        "by_frequency": filters.by_frequency,
        "semi_axes_m": list(filters.semi_axes),
        "preload_n": load,
        "wheel_radius_m": wheel_radius,
        **describe(params, "geometry"),  # the radii in use, SI (an infinite tread as null)
        "contact_geometry": describe_contact(params),
        "speed_m_s": speed,
        "reference": (
            "levels in dB (10 log10 |H|^2, averaged over each band); cnossos: Directive (EU) 2015/996 Appendix G "
            "Table G-2 as replaced by (EU) 2021/1226, other loads/diameters by the Hertz semi-axis rule; "
            "null where undefined"
        ),
    }


def _cell(value: float) -> str:
    return "" if not np.isfinite(value) else f"{value:.2f}"


def _write_csv(result: dict, path) -> None:
    def write(handle):
        writer = csv.writer(handle)
        writer.writerow(["axis", "band", "centre", "unit", *(f"{name}_db" for name in REFERENCE_FILTERS)])
        for axis, centres, labels, unit, levels in (
            ("wavelength", result["wavelength_mm"], result["wavelength_labels_mm"], "mm", result["by_wavelength"]),
            ("frequency", result["band_centres_hz"], result["band_labels_hz"], "Hz", result["by_frequency"]),
        ):
            for i, (centre, label) in enumerate(zip(centres, labels, strict=True)):
                writer.writerow([axis, label, f"{centre:.6g}", unit, *(_cell(levels[n][i]) for n in REFERENCE_FILTERS)])

    atomic_write(path, write, mode="w", newline="", encoding="utf-8")  # a failure names the file and why


def filters_figure(result: dict):
    """``--plot``'s figure (a matplotlib Figure, Agg): the filters by wavelength and by frequency, titled with the
    speed and core's words for the contact (``describe_contact``: the radii and the Hertz patch at the preload)."""
    import textwrap

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 7.5), layout="constrained")
    FigureCanvasAgg(fig)
    ax_wl, ax_f = fig.subplots(2, 1)
    styles = {"cnossos": "k-o", "averaging": "C0--", "patch-correlated": "C1--", "patch-incoherent": "C2--"}
    for name in REFERENCE_FILTERS:
        ax_wl.semilogx(result["wavelength_mm"], result["by_wavelength"][name], styles[name], label=name, ms=3)
        ax_f.semilogx(result["band_centres_hz"], result["by_frequency"][name], styles[name], label=name, ms=3)
    ax_wl.invert_xaxis()
    ax_wl.set(xlabel="wavelength (mm)", ylabel="contact filter (dB)")
    ax_f.set(xlabel="frequency (Hz)", ylabel="contact filter (dB)")
    title = f"Reference contact filters at {result['speed_m_s'] * 3.6:g} km/h: {result['contact_geometry']}"
    ax_wl.set_title("\n".join(textwrap.wrap(title, 80)), fontsize=9)
    for ax in (ax_wl, ax_f):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    return fig


def _plot(result: dict, path) -> None:
    fig = filters_figure(result)

    def write(handle):
        fig.savefig(handle, format="png", dpi=100)

    try:
        atomic_write(path, write)  # a disk's failure names the file and why
    except WheelrailError:
        raise
    except ValueError as error:
        raise WheelrailError(f"--plot {path}: cannot draw the figure ({error})") from None


def _print_table(result: dict) -> None:
    print("reference contact filters, dB")
    print(f"  contact geometry: {result['contact_geometry']}")
    header = "".join(f"{name:>18}" for name in REFERENCE_FILTERS)
    print(f"{'wavelength mm':>14}{header}")
    for i, label in enumerate(result["wavelength_labels_mm"]):
        print(f"{label:>14}" + "".join(f"{_cell(result['by_wavelength'][n][i]) or '-':>18}" for n in REFERENCE_FILTERS))
    print()
    print(f"at {result['speed_m_s'] * 3.6:g} km/h")
    print(f"{'band Hz':>14}{header}")
    for i, label in enumerate(result["band_labels_hz"]):
        print(f"{label:>14}" + "".join(f"{_cell(result['by_frequency'][n][i]) or '-':>18}" for n in REFERENCE_FILTERS))
    print("('-': undefined, e.g. CNOSSOS beyond the table's 0.8 mm after scaling)")


def run(args) -> int:
    speed = speed_from_kmh(args.speed_kmh)
    load = args.preload_kn * 1e3
    geometry = {entry.key: getattr(args, entry.dest) * entry.shown.si for entry in given_inputs(args, "geometry")}
    contact = ContactParameters(preload=load, **geometry)  # checked before any file is touched, as a run has it
    csv_path = Path(args.csv) if args.csv is not None else None  # checked by the dispatcher: FILES
    plot_path = Path(args.plot) if args.plot is not None else None
    result = summary(contact, speed)
    with all_or_none():  # the table and the figure appear together or not at all
        if csv_path is not None:
            _write_csv(result, csv_path)
        if plot_path is not None:
            _plot(result, plot_path)
    if args.json:
        print_json(result)
        return 0
    _print_table(result)
    for option, path in (("table", csv_path), ("figure", plot_path)):
        if path is not None:
            print(f"{option} written to {path}")
    return 0
