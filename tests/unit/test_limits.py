"""Memory bounds of a run (core/engine/memory.py): the estimate bounds the traced peak, absurd runs are refused."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from wheelrail.core.engine import memory as limits
from wheelrail.core.engine import prepare_run
from wheelrail.core.errors import WheelrailError


def _peaks(model, *lengths):
    """The traced peak of each 1 mm run, bytes, in a fresh interpreter (tests/traced_peaks.py: why)."""
    script = Path(__file__).parents[1] / "traced_peaks.py"
    done = subprocess.run(
        [sys.executable, str(script), model, "1e-3", *map(str, lengths)], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.splitlines()[-1])


@pytest.mark.parametrize(("model", "short", "long"), [("hertz", 200.0, 600.0), ("2d", 200.0, 600.0), ("3d", 8.0, 16.0)])
@pytest.mark.slow
def test_estimate_bounds_the_traced_growth(model, short, long):
    # lengths long enough that the run's arrays outgrow the set-up's fixed peak (~18 MB: Green's functions)
    peak_short, peak_long = _peaks(model, short, long)
    measured = (peak_long - peak_short) / ((long - short) / 1e-3)
    n_lines = 25 if model == "3d" else 1  # cast-iron-wheel: 25 lines in the 3d window

    def estimate(length):
        n = length / 1e-3
        return limits.run_memory_bytes(
            n_elements=n,
            n_steps=n,
            n_lines=n_lines,
            window_columns=25 if model == "2d" else 0,
            pressure_elements=625 if model == "3d" else 0,
        )

    per_element = (estimate(long) - estimate(short)) / ((long - short) / 1e-3)
    # an estimate must never be below what the run takes, and not so far above that it refuses
    # reasonable runs: within a factor of two of the growth tracemalloc sees
    assert measured <= per_element <= 2 * measured


@pytest.mark.parametrize(
    ("model", "length", "keep"), [("hertz", 1e9, True), ("3d", 1e5, True), ("3d", 1e5, False), ("hertz", 1e306, True)]
)
def test_absurd_lengths_are_refused_with_the_figure(model, length, keep):
    with pytest.raises(
        WheelrailError, match=r"needs (about|more than) .*iB of memory.*, over the 2 GiB limit"
    ) as error:
        prepare_run("cast-iron-wheel", model=model, length=length, keep_pressure=keep)
    assert "about over" not in str(error.value)  # past 1e290 EiB the estimate is a bound, not a figure


@pytest.mark.parametrize("run_in", [1e308, 1e9])
def test_an_absurd_run_in_is_named_as_the_cause(run_in):
    # prepare_run(run_in_length=1e308) on a 1 m run said "a hertz run of 1000 steps needs about over 1e290 EiB
    # ...; shorten the run": the run was short, the run-in was not
    with pytest.raises(WheelrailError) as error:
        prepare_run("cast-iron-wheel", length=1.0, run_in_length=run_in)
    text = str(error.value)
    assert f"run-in of {run_in:.4g} m" in text and "shorten the run-in" in text, text
    assert "about over" not in text and "about more" not in text, text  # an estimate past 1e290 EiB is no figure


def test_pressure_maps_count_only_when_kept(monkeypatch):
    # 3d over 1000 m: 25 x 25 float32 maps are 2.3 GiB, over the 2 GiB default; without them 0.6 GiB
    from wheelrail.core.models import model_entry
    from wheelrail.core.parameters import ModelParameters

    entry, params = model_entry("3d"), ModelParameters()
    with pytest.raises(WheelrailError, match="2.33 GiB are the pressure maps kept"):
        limits.check_run_memory(entry, params, 1000.0, 1.0, keep_pressure=True)
    dropped = limits.check_run_memory(entry, params, 1000.0, 1.0, keep_pressure=False)  # 20 mm margins, 1 m run-in
    assert dropped == pytest.approx((1000 + 2 * 0.020 + 1.0) / 1e-3 * (200 + 16 * 25))
    monkeypatch.setenv(limits.MEMORY_LIMIT_ENV, "8")
    assert limits.memory_limit() == 8 * 1024**3
    assert limits.check_run_memory(entry, params, 1000.0, 1.0, keep_pressure=True) > dropped
    monkeypatch.setenv(limits.MEMORY_LIMIT_ENV, "lots")
    with pytest.raises(WheelrailError, match=limits.MEMORY_LIMIT_ENV):
        limits.memory_limit()
