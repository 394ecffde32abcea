"""A noise component is one entry of core's registry (wheelrail.core.noise.components): one registered component
(a rail damper radiating a quarter of the rail's power) reaches the chain, the JSON and CSV outputs, the command
line's table, the explorer's curves and table, and leaves with its entry."""

from __future__ import annotations

import functools
import json
import math

import numpy as np
import pytest

from wheelrail.cli.dispatch import main
from wheelrail.core.drawing.palette import OKABE_ITO
from wheelrail.core.engine import simulate
from wheelrail.core.errors import WheelrailError
from wheelrail.core.noise import run_noise as run_noise_module
from wheelrail.core.noise.components import (
    NoiseComponent,
    component,
    component_names,
    register_component,
    sound_power_parts,
    unregister_component,
)
from wheelrail.core.noise.run_noise import run_noise
from wheelrail.core.noise.twins import NoiseNumerics, track_noise_model
from wheelrail.core.parameters import ModelParameters
from wheelrail.core.spectra.levels import energy_sum

SMALL = NoiseNumerics(track_bays=40, elements_per_bay=4, points_per_band=1)  # coarse: the plumbing, not the physics
QUARTER_DB = 10 * math.log10(0.25)


def _quarter_of_the_rail(chain):
    return 0.25 * component("rail").radiation(chain)


DAMPER = NoiseComponent(
    name="rail_damper",
    label="rail damper",
    colour=OKABE_ITO["bluish green"],
    driven_by="force",
    response=component("rail").response,
    radiation=_quarter_of_the_rail,
)


@pytest.fixture(scope="module")
def short_run():
    return simulate("corrugated-rail", model="hertz", line=0, length=0.6)


@pytest.fixture
def damper():
    register_component(DAMPER)
    try:
        yield DAMPER
    finally:
        unregister_component(DAMPER.name)


def test_a_registered_component_is_in_the_chain_and_its_outputs(short_run, damper, tmp_path, monkeypatch, capsys):
    noise = run_noise(short_run, numerics=SMALL)
    assert (
        list(noise.sound_power_db)
        == ["rail", "rail_lateral", "sleeper", "wheel", "rail_damper", "total"]
        == [*sound_power_parts()]
    )
    # the chain: a quarter of the rail's power in every band, and in the total
    np.testing.assert_allclose(noise.sound_power_db["rail_damper"], noise.sound_power_db["rail"] + QUARTER_DB)
    parts = [noise.sound_power_db[name] for name in component_names()]
    np.testing.assert_allclose(noise.sound_power_db["total"], energy_sum(*parts))
    track = track_noise_model(short_run.header.params, SMALL)
    np.testing.assert_allclose(track.transfer_db["rail_damper"], track.transfer_db["rail"] + QUARTER_DB)
    assert "rail_damper_transfer_dB" in track.to_dict()
    # the JSON and the CSV
    assert set(noise.to_dict()["sound_power_dB"]) == set(sound_power_parts())
    header = next(line for line in noise.csv_text().splitlines() if line.startswith("band,"))
    assert header == "band,centre_hz,force_dB_re_1N,rail_dB,rail_lateral_dB,sleeper_dB,wheel_dB,rail_damper_dB,total_dB"
    # the command line's JSON and table (its noise on the coarse track)
    monkeypatch.setattr(run_noise_module, "run_noise", functools.partial(run_noise, numerics=SMALL))
    short_run.save_npz(tmp_path / "run.npz")
    assert main(["noise", "--run", str(tmp_path / "run.npz"), "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["sound_power_dBA"]["rail_damper"] == pytest.approx(noise.sound_power_dba["rail_damper"])
    assert main(["noise", "--run", str(tmp_path / "run.npz")]) == 0
    table = capsys.readouterr().out
    assert "band Hz   force dB   rail rail_lateral sleeper  wheel rail_damper  total" in table
    assert f"rail_damper {noise.sound_power_dba['rail_damper']:.1f}" in table


def test_a_registered_component_is_in_the_explorers_curves_and_table(short_run, damper):
    from wheelrail.explorer.noise_tab import NoiseTab, power_curves

    noise = run_noise(short_run, numerics=SMALL)
    curves = power_curves({"hertz": noise}, "hertz", {})
    drawn = {label: (colour, style, levels) for label, colour, style, levels in curves}
    assert [label for label, *_ in curves][:6] == [f"hertz: {name}" for name in sound_power_parts()]
    colour, style, levels = drawn["hertz: rail_damper"]
    assert (colour, style) == (OKABE_ITO["bluish green"], "solid")
    np.testing.assert_allclose(levels, drawn["hertz: rail"][2] + QUARTER_DB)
    table = NoiseTab._totals(None, {"hertz": noise}, "hertz", {}, None, (40, 200.0), None).splitlines()
    assert table[0] == (
        "| L_WA, dB(A) | rail | rail, lateral | sleeper | rail damper | track | wheel (directive) | total | pass-by |"
    )
    row = table[2].split(" | ")
    dba = {name: value + 10 * math.log10(2) for name, value in noise.sound_power_dba.items()}
    assert row[4] == f"{dba['rail_damper']:.1f}"
    assert row[5] == f"{energy_sum(dba['rail'], dba['sleeper'], dba['rail_damper']):.1f}"  # the track: its parts


def test_the_component_leaves_with_its_entry(short_run):
    register_component(DAMPER)
    unregister_component(DAMPER.name)
    assert component_names() == ("rail", "rail_lateral", "sleeper", "wheel")
    noise = run_noise(short_run, numerics=SMALL)
    assert list(noise.sound_power_db) == ["rail", "rail_lateral", "sleeper", "wheel", "total"]
    assert "rail_damper_transfer_dB" not in track_noise_model(ModelParameters(), SMALL).to_dict()


@pytest.mark.parametrize(
    ("changes", "words"),
    [
        ({"name": "Rail damper"}, "lower-case letters, digits and _ only"),
        ({"name": "total"}, "the name of the sum of the components"),
        ({"driven_by": "speed"}, "driven_by 'speed'; one of ('force', 'roughness')"),
        ({"radiation": None}, "driven by force: give radiation"),
    ],
)
def test_a_component_that_cannot_be_is_one_clear_error(changes, words):
    fields = {"name": "damper", "label": "damper", "colour": "#000000", "driven_by": "force"}
    fields |= {"response": DAMPER.response, "radiation": DAMPER.radiation, **changes}
    with pytest.raises(WheelrailError, match="noise component") as raised:
        NoiseComponent(**fields)
    assert words in str(raised.value)


def test_a_taken_name_or_a_built_in_removal_is_refused():
    with pytest.raises(WheelrailError, match="already registered"):
        register_component(component("rail"))
    with pytest.raises(WheelrailError, match="cannot be removed"):
        unregister_component("wheel")
    with pytest.raises(WheelrailError, match="takes a NoiseComponent"):
        register_component("rail damper")


@pytest.mark.parametrize("bays", [20, 39])
def test_a_track_too_short_for_the_free_wave_is_one_clear_error(bays):
    # the free wave's decay is fitted 3 to 20 bays from the load in the middle: fewer than 40 bays have no 20th
    with pytest.raises(WheelrailError, match=f"track_bays must be at least 40 .*, got {bays}$"):
        NoiseNumerics(track_bays=bays)
