"""The track's Green's functions of this checkout against another's (e.g. the commit before a change of the
integration): max |new - base| / max |base| of the stored responses before their float32 cast.

Each checkout integrates the default track's impulse responses (``TrackNumerics()``: every excitation position,
the whole wedge, float64) in a process of its own, with its own ``.venv``; the wedge's layout (counts, offsets)
must be the same. Run:

    python3 validation/track_newmark_identity.py --base /path/to/other/checkout [--pad-width-mm 150]
        [--rail-loss-factor 0.02]

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


def responses(pad_width: float, loss_factor: float, path: str) -> None:
    """Integrate the track's responses with the installed ``wheelrail`` (the checkout whose python runs this)
    and save data (float64), counts and offsets to ``path`` (.npz)."""
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
    data = stationary.integrate_responses(
        model, x_e, numerics.time_step, n_steps, numerics.store_every, nodes, counts, offsets, impulse=True
    )
    np.savez(path, data=np.asarray(data, dtype=np.float64), counts=counts, offsets=offsets)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--base", type=Path, required=True, help="the other checkout (run with its .venv)")
    parser.add_argument("--pad-width-mm", type=float, default=0.0)
    parser.add_argument("--rail-loss-factor", type=float, default=0.0)
    parser.add_argument("--_worker", nargs=1, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args._worker:
        responses(args.pad_width_mm / 1e3, args.rail_loss_factor, args._worker[0])
        return
    folder = Path(tempfile.mkdtemp(prefix="wheelrail-identity-"))
    results = {}
    for name, python in (("this", sys.executable), ("base", str(args.base.resolve() / ".venv" / "bin" / "python"))):
        path = folder / f"{name}.npz"
        subprocess.run(
            [python, str(HERE), "--base", str(args.base), "--pad-width-mm", str(args.pad_width_mm),
             "--rail-loss-factor", str(args.rail_loss_factor), "--_worker", str(path)],
            check=True,
        )  # fmt: skip
        results[name] = np.load(path)
    new, old = results["this"], results["base"]
    if not (np.array_equal(new["counts"], old["counts"]) and np.array_equal(new["offsets"], old["offsets"])):
        raise SystemExit("the two checkouts store different wedges: not comparable")
    print(
        f"track: pad width {args.pad_width_mm:g} mm, rail loss factor {args.rail_loss_factor:g}; "
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
