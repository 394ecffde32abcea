"""The noise chain at a new contact position: wall and CPU time of ``track_noise_model`` for a second and a third
position in the process that computed the first, optionally side by side with another checkout (its ``.venv``).

For each wheel model (the directive's, the modal wheel's), at the chain's default numerics (240 bays, 16 elements
per bay, 20 points per band) and the paper's track: the centred contact (the first chain: the track, the wheel and
everything else), then the contact 10 mm off the rail's centreline and 10 mm along the tread (both offsets new),
then 20 mm off the centreline at the same tread offset (the railhead's offset only). Each checkout runs in a fresh
process of its own after one untimed process that fills the disk cache (the modal wheel's modes and radiation,
the rail section's radiation efficiencies); both share the cache folder (``WHEELRAIL_CACHE_DIR`` if set, else a
folder in the system's temporary directory). The load average is printed beside each line.

    python3 benchmarks/noise_position.py [--base /path/to/other/checkout] [--rounds 1]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

POSITIONS_MM = (("centred", 0.0, 0.0), ("second", 10.0, 10.0), ("railhead only", 20.0, 10.0))
WHEEL_MODELS = ("directive", "modal")


def session() -> dict:
    """This process's times: per wheel model and position, (wall s, CPU s) of its chain, in order."""
    from wheelrail.core.inputs.contact_position import ContactPosition
    from wheelrail.core.noise.twins import track_noise_model
    from wheelrail.core.parameters import ModelParameters

    out = {}
    for wheel_model in WHEEL_MODELS:
        for name, rail_mm, wheel_mm in POSITIONS_MM:
            position = ContactPosition(rail_offset=rail_mm * 1e-3, wheel_offset=wheel_mm * 1e-3)
            start, cpu = time.perf_counter(), time.process_time()
            track_noise_model(ModelParameters(), wheel_model=wheel_model, contact_position=position)
            out[f"{wheel_model} {name}"] = (time.perf_counter() - start, time.process_time() - cpu)
    return out


def _run(python: str, cache: str) -> dict:
    env = {**os.environ, "WHEELRAIL_CACHE_DIR": cache}
    done = subprocess.run([python, __file__, "--_session"], env=env, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--base", type=Path, help="another checkout (its .venv): side by side with it")
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--_session", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args._session:
        print(json.dumps(session()))
        return
    cache = os.environ.get("WHEELRAIL_CACHE_DIR") or str(Path(tempfile.gettempdir()) / "wheelrail-bench-noise")
    pythons = {"this": sys.executable}
    if args.base is not None:
        pythons["base"] = str(args.base.resolve() / ".venv" / "bin" / "python")
    print(f"cache: {cache}; {os.cpu_count()} cores; wall s / CPU s of each position's chain, in one process")
    _run(sys.executable, cache)  # fills the disk cache; not timed
    header = " ".join(f"{f'{name} ({r:g}, {w:g} mm)':>26}" for name, r, w in POSITIONS_MM)
    print(f"{'load':>5} {'code':>5} {'wheel':>9} {header}")
    for _ in range(args.rounds):
        for code, python in pythons.items():
            load = os.getloadavg()[0]
            times = _run(python, cache)
            for wheel_model in WHEEL_MODELS:
                pairs = [times[f"{wheel_model} {name}"] for name, _, _ in POSITIONS_MM]
                cells = " ".join(f"{f'{wall:.1f} / {cpu:.1f}':>26}" for wall, cpu in pairs)
                print(f"{load:5.1f} {code:>5} {wheel_model:>9} {cells}", flush=True)


if __name__ == "__main__":
    main()
