"""Plain JSON values from numpy-laden summaries: one conversion for the CLI, studies and recordings."""

from __future__ import annotations

import json
import math

import numpy as np


def json_ready(value):
    """Arrays to lists, numpy scalars to Python numbers, non-finite floats to ``None`` (strict JSON).

    Dicts get string keys; lists and tuples are converted element by element; anything else passes.
    """
    if isinstance(value, dict):
        return {str(k): json_ready(v) for k, v in value.items()}
    if isinstance(value, np.ndarray):
        return [json_ready(v) for v in value.tolist()]
    if isinstance(value, list | tuple):
        return [json_ready(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def strict_json(value, **options) -> str:
    """``value`` as strict JSON text (via :func:`json_ready`: no ``Infinity`` or ``NaN``; they read back as null).

    Every metadata string the package writes (run files, recordings, study summaries) goes through here;
    ``options`` are :func:`json.dumps`'s (``indent``, ``sort_keys``).
    """
    return json.dumps(json_ready(value), allow_nan=False, **options)
