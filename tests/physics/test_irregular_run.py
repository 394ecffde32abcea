"""Discrete irregularities through a run: the parameters and header that carry them, each model's treatment (the
surface for 2d and 3d, the wheel-centre trajectory or the raw profile for the Hertz models), loss of contact, the
impact summary, and the Hertz models against the independent impact simulation (validation/impact_reference.py)."""

import numpy as np
import pytest

from wheelrail.core.engine import impact_summary, prepare_run, simulate
from wheelrail.core.engine.results import RunHeader
from wheelrail.core.errors import WheelrailError
from wheelrail.core.irregularities import DippedWeld, RailJoint, Squat, WheelFlat, flat_depth
from wheelrail.core.parameters import KMH, ModelParameters, RunParameters, as_dict, from_dict
from wheelrail.core.roughness import RoughnessSet

BAY = ModelParameters().track.support.sleeper_spacing
RADIUS = ModelParameters().contact.radius_along
# the independent reference (validation/impact_reference.py, docs/validation.md): a 50 mm rounded flat at midspan
# on a smooth rail, 65 kN: peak force (kN) per speed (km/h); contact lost 0.25 ms at 100 km/h
REFERENCE_PEAK_KN = {30.0: 97.6, 60.0: 116.2, 100.0: 155.1}


def _smooth(length=3 * BAY + 0.1, lines=19):
    return RoughnessSet.smooth(length, lines=lines)


def _params(items, speed_kmh=100.0, element_size=1e-3, irregularity_input="trajectory"):
    run = RunParameters(speed=speed_kmh * KMH, element_size=element_size, irregularities=tuple(items),
                        irregularity_input=irregularity_input)  # fmt: skip
    return ModelParameters(run=run)


FLAT = WheelFlat(length=0.05, position=1.5 * BAY)  # its centre first meets the rail at a midspan


def _flat_run(model="hertz", speed_kmh=100.0, element_size=1e-3, irregularity_input="trajectory", items=(FLAT,)):
    params = _params(items, speed_kmh, element_size, irregularity_input)
    length = round(2 * BAY / element_size) * element_size
    return simulate(_smooth(), model=model, params=params, length=length)


def test_the_irregularities_travel_in_the_parameters_and_every_header_states_them():
    params = _params([FLAT])
    assert params.run.irregularities == (FLAT,)
    values = as_dict(params)
    assert values["run"]["irregularities"] == [
        {"kind": "flat", "length": 0.05, "depth": None, "shape": "rounded", "position": 1.5 * BAY}
    ]
    assert from_dict(ModelParameters, values) == params
    run = prepare_run(_smooth(), model="hertz", params=params, length=2 * BAY)
    header = run.header.to_dict()
    assert header["parameters"]["run"]["irregularities"][0]["kind"] == "flat"
    assert RunHeader.from_dict(header) == run.header
    assert f"flat 50 mm rounded at x = {1.5 * BAY:g} m" in run.header.description()
    assert "Hertz on the trajectory" in run.header.description()
    # a run without irregularities says nothing of them
    assert "irregularities" not in prepare_run(_smooth(), length=0.1).header.description()


@pytest.mark.parametrize(
    ("items", "key"),
    [
        ([WheelFlat(length=0.05, position=0.01)], "flat_position"),  # outside the run (it starts at 20 mm)
        ([WheelFlat(length=1.0, position=1.5 * BAY)], "flat_length"),  # longer than the wheel's diameter can hold
        ([RailJoint(position=1.5 * BAY, gap=BAY)], "joint_gap"),  # as wide as a sleeper bay
    ],
)
def test_bad_geometry_is_refused_in_one_line_before_the_run_is_built(items, key):
    with pytest.raises(WheelrailError) as error:
        prepare_run(_smooth(), params=_params(items), length=2 * BAY)
    assert error.value.parameter == key and "\n" not in str(error.value)


def test_bad_irregularity_parameters_are_one_error_each():
    with pytest.raises(WheelrailError, match="WheelFlat, RailJoint"):
        RunParameters(irregularities=(1.0,))
    with pytest.raises(WheelrailError) as error:
        RunParameters(irregularity_input="envelope")
    assert error.value.parameter == "irregularity_input"


def test_hertz_on_the_trajectory_bridges_the_flat_and_on_the_raw_profile_does_not():
    trajectory, raw = _flat_run(), _flat_run(irregularity_input="raw")
    depth = flat_depth(FLAT, RADIUS)
    # what the spring is driven by: the raw profile reaches the full depth; a rigid wheel bridges the rounded flat
    assert raw.equivalent_roughness.min() == pytest.approx(-depth, rel=1e-3)
    assert -depth < trajectory.equivalent_roughness.min() < -0.5 * depth
    # the surface recorded is the flat itself either way
    assert trajectory.roughness.min() == pytest.approx(-depth, rel=1e-3)
    for result in (trajectory, raw):  # the wheel leaves the rail and lands: F = 0 there, never NaN or below 0
        assert np.all(np.isfinite(result.force)) and result.force.min() == 0.0
        assert result.loss_of_contact_steps > 0


def test_the_2d_model_sees_the_surface_and_loses_contact_over_the_flat():
    result = _flat_run(model="2d")
    assert result.equivalent_roughness.min() == pytest.approx(-flat_depth(FLAT, RADIUS), rel=1e-3)
    assert np.all(np.isfinite(result.force)) and result.force.min() == 0.0
    assert result.force.max() > 2.0 * ModelParameters().contact.preload


def test_a_hertz_model_on_the_line_does_not_see_a_squat_beside_it():
    squat = Squat(position=1.5 * BAY, length=0.03, width=0.006, depth=2e-4, lateral_position=0.006)
    result = _flat_run(items=(squat,))
    assert np.max(np.abs(result.equivalent_roughness)) == 0.0


@pytest.mark.slow
def test_the_3d_model_sees_a_squat_narrower_than_the_patch_beside_its_line():
    # 3 mm wide, 3 mm off the line: the Hertz spring on the line sees nothing; the 3D patch (b = 5.5 mm) loses
    # part of its area over it and the force changes
    squat = Squat(position=1.5 * BAY, length=0.02, width=0.003, depth=5e-5, lateral_position=0.003)
    with_squat = _flat_run(model="3d", items=(squat,))
    params = _params(())
    smooth = simulate(_smooth(), model="3d", params=params, length=2 * BAY)
    assert np.all(np.isfinite(with_squat.force))
    assert np.max(np.abs(with_squat.force - smooth.force)) > 1e3
    assert with_squat.contact_area.min() < 0.95 * smooth.contact_area.min()


def test_the_impact_summary_finds_the_flat_and_converges_when_the_step_is_halved():
    # the rule: the force above 1.2 P or without contact, stretches closer than 0.1 m joined; the time without
    # contact between the crossings of F = 0 placed within their steps
    coarse, fine = (impact_summary(_flat_run(element_size=dx)) for dx in (1e-3, 5e-4))
    for summary in (coarse, fine):
        assert len(summary.impacts) == 1
        impact = summary.impacts[0]
        assert FLAT.position - 0.03 < impact.position < FLAT.position + 0.03
        assert impact.peak == summary.peak and summary.minimum == 0.0
        assert impact.time_without_contact == pytest.approx(summary.time_without_contact)
    assert fine.peak == pytest.approx(coarse.peak, rel=0.01)
    assert fine.time_without_contact == pytest.approx(coarse.time_without_contact, rel=0.01)
    values = fine.to_dict()
    assert values["impacts"][0]["position_m"] == fine.impacts[0].position and "1.2 P" in values["rule"]


def test_no_impact_on_a_smooth_rail():
    summary = impact_summary(simulate(_smooth(), length=BAY))
    assert summary.impacts == () and summary.time_without_contact == 0.0


def test_hertz_on_the_trajectory_matches_the_independent_impact_simulation_at_100_kmh():
    summary = impact_summary(_flat_run(speed_kmh=100.0))
    assert summary.peak / 1e3 == pytest.approx(REFERENCE_PEAK_KN[100.0], rel=0.05)
    assert summary.time_without_contact > 0.0  # the reference: 0.25 ms


@pytest.mark.slow
@pytest.mark.parametrize("speed_kmh", [30.0, 60.0])
def test_hertz_on_the_trajectory_matches_the_independent_impact_simulation(speed_kmh):
    summary = impact_summary(_flat_run(speed_kmh=speed_kmh))
    assert summary.peak / 1e3 == pytest.approx(REFERENCE_PEAK_KN[speed_kmh], rel=0.05)
    assert summary.time_without_contact == 0.0  # contact is kept below 100 km/h


def test_an_irregularity_widens_the_window_by_how_far_it_moves_the_contact():
    # over a rounded flat the wheel rests on its flanks, up to R pi D / L from its centre (9.8 mm for 50 mm on
    # R = 0.39 m): the 3D window and the bedding grow by that along the rail, not across
    from wheelrail.core.engine.track_lines import window_half_elements

    plain, flat = window_half_elements(ModelParameters()), window_half_elements(_params([FLAT]))
    reach = RADIUS * np.pi * flat_depth(FLAT, RADIUS) / FLAT.length
    assert flat == (plain[0] + int(np.ceil(reach / 1e-3)), plain[1])


@pytest.mark.slow
def test_the_3d_model_loses_contact_over_the_flat_and_lands_again():
    wide = RoughnessSet.smooth(3 * BAY + 0.1, lines=41)  # 40 mm across: the patch at 2.4 P
    result = simulate(wide, model="3d", params=_params([FLAT]), length=2 * BAY)
    summary = impact_summary(result)
    assert np.all(np.isfinite(result.force)) and summary.minimum == 0.0 and summary.time_without_contact > 0
    assert result.contact_area[result.force == 0.0].max() == 0.0  # no patch while the wheel is in the air
    assert 2.0 < summary.peak / ModelParameters().contact.preload < 3.0


def test_a_run_without_irregularities_keeps_its_parameters_dict_and_so_its_cache_keys():
    # the recordings, cache keys and digests made of as_dict stay what they were before runs had irregularities
    assert set(as_dict(ModelParameters())["run"]) == {"speed", "element_size"}
    assert from_dict(ModelParameters, as_dict(ModelParameters())) == ModelParameters()
    raw = ModelParameters(run=RunParameters(irregularity_input="raw"))
    assert as_dict(raw)["run"]["irregularity_input"] == "raw" and from_dict(ModelParameters, as_dict(raw)) == raw


def _impact_reference():
    """validation/impact_reference.py as a module (its static solution of the geometry)."""
    import importlib.util
    import sys
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "validation" / "impact_reference.py"
    spec = importlib.util.spec_from_file_location("validation_impact_reference", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


@pytest.mark.slow
def test_at_walking_speed_the_force_follows_the_static_solution_of_the_geometry():
    # the reference's long gentle dip (3 mm over 1.8 m: nothing to bridge) at 5 km/h, centred at a midspan: the
    # run's force against the static solution at each position (wheel, FE track and Hertz spring in series,
    # validation/impact_reference.static_force), within 0.3 % of P (measured 0.11 kN; the suspension's damper and
    # the track's ringing under the moving load)
    reference = _impact_reference()
    centre = 3.5 * BAY
    flat_rail = RoughnessSet.smooth(7 * BAY)
    weld = DippedWeld(position=centre, length=1.8, depth=3e-3)
    result = simulate(flat_rail, params=_params([weld], speed_kmh=5.0), length=round(6 * BAY / 1e-3) * 1e-3)
    x, force = result.x[::50], result.force[::50]
    _, reference_centre, _ = reference.layout(70)
    static = reference.static_force(x - centre + reference_centre, kind="weld")
    assert static.max() - static.min() > 3e3  # the dip changes the static force by 3.4 kN
    assert np.max(np.abs(force - static)) < 0.003 * ModelParameters().contact.preload
