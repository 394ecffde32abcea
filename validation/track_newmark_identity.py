"""The track's Green's functions of this checkout against another's (e.g. the commit before a change of the
integration), or its integration on the model's mirror symmetry against every position integrated: max |new -
base| / max |base| of the stored responses before their float32 cast.

Each checkout integrates the default track's impulse responses (``TrackNumerics()``: every excitation position,
the whole wedge, float64) in a process of its own, with its own ``.venv``; the wedge's layout (counts, offsets)
must be the same. With ``--full`` instead of ``--base``, this checkout's responses as computed (the positions
past the central bay's middle read from their mirror images, ``stationary.mirror_plan``) against every position
integrated, on the same model. Run:

    python3 validation/track_newmark_identity.py --base /path/to/other/checkout [--pad-width-mm 150]
        [--rail-loss-factor 0.02]
    python3 validation/track_newmark_identity.py --full [--pad-width-mm 150] [--rail-loss-factor 0.02]

Prints the relative difference per quantity (rail displacement w, rotation theta) and overall.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve()


def responses(pad_width: float, loss_factor: float, path: str, mirror: bool = True) -> None:
    """Integrate the track's responses with the installed ``wheelrail`` (the checkout whose python runs this)
    and save data (float64), counts and offsets to ``path`` (.npz); ``mirror`` False: every position integrated
    (a checkout without the mirror symmetry integrates every position anyway)."""
    from wheelrail.core.parameters import RailParameters, SupportParameters, TrackNumerics, TrackParameters
    from wheelrail.core.track import stationary

    track = TrackParameters(
        support=SupportParameters(pad_width=pad_width), rail=RailParameters(loss_factor=loss_factor)
    )
    numerics = TrackNumerics()
    model = stationary.numerics_model(track, numerics)
    _, x_e, _ = stationary.excitation_nodes(model, numerics)
    t_stored, n_steps = stationary.stored_times(numerics)
    nodes, _, counts, offsets = stationary.stored_nodes(model, numerics, x_e, numerics.max_speed, t_stored)
    if not mirror:
        stationary.MIRROR_SYMMETRY = False
    data = stationary.integrate_responses(
        model, x_e, numerics.time_step, n_steps, numerics.store_every, nodes, counts, offsets, impulse=True
    )
    np.savez(path, data=np.asarray(data, dtype=np.float64), counts=counts, offsets=offsets)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    which = parser.add_mutually_exclusive_group(required=True)
    which.add_argument("--base", type=Path, help="the other checkout (run with its .venv)")
    which.add_argument("--full", action="store_true", help="against every position integrated, this checkout")
    parser.add_argument("--pad-width-mm", type=float, default=0.0)
    parser.add_argument("--rail-loss-factor", type=float, default=0.0)
    parser.add_argument("--_worker", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args._worker:
        responses(args.pad_width_mm / 1e3, args.rail_loss_factor, args._worker[0], args._worker[1] == "mirror")
        return
    folder = Path(tempfile.mkdtemp(prefix="wheelrail-identity-"))
    results = {}
    if args.full:
        runs = (("this", sys.executable, "mirror"), ("base", sys.executable, "full"))
    else:
        runs = (("this", sys.executable, "mirror"), ("base", str(args.base.resolve() / ".venv" / "bin" / "python"), ""))
    for name, python, how in runs:
        path = folder / f"{name}.npz"
        subprocess.run(
            [python, str(HERE), "--full", "--pad-width-mm", str(args.pad_width_mm),
             "--rail-loss-factor", str(args.rail_loss_factor), "--_worker", str(path), how or "mirror"],
            check=True,
        )  # fmt: skip
        results[name] = np.load(path)
    new, old = results["this"], results["base"]
    if not (np.array_equal(new["counts"], old["counts"]) and np.array_equal(new["offsets"], old["offsets"])):
        raise SystemExit("the two checkouts store different wedges: not comparable")
    against = "every position integrated" if args.full else str(args.base)
    print(
        f"this checkout against {against}: pad width {args.pad_width_mm:g} mm, rail loss factor "
        f"{args.rail_loss_factor:g}; "
        f"{old['data'].shape[0]} stored points x (w, theta)"
    )
    for column, label in ((0, "w"), (1, "theta")):
        diff = np.max(np.abs(new["data"][:, column] - old["data"][:, column]))
        print(f"  {label:5s}: max |new - base| / max |base| = {diff / np.max(np.abs(old['data'][:, column])):.2e}")
    overall = np.max(np.abs(new["data"] - old["data"])) / np.max(np.abs(old["data"]))
    print(f"  all  : {overall:.2e}   (acceptance: <= 1e-9)")
    for path in folder.iterdir():
        path.unlink()
    folder.rmdir()


if __name__ == "__main__":
    main()
