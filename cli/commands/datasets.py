"""``wheelrail datasets``: list the bundled roughness sets."""

from __future__ import annotations

from wheelrail.cli.commands._common import print_json
from wheelrail.core.roughness import bundled_names, load_roughness


def add_parser(sub):
    parser = sub.add_parser(
        "datasets",
        help="list the bundled roughness sets",
        description="List the bundled roughness sets: name, kind, lines, length and spacings.",
    )
    parser.add_argument("--json", action="store_true", help="print a machine-readable summary (SI units)")
    return parser


def describe(name: str) -> dict:
    """Summary of one bundled set in SI units (m)."""
    roughness = load_roughness(name)
    return {
        "name": name,
        "kind": roughness.kind,
        "lines": roughness.n_lines,
        "line_numbers": [int(roughness.line_numbers[0]), int(roughness.line_numbers[-1])],
        "samples": roughness.n_samples,
        "length_m": roughness.length,
        "dx_m": roughness.dx,
        "lateral_spacing_m": roughness.lateral_spacing,
        "description": roughness.description,
    }


def run(args) -> int:
    sets = [describe(name) for name in bundled_names()]
    if args.json:
        print_json({"datasets": sets})
        return 0
    print(f"{'name':<18} {'kind':<6} {'lines':>5} {'numbers':>9} {'length':>8} {'dx':>7} {'line spacing':>12}")
    for s in sets:
        numbers = f"{s['line_numbers'][0]}..{s['line_numbers'][1]}"
        print(
            f"{s['name']:<18} {s['kind']:<6} {s['lines']:>5} {numbers:>9} {s['length_m']:>6.3g} m "
            f"{s['dx_m'] * 1e3:>4.3g} mm {s['lateral_spacing_m'] * 1e3:>9.3g} mm"
        )
    print("All bundled sets are synthetic (see sample_data/README.md). Use --set NAME or --set FILE.csv|.npz.")
    return 0
