"""How a run is built: one margin and length rule, the lines a lateral window can use."""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.engine import prepare_run
from wheelrail.core.engine.track_lines import run_margin, usable_length, window_lines
from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import ContactParameters, ModelParameters, RunParameters
from wheelrail.core.roughness import load_roughness


def test_one_margin_and_one_default_length_for_every_model():
    rail = load_roughness("corrugated-rail")
    # 20 mm at 1 mm elements (the bedding pre-filter's 3a = 16.4 mm, rounded up); 16 mm + 4 elements
    # (the 3D window's half-width) would be less
    assert run_margin(1e-3) == pytest.approx(0.020)
    length = usable_length(rail, 1e-3)
    assert length == pytest.approx((rail.n_samples - 1) * rail.dx - 0.040)
    for model in ("hertz", "2d"):
        assert prepare_run(rail, model=model).n_steps == round(length / 1e-3)
    # wheel data repeat: one circumference
    wheel = load_roughness("sinter-wheel-1")
    assert usable_length(wheel, 1e-3) == pytest.approx(wheel.length)
    # the default run is the longest the data allow: one more element is refused
    with pytest.raises(WheelrailError, match="run needs more than the 7.999 m of rail roughness data"):
        prepare_run(rail, model="hertz", length=length + 1e-3)


def test_rail_data_too_short_for_the_margins_is_one_clear_error():
    rail = load_roughness("corrugated-rail")
    short = rail.with_heights(rail.heights[:, :40], note="40 mm")
    with pytest.raises(WheelrailError, match="too short for a run"):
        usable_length(short, 1e-3)


def test_window_lines_keep_the_patch_inside_the_data():
    rail = load_roughness("corrugated-rail")  # 19 lines over +-9 mm
    # a = 5.48 mm at 65 kN -> 6 mm of rows plus one free row: lines at most 2 mm from the middle
    assert window_lines(rail) == (-2, -1, 0, 1, 2)
    # a smaller patch at 25 kN (a = 4.0 mm): 5 mm of data needed, lines -4..4
    light = ModelParameters(contact=ContactParameters(preload=25e3))
    assert window_lines(rail, light) == tuple(range(-4, 5))
    with pytest.raises(WheelrailError, match=r"line 3: too close .* at 65 kN .*; accepted -2 to 2$"):
        prepare_run(rail, model="3d", line=3, length=0.05)
    # the one-line models are not limited
    assert prepare_run(rail, model="2d", line=9, length=0.05).n_steps == 50


@pytest.mark.parametrize("line", [-2, 2])
@pytest.mark.slow
def test_the_outermost_window_lines_run_without_reaching_the_window_edge(line):
    result = prepare_run(
        "corrugated-rail",
        model="3d",
        line=line,
        length=1.5,
        keep_pressure=False,
        params=ModelParameters(run=RunParameters()),
    ).run()
    assert result.n_steps == 1500 and np.all(np.isfinite(result.force))


def test_track_numerics_of_another_type_is_one_clear_error():
    # prepare_run(track_numerics="fine") ended in AttributeError deep in the moving Green's functions
    with pytest.raises(WheelrailError, match="prepare_run: track_numerics must be TrackNumerics or None, got str"):
        prepare_run("corrugated-rail", model="hertz", length=0.01, track_numerics="fine")


def _engine_calls_from_prepare(**options) -> dict[str, list[str]]:
    """The engine's functions that ``core/engine/prepare.py``'s own code calls while a run is prepared, per
    module of ``wheelrail.core.engine`` (prepare's helpers included, so a parameter's path is followed)."""
    import sys

    prepare = "wheelrail.core.engine.prepare"
    calls: dict[str, list[str]] = {}

    def profile(frame, event, _arg):
        caller = frame.f_back
        if event != "call" or caller is None or caller.f_globals.get("__name__") != prepare:
            return
        module = frame.f_globals.get("__name__", "")
        if module.startswith("wheelrail.core.engine.") and module != prepare and frame.f_code.co_name != "<module>":
            calls.setdefault(module.removeprefix("wheelrail.core.engine."), []).append(frame.f_code.co_name)

    sys.setprofile(profile)
    try:
        prepare_run("corrugated-rail", model="hertz", length=0.05, **options)
    finally:
        sys.setprofile(None)
    return calls


@pytest.mark.parametrize("run_in", [None, 0.01], ids=["steady start", "run-in given"])
def test_prepare_run_passes_through_each_engine_module_once(run_in):
    """``prepare_run`` asks ``history`` for the run-in (its length and start, which the memory check takes before
    the lines are laid), ``track_lines`` for the lines, then ``history`` once for the loop's arrays with the model
    prepared on them and the wheel settled: no module is gone back into for one more piece."""
    calls = _engine_calls_from_prepare(run_in_length=run_in)
    assert calls.get("track_lines") == ["track_roughness"], calls
    assert calls.get("history") == ["run_in", "run_history"], calls
    assert "kernels" not in calls and "laws.base" not in calls, calls
