"""``wheelrail wheel``: the modal wheel's natural frequencies by family and n, and its receptances at the contact.

The wheel is a named standard-like wheel (``--wheel``), changed by the shape options (``--tyre-width-mm``, ...,
each a field of ``wheelrail.core.modal_wheel.WheelProfile`` with its range in ``core.inputs.ranges``), or a
cross-section read from a CSV outline (``--outline``). Its modes come from the axisymmetric finite elements of
``wheelrail.core.modal_wheel`` (computed once, then cached on disk).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

from wheelrail.cli.commands._common import WHEEL_SHAPE_KEYS as SHAPE_KEYS
from wheelrail.cli.commands._common import Files, Output, print_json
from wheelrail.cli.commands._common import wheel_shape_option as shape_option
from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.ranges import ACCEPTED

FILES = Files(
    reads=("outline",),
    writes=(Output("csv", "--csv", beside=lambda path: (_modes_path(path),)), Output("plot", "--plot", ".png")),
)
"""The outline read and the files written (checked by the dispatcher: ``_common.check_files``)."""

BAND_RANGE_HZ = (100.0, 10e3)
"""The third-octave bands whose (exact) centres the summary states the receptances at."""


def add_parser(sub):
    parser = sub.add_parser(
        "wheel",
        help="the modal wheel: natural frequencies by family and nodal diameters, receptances at the contact",
        description=(
            "Compute a solid wheel's modes from its cross-section (axisymmetric finite elements with "
            "circumferential harmonics n = 0..N, the bore clamped on the axle) and print its natural "
            "frequencies by family (axial, radial, circumferential) and n, and its radial, axial and cross "
            "receptances at the contact. Modes are cached on disk."
        ),
    )
    shape = parser.add_argument_group("Wheel shape (mm; each changes the named wheel)")
    shape.add_argument("--wheel", default="freight_920", help="named wheel: freight_920 (default), wheel_840, "
                       "wheel_640")  # fmt: skip
    for key in SHAPE_KEYS:
        low, high = ACCEPTED[key].in_unit(1e3)
        shape.add_argument(shape_option(key), type=float, help=f"{ACCEPTED[key].reason} (accepted {low:g} to "
                           f"{high:g})")  # fmt: skip
    shape.add_argument("--outline", metavar="FILE.csv", help="a cross-section outline instead: (r, z) in mm per line")
    shape.add_argument("--contact-z-mm", type=float, default=0.0, help="with --outline: the contact's z (default 0)")
    numerics = parser.add_argument_group("Modes")
    numerics.add_argument("--max-frequency-hz", type=float, default=10e3, help="modes up to (default 10000)")
    numerics.add_argument("--max-harmonic", type=int, default=10, help="nodal diameters n = 0..N (default 10)")
    numerics.add_argument("--element-size-mm", type=float, default=12.0, help="mesh size, 2 to 50 mm (default 12); "
                          "the modes' cost is said first and bounded")  # fmt: skip
    numerics.add_argument("--added-loss-factor", type=float, default=0.0, help="a damper's loss factor (default 0)")
    numerics.add_argument("--free-hub", action="store_true", help="leave the bore free (default: clamped)")
    parser.add_argument("--json", action="store_true", help="print a machine-readable summary (SI units)")
    parser.add_argument("--csv", metavar="FILE", help="write the receptances to FILE and the modes to FILE's stem "
                        "+ _modes")  # fmt: skip
    parser.add_argument("--df-hz", type=float, default=10.0, help="frequency step of --csv and --plot (1-100 Hz)")
    parser.add_argument("--plot", metavar="FILE.png", help="plot the cross-section, the frequencies and receptances")
    return parser


def profile_from_args(args):
    """The wheel the options describe (SI): the named wheel with the shape options set, or the outline."""
    from dataclasses import replace

    from wheelrail.core.modal_wheel import named_profile, read_outline

    given = {key: getattr(args, shape_option(key)[2:].replace("-", "_")) for key in SHAPE_KEYS}
    given = {key: value for key, value in given.items() if value is not None}
    if args.outline is not None:
        if given:
            raise WheelrailError(f"--outline and {shape_option(next(iter(given)))} cannot be given together")
        return read_outline(args.outline, args.contact_z_mm)
    fields = {(k if k == "wheel_radius" else k.removeprefix("wheel_")): v * 1e-3 for k, v in given.items()}
    return replace(named_profile(args.wheel), **fields)


def _checked(args) -> dict:
    """The numerical settings in SI, each within its range (one WheelrailError naming its option)."""
    from wheelrail.core.modal_wheel import modal_loss_factor
    from wheelrail.core.modal_wheel.section import check_element_size

    size = check_element_size(args.element_size_mm * 1e-3)

    modal_loss_factor(0, "axial", args.added_loss_factor)  # refused now, not after the modes
    if not (math.isfinite(args.df_hz) and 1.0 <= args.df_hz <= 100.0):
        raise WheelrailError(f"--df-hz must be in [1, 100] Hz, got {args.df_hz:g}")
    return {"max_frequency": args.max_frequency_hz, "max_harmonic": args.max_harmonic, "element_size": size,
            "clamped": not args.free_hub}  # fmt: skip


def frequency_table(modes) -> list[dict]:
    """Per harmonic n: its natural frequencies (Hz) by family, and its number of rigid-body motions (a free hub's:
    not natural frequencies, ``WheelModes.rigid_body``)."""
    import numpy as np

    table = []
    for n in range(modes.max_harmonic + 1):
        row = {"n": n, "rigid_body": int(np.sum((modes.harmonic == n) & modes.rigid_body))}
        for family in ("axial", "radial", "circumferential"):
            chosen = (modes.harmonic == n) & (modes.family == family) & ~modes.rigid_body
            row[family] = [float(f) for f in np.sort(modes.frequency[chosen])]
        table.append(row)
    return table


def run(args) -> int:
    import sys
    import time

    import numpy as np

    from wheelrail.core.modal_wheel import contact_receptance, section_mass, wheel_modes

    settings = _checked(args)
    csv_path = Path(args.csv) if args.csv is not None else None  # checked with the outline: FILES
    plot_path = Path(args.plot) if args.plot is not None else None
    profile = profile_from_args(args)
    start = time.perf_counter()
    modes = wheel_modes(profile, **settings, announce=_announce(sys.stderr))
    elapsed = time.perf_counter() - start
    from wheelrail.core.spectra.bands import frequency_bands

    bands = frequency_bands(None, (BAND_RANGE_HZ[0], min(BAND_RANGE_HZ[1], modes.max_frequency))).centres
    at_bands = contact_receptance(modes, bands, args.added_loss_factor)
    summary = {
        "wheel": profile.describe(),
        "mass_kg": section_mass(profile, modes.material.density),
        "modes": {
            **{k: v for k, v in settings.items()},
            "count": int(np.sum(~modes.rigid_body)),
            "rigid_body": int(np.sum(modes.rigid_body)),
            "elements": len(modes.mesh.triangles),
            "time_s": elapsed,
            "cache": modes.cache_path,
            "nodes": len(modes.mesh.nodes),
        },  # fmt: skip
        "loss_factor": {"n_0_1": 1e-3, "n_2_and_above": 1e-4, "added": args.added_loss_factor},
        "natural_frequencies_hz": frequency_table(modes),
        "receptance_at_bands": _receptance_dict(at_bands),
    }
    if csv_path or plot_path:
        from wheelrail.core.files.atomic import all_or_none

        frequencies = np.arange(args.df_hz, modes.max_frequency + 1e-9, args.df_hz)
        fine = contact_receptance(modes, frequencies, args.added_loss_factor)
        with all_or_none():
            if csv_path:
                _write_csv(csv_path, fine, modes, args.added_loss_factor)
                summary["csv"], summary["modes_csv"] = str(csv_path), str(_modes_path(csv_path))
            if plot_path:
                _plot(plot_path, modes, fine, args.added_loss_factor)
                summary["plot"] = str(plot_path)
    if args.json:
        print_json(summary)
    else:
        _print_summary(summary)
    return 0


def _announce(stream):
    """Say on ``stream``, if it is a terminal (pipes and ``--json`` stay clean), what the modes will cost."""

    def say(cost) -> None:
        print(f"wheelrail wheel: computing the modes once (then cached): {cost.describe()}", file=stream, flush=True)

    return say if stream.isatty() else None


def _receptance_dict(receptance) -> dict:
    import numpy as np

    return {
        "frequency_hz": receptance.frequency,
        "radial_m_per_n": np.abs(receptance.radial),
        "axial_m_per_n": np.abs(receptance.axial),
        "cross_m_per_n": np.abs(receptance.cross),
    }


def _print_summary(summary: dict) -> None:
    wheel, modes = summary["wheel"], summary["modes"]
    if wheel["kind"] == "parametric":
        print(
            f"Wheel: {2e3 * wheel['wheel_radius']:g} mm, rim {wheel['tyre_width'] * 1e3:g} x "
            f"{wheel['tyre_depth'] * 1e3:g} mm, web {wheel['web_thickness'] * 1e3:g} mm (offset "
            f"{wheel['web_offset'] * 1e3:g} mm), contact {wheel['contact_offset'] * 1e3:g} mm from the web"
        )
    else:
        print(f"Wheel: outline {wheel['name']} ({len(wheel['points'])} points), contact at {wheel['contact']} m")
    print(f"  mass {summary['mass_kg']:.0f} kg (steel, the cross-section turned about the axle)")
    how = f"cached in {modes['cache']}" if modes["cache"] else "not cached"
    print(f"  {modes['count']} modes up to {modes['max_frequency']:g} Hz, n = 0..{modes['max_harmonic']}, "
          f"{modes['elements']} elements, {modes['nodes']} nodes, {modes['time_s']:.2f} s ({how})")  # fmt: skip
    if modes["rigid_body"]:
        print(f"  and {modes['rigid_body']} rigid-body motions at 0 Hz (the hub free: along, about and across the "
              "axle, rocking), in the receptances, not natural frequencies")  # fmt: skip
    if not modes["count"]:
        print(f"  no natural frequency up to {modes['max_frequency']:g} Hz: raise --max-frequency-hz to see some")
    print("Natural frequencies (Hz) by nodal diameters n:")
    for row in summary["natural_frequencies_hz"]:
        parts = [f"{family} " + " ".join(f"{f:.0f}" for f in row[family]) for family in ("axial", "radial",
                 "circumferential") if row[family]]  # fmt: skip
        print(f"  n = {row['n']:2d}: " + "; ".join(parts))
    bands = summary["receptance_at_bands"]
    from wheelrail.core.spectra.bands import nominal_band_label

    print("Receptance at the contact (m/N): band Hz, radial, axial, cross")
    for f, rr, zz, rz in zip(bands["frequency_hz"], bands["radial_m_per_n"], bands["axial_m_per_n"],
                             bands["cross_m_per_n"], strict=True):  # fmt: skip
        print(f"  {nominal_band_label(f):>7}  {rr:10.3e} {zz:10.3e} {rz:10.3e}")
    for key, what in (("csv", "receptances"), ("modes_csv", "modes"), ("plot", "plot")):
        if key in summary:
            print(f"  {what} written to {summary[key]}")


def _modes_path(csv_path: Path) -> Path:
    return csv_path.with_name(f"{csv_path.stem}_modes{csv_path.suffix or '.csv'}")


def _write_csv(path: Path, receptance, modes, added_loss_factor: float) -> None:
    import numpy as np

    from wheelrail.core.files.atomic import atomic_write

    def write_receptance(handle) -> None:
        writer = csv.writer(handle)
        names = ("radial", "axial", "cross")
        writer.writerow(["frequency_hz"] + [f"{n}_{part}" for n in names for part in ("abs_m_per_n", "phase_rad")])
        values = (receptance.radial, receptance.axial, receptance.cross)
        for i, f in enumerate(receptance.frequency):
            writer.writerow([f"{f:.6g}"] + [f"{v:.9e}" for a in values for v in (abs(a[i]), np.angle(a[i]))])

    def write_modes(handle) -> None:
        writer = csv.writer(handle)
        writer.writerow(["n", "family", "frequency_hz", "loss_factor"])
        eta = modes.loss_factor(added_loss_factor)
        families = np.where(modes.rigid_body, "rigid-body", modes.family)  # a free hub's rigid-body motions
        for n, family, f, loss in zip(modes.harmonic, families, modes.frequency, eta, strict=True):
            writer.writerow([int(n), family, f"{f:.6g}", f"{loss:.3g}"])

    atomic_write(path, write_receptance, mode="w", newline="")
    atomic_write(_modes_path(path), write_modes, mode="w", newline="")


def _plot(path: Path, modes, receptance, added_loss_factor: float = 0.0) -> None:
    from wheelrail.core.files.atomic import atomic_write

    fig = wheel_figure(modes, receptance, added_loss_factor)
    atomic_write(path, lambda handle: fig.savefig(handle, format="png", dpi=100))


def wheel_figure(modes, receptance, added_loss_factor: float = 0.0):
    """``--plot``'s figure (a matplotlib Figure, Agg): the cross-section and mesh, the natural frequencies and the
    receptances at the contact, titled with the wheel (core's ``describe_wheel``)."""
    import numpy as np
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from wheelrail.core.modal_wheel import describe_wheel

    fig = Figure(figsize=(16, 4.8), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, 3)
    nodes, corners = modes.mesh.nodes * 1e3, modes.mesh.triangles[:, :3]
    axes[0].triplot(nodes[:, 1], nodes[:, 0], corners, lw=0.4)
    axes[0].plot(*(np.array(modes.profile.contact_point())[::-1] * 1e3), "r^", label="contact")
    axes[0].set(xlabel="z (mm)", ylabel="r (mm)", title="Cross-section and mesh", aspect="equal")
    axes[0].legend()
    for family, marker in (("axial", "o"), ("radial", "s"), ("circumferential", "^")):
        chosen = (modes.family == family) & ~modes.rigid_body
        axes[1].plot(modes.harmonic[chosen], modes.frequency[chosen], marker, ls="", label=family)
    axes[1].set(xlabel="nodal diameters n", ylabel="frequency (Hz)", title="Natural frequencies")
    axes[1].legend()
    for values, label in ((receptance.radial, "radial"), (receptance.axial, "axial"), (receptance.cross, "cross")):
        axes[2].loglog(receptance.frequency, np.abs(values), label=label)
    axes[2].set(xlabel="frequency (Hz)", ylabel="|receptance| (m/N)", title="Receptance at the contact")
    axes[2].legend()
    damper = f", a damper's added loss factor {added_loss_factor:g}" if added_loss_factor else ""
    bore = "bore clamped" if modes.clamped else "bore free"
    fig.suptitle(
        f"wheelrail wheel: {describe_wheel(modes.profile)}; {bore}{damper}; {len(modes.frequency)} modes up to "
        f"{modes.max_frequency:g} Hz, n = 0..{modes.max_harmonic}",
        fontsize=10,
    )
    return fig
