"""``wheelrail study``: the paper's studies (Figs 10-14, 16, 17, 11) as batches of runs."""

from __future__ import annotations

import math
import sys

from wheelrail.core.commands._common import (
    add_geometry_options,
    add_speed_option,
    geometry_from_mm,
    print_json,
    speed_from_kmh,
)
from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import ContactParameters
from wheelrail.core.study import STUDIES


def add_parser(sub):
    parser = sub.add_parser(
        "study",
        help="run one of the paper's studies (force spectra, contact filters, model differences)",
        description=(
            "Batch of independent runs reproducing a figure of the paper on any roughness set: filters "
            "(Fig. 10), line-spread (Figs 12-14), averaged-input (Fig. 16), lateral-resolution (Fig. 17), "
            "speeds (Fig. 11). Writes one CSV per figure table (band name, exact centre in Hz, levels in dB), a PNG "
            "laid out like the paper's figure and a JSON summary into --out; finished runs are kept in "
            "OUT/runs, so an interrupted study resumes with the missing runs only."
        ),
    )
    parser.add_argument("name", metavar="NAME", help=f"study: {', '.join(STUDIES)}")
    parser.add_argument(
        "--set",
        required=True,
        action="append",
        metavar="SET",
        dest="sets",
        help="bundled roughness set name or CSV/NPZ file; repeat for several sets (one panel each)",
    )
    parser.add_argument(
        "--wheel-set",
        metavar="WHEEL_SET",
        default=None,
        help="a wheel roughness set added to every rail set --set in every run (combined roughness "
        "r_rail + r_wheel; part of every run key); default none",
    )
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder (created if missing)")
    parser.add_argument(
        "--length-m",
        type=float,
        default=None,
        help="run length, m (default: the whole set: rail data less margins, one wheel turn)",
    )
    add_speed_option(parser, "train speed, km/h (for `speeds` the speed of the half-mass case)")
    where = parser.add_mutually_exclusive_group()
    # default None, not 2: argparse lets an option of a mutually exclusive group through when its value
    # equals the default, so `--dask ADDR --workers 2` would be accepted
    where.add_argument("--workers", type=int, default=None, help="local worker processes (default 2)")
    where.add_argument(
        "--dask", metavar="ADDR", default=None, help="run on a Dask cluster: scheduler address tcp://HOST:PORT"
    )
    add_geometry_options(parser)
    parser.add_argument("--json", action="store_true", help="print the machine-readable summary (SI units)")
    return parser


def run(args) -> int:
    from wheelrail.core.study import StudyContact, parse_dask_address, run_study

    if args.name not in STUDIES:
        raise WheelrailError(f"unknown study {args.name!r}; choose one of {', '.join(STUDIES)}")
    speed = speed_from_kmh(args.speed_kmh)
    if args.length_m is not None and (not math.isfinite(args.length_m) or args.length_m <= 0):
        raise WheelrailError(f"--length-m must be a positive length in m, got {args.length_m}")
    workers = 2 if args.workers is None else args.workers
    if workers < 1:
        raise WheelrailError(f"--workers must be at least 1, got {workers}")
    address = parse_dask_address(args.dask) if args.dask is not None else None
    geometry = geometry_from_mm(args)
    contact = StudyContact(contact=ContactParameters(**geometry), wheel_set=args.wheel_set)
    result = run_study(
        args.name,
        args.sets,
        args.out,
        speed=speed,
        length=args.length_m,
        workers=workers,
        contact=contact,
        dask_address=address,
        progress=not args.json and sys.stderr.isatty(),
    )
    summary = result.summary
    if args.json:
        print_json(summary)
        return 0
    wheel = f" + wheel set {summary['wheel_set']}" if summary["wheel_set"] else ""
    print(
        f"study {args.name} on {', '.join(summary['sets'])}{wheel}, {args.speed_kmh:g} km/h: {summary['runs']} runs "
        f"({summary['runs_computed']} computed, {summary['runs_cached']} from {args.out}/runs) "
        f"in {summary['wall_time_s']:.1f} s on {summary['backend']}"
    )
    if summary["loss_of_contact_steps"]:
        print(f"  loss of contact in {summary['loss_of_contact_steps']} steps over all runs")
    for table in result.tables:
        print(f"  {table.title}")
    for path in summary["files"]:
        print(f"  wrote {path}")
    return 0
