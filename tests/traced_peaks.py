"""The traced peak memory of runs, each printed as bytes in one JSON list (run by the memory tests in a subprocess).

Run: python tests/traced_peaks.py MODEL ELEMENT_SIZE_M LENGTH_M [LENGTH_M ...]

The runs are the cast-iron-wheel's with a 0.1 m run-in. A fresh interpreter holds no other test's threads, and a
first 0.01 m run puts the fixed costs (Green's functions, compiled kernels) out of the way; a new track's cache entry
is written in a thread of its own, so the script waits for it before tracing (tracemalloc counts every thread's
allocations: with an empty cache the write overlapped the first traced 8 m ``3d`` run, 43.0 MB against 26.9 MB).
"""

import json
import sys
import tracemalloc

from wheelrail.core.engine import prepare_run
from wheelrail.core.files.cache import wait_for_writes
from wheelrail.core.parameters import ModelParameters, RunParameters


def peak(model: str, params: ModelParameters, length: float) -> int:
    tracemalloc.start()
    try:
        prepare_run("cast-iron-wheel", model=model, length=length, run_in_length=0.1, params=params).run()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


if __name__ == "__main__":
    model, element_size, *lengths = sys.argv[1:]
    params = ModelParameters(run=RunParameters(element_size=float(element_size)))
    peak(model, params, 0.01)
    wait_for_writes()
    print(json.dumps([peak(model, params, float(length)) for length in lengths]))
