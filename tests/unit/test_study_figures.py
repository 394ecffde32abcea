"""The study figures name what they show: the configuration in the title, the swept value on the axis, units on
every y axis, curves by model or by track (core/study/figures.py), and the summary's tracks as they are."""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.drawing import palette
from wheelrail.core.inputs.declared import model_parameters
from wheelrail.core.noise.components import component_names, noise_components
from wheelrail.core.study.figures import study_figures
from wheelrail.core.study.noise_plan import noise_models
from wheelrail.core.study.tables import Table
from wheelrail.core.study.track_plan import track_description

PADS_MN_M = (60.0, 120.0)
SET = "corrugated-rail"


def _track_tables() -> list[Table]:
    """A track study's two tables as ``track_plan`` lays them out (two tracks: pad stiffness swept)."""
    rng = np.random.default_rng(1)
    noise = {"pad_stiffness_mn_m": np.array(PADS_MN_M)}
    force = {}
    centres = 1000.0 * 10.0 ** (np.arange(-13, 10) / 10)
    for model in noise_models():
        column = model.replace("-", "_")
        noise[f"{column}_force_dB"] = 120 + rng.random(2)
        for part in component_names():
            noise[f"{column}_{part}_LWA_dBA"] = 100 + rng.random(2)
        noise[f"{column}_LWA_dBA"] = 105 + rng.random(2)
        noise[f"{column}_LpAeq_dBA"] = 80 + rng.random(2)
        for k in range(2):
            force[f"{column}_track{k + 1}_db"] = 100 + rng.random(len(centres))
    return [
        Table(name=f"track_{SET}_noise", figure="track", panel=SET, band_centres=np.array([1.0, 2.0]),
              columns=noise, axis_name="track", title="per track"),
        Table(name=f"track_{SET}_force_levels", figure="track-force", panel=SET, band_centres=centres,
              columns=force, title="force levels"),
    ]  # fmt: skip


@pytest.fixture(scope="module")
def figures():
    caption = "100 km/h, 65 kN; every track the paper's but for its pad stiffness"
    return study_figures("track", _track_tables(), caption)


def test_the_track_summary_puts_the_swept_value_on_the_axis_and_units_on_every_panel(figures):
    figure = figures["track_track.png"]
    assert "every track the paper's but for its pad stiffness" in figure._suptitle.get_text().replace("\n", " ")
    width, height = figure.get_size_inches() * 110
    assert width >= 1200 and height >= 400  # not the 550 x 440 of one panel for 30 curves
    for ax in figure.axes:
        assert ax.get_xlabel() == "pad stiffness (MN/m)"
        assert [t.get_text() for t in ax.get_xticklabels()] == ["60", "120"]
        assert ax.get_ylabel() and ("dB re 1 N" in ax.get_ylabel()) != ("dB(A)" in ax.get_ylabel())
    legends = [text.get_text() for ax in figure.axes if ax.get_legend() for text in ax.get_legend().get_texts()]
    parts = {part.label for part in noise_components()}  # a part's legend is its label (rail_lateral: 'rail, lateral')
    assert set(noise_models()) | parts == set(legends)  # the models and the parts, no column names
    colours = {line.get_label(): line.get_color() for line in figure.axes[0].get_lines()}
    assert colours == {model: palette.MODEL_COLOURS[model] for model in noise_models()}


def test_the_track_force_figure_names_each_curve_by_its_track(figures):
    figure = figures["track_force_track.png"]
    for ax in figure.axes:
        labels = [text.get_text() for text in ax.get_legend().get_texts()]
        assert labels == [f"pad stiffness {k:g} MN/m" for k in PADS_MN_M]
        assert ax.get_ylabel() == "L_F (dB re 1 N)"
    assert sorted(ax.get_title().split(": ")[1] for ax in figure.axes) == sorted(noise_models())


def test_the_summary_states_what_the_tracks_share_and_each_ones_swept_values():
    base = model_parameters({"sleeper_mass": 150.0})
    tracks = [model_parameters({"pad_stiffness": k * 1e6}, base).track for k in PADS_MN_M]
    described = track_description(base, tracks)
    assert described["swept_track_inputs"] == ["pad_stiffness"]
    assert "pad_stiffness" not in described["track"] and described["track"]["sleeper_mass"] == 150.0
    assert described["tracks"] == [{"pad_stiffness": 60e6}, {"pad_stiffness": 120e6}]
    one = track_description(base, [base.track])  # one track: all of it, in both places
    assert one["track"]["pad_stiffness"] == 120e6 and one["tracks"] == [one["track"]] and not one["swept_track_inputs"]


def test_a_study_figure_is_titled_with_what_its_runs_share():
    from wheelrail.core.study import plan_study
    from wheelrail.core.study.runner import study_caption

    tracks = [model_parameters({"pad_stiffness": k * 1e6, "wheel_radius": 0.46}) for k in PADS_MN_M]
    plan = plan_study("track", [SET], length=1.0, params=tracks)
    assert study_caption("track", plan) == (
        "100 km/h, 65 kN; wheel radius 460 mm; every track the paper's but for its pad stiffness"
    )
    plan = plan_study("noise", [SET], length=2.0, params=model_parameters({"sleeper_mass": 150.0}))
    assert study_caption("noise", plan) == "65 kN; the track with sleeper mass 150 kg (else the paper's)"
