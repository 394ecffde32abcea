import math

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import (
    ContactParameters,
    RunParameters,
    SupportParameters,
    TrackNumerics,
    WheelParameters,
)


def test_hertz_values_of_spec():
    # Hertz check (docs/physics.md, Contact models): a = 5.482 mm, p0 = 1032.6 MPa, approach 77.07 um at 65 kN.
    # Tolerance 0.05 %: these are closed-form expressions, the spec rounds to 4 digits.
    c = ContactParameters()
    assert c.hertz_radius() == pytest.approx(5.482e-3, rel=5e-4)
    assert c.hertz_peak_pressure() == pytest.approx(1032.6e6, rel=5e-4)
    assert c.hertz_approach() == pytest.approx(77.07e-6, rel=5e-4)
    # eq. (12)-(13): C_H delta^1.5 = P, exactly
    assert c.hertz_constant * c.hertz_approach() ** 1.5 == pytest.approx(c.preload, rel=1e-12)


def test_time_step_is_element_over_speed():
    run = RunParameters(speed=100 / 3.6, element_size=1e-3)
    assert run.time_step == pytest.approx(3.6e-5)


@pytest.mark.parametrize(
    ("cls", "name", "value", "unit"),
    [
        (WheelParameters, "unsprung_mass", -1.0, "kg"),
        (WheelParameters, "wheel_stiffness", 0.0, "N/m"),
        (SupportParameters, "pad_stiffness", math.nan, "N/m"),
        (SupportParameters, "sleeper_mass", 0.0, "kg"),
        (RunParameters, "speed", -10.0, "m/s"),
        (RunParameters, "element_size", 0.0, "m"),
        (ContactParameters, "preload", -65e3, "N"),
        (TrackNumerics, "time_step", math.inf, "s"),
    ],
)
def test_bad_parameter_names_itself_and_unit(cls, name, value, unit):
    with pytest.raises(WheelrailError) as info:
        cls(**{name: value})
    message = str(info.value)
    assert name in message and unit in message and "\n" not in message


def test_poisson_ratio_range():
    with pytest.raises(WheelrailError, match="poisson_ratio"):
        ContactParameters(poisson_ratio=0.5)


def test_parameters_are_frozen():
    with pytest.raises(AttributeError):
        WheelParameters().unsprung_mass = 1.0  # type: ignore[misc]


# --- elliptic patches ---------------------------------------------------------------------------------------

REAL = ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30)  # a worn wheel on a rail head
CONCAVE = ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30, wheel_transverse_radius=-0.5)


def test_default_geometry_is_the_papers_circle_to_the_bit():
    # the defaults must give the previous closed forms exactly (every earlier result depends on them)
    c = ContactParameters()
    assert c.circular and c.radius_along == c.radius_across == 0.39
    a, b = c.hertz_semi_axes()
    assert a == b == (3.0 * 65e3 * 0.39 / (4.0 * c.reduced_modulus)) ** (1.0 / 3.0)
    assert c.hertz_constant == 4.0 / 3.0 * c.reduced_modulus * math.sqrt(0.39)
    # both radii follow ``radius`` when unset (files written before they existed carry only it)
    assert (
        ContactParameters(radius=0.45).hertz_semi_axes()
        == ContactParameters(wheel_radius=0.45, rail_crown_radius=0.45).hertz_semi_axes()
    )


@pytest.mark.parametrize(
    "contact",
    [REAL, CONCAVE, ContactParameters(wheel_radius=0.2, rail_crown_radius=0.8)],
    ids=["0.46-on-0.30", "concave-tread", "wide"],
)
@pytest.mark.slow
def test_elliptic_hertz_against_quadrature_of_its_pressure(contact):
    """Johnson 4.2 checked without the elliptic integrals: the load is the integral of the ellipsoidal pressure,
    2/3 pi a b p0, and the approach is the Boussinesq displacement of that pressure at the centre,
    delta = p0 / (4 E*) * integral over theta of rho(theta), rho the ellipse's polar radius (a 1D integral,
    done here with 2000-point Gauss-Legendre: exact to round-off for this smooth periodic integrand).
    The semi-axis ratio is checked against the 3D solver in tests/physics/test_contact_models.py."""
    h = contact.hertz()
    a, b = h.semi_axis_along, h.semi_axis_across
    assert 2.0 / 3.0 * math.pi * a * b * h.peak_pressure == pytest.approx(contact.preload, rel=1e-12)
    nodes, weights = np.polynomial.legendre.leggauss(2000)
    theta = math.pi * (nodes + 1.0)
    rho = 1.0 / np.sqrt(np.cos(theta) ** 2 / a**2 + np.sin(theta) ** 2 / b**2)
    approach = h.peak_pressure / (4.0 * contact.reduced_modulus) * math.pi * np.sum(weights * rho)
    assert h.approach == pytest.approx(approach, rel=1e-10)
    assert contact.hertz_constant * h.approach**1.5 == pytest.approx(contact.preload, rel=1e-12)
    # a along the rail is the longer axis where the rolling radius is the larger relative radius
    assert (a > b) == (contact.radius_along > contact.radius_across)


def test_elliptic_hertz_tends_to_the_circle():
    # continuity at the circle: the elliptic branch 1e-9 away from equal radii agrees with the closed forms
    # to about the radii's own difference (no cancellation in K - E: Carlson's R_D form)
    near = ContactParameters(wheel_radius=0.39, rail_crown_radius=0.39 * (1 + 1e-9))
    circle = ContactParameters()
    assert not near.circular
    for got, want in zip(near.hertz(), circle.hertz(), strict=True):
        assert got == pytest.approx(want, rel=1e-8)


def test_semi_axes_scale_with_load_to_the_one_third():
    # a, b proportional to P^(1/3) and delta to P^(2/3) at fixed radii (so C = P / delta^1.5 is one constant)
    h1, h8 = REAL.hertz(10e3), REAL.hertz(80e3)
    assert h8.semi_axis_along / h1.semi_axis_along == pytest.approx(2.0, rel=1e-10)
    assert h8.semi_axis_across / h1.semi_axis_across == pytest.approx(2.0, rel=1e-10)
    assert h8.approach / h1.approach == pytest.approx(4.0, rel=1e-10)
    assert h8.constant == pytest.approx(h1.constant, rel=1e-10)


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"wheel_radius": -0.46}, "wheel_radius"),
        ({"rail_crown_radius": 0.0}, "rail_crown_radius"),
        ({"wheel_transverse_radius": 0.0}, "wheel_transverse_radius"),
        ({"wheel_transverse_radius": math.nan}, "wheel_transverse_radius"),
        ({"rail_crown_radius": 0.3, "wheel_transverse_radius": -0.3}, "surfaces conform"),
        ({"rail_crown_radius": 0.3, "wheel_transverse_radius": -0.2}, "surfaces conform"),
    ],
)
def test_bad_geometry_is_one_clear_error(kwargs, words):
    with pytest.raises(WheelrailError, match=words) as info:
        ContactParameters(**kwargs)
    assert "\n" not in str(info.value)


def test_old_files_with_only_radius_and_json_null_tread_read_back():
    from wheelrail.core.parameters import ModelParameters, as_dict, from_dict

    old = {"youngs_modulus": 210e9, "poisson_ratio": 0.3, "radius": 0.39, "preload": 65e3}
    assert from_dict(ContactParameters, old) == ContactParameters()
    written = as_dict(ModelParameters(contact=CONCAVE))
    written["contact"]["wheel_transverse_radius"] = None  # strict JSON writes the infinite default as null
    assert from_dict(ModelParameters, written).contact.wheel_transverse_radius == math.inf


def _parameter_classes():
    import dataclasses

    from wheelrail.core import parameters

    return [
        cls
        for cls in vars(parameters).values()
        if isinstance(cls, type) and dataclasses.is_dataclass(cls) and cls.__module__ == parameters.__name__
    ]


EXTREMES = [1e308, -1e308, 1e-308, -1e-308, math.inf, -math.inf, math.nan, 10**30, 10**400, -(10**400), True, "1"]


@pytest.mark.parametrize("value", EXTREMES, ids=repr)
def test_every_parameter_class_refuses_extreme_values_in_one_line_or_holds_a_usable_value(value):
    # every field of every parameter class, one at a time: a one-line WheelrailError naming the field, or an
    # object whose values are finite floats (a flat tread's infinite transverse radius aside) and whose Hertz
    # solution, where it has one, is finite: no ZeroDivisionError or OverflowError, then or later
    import dataclasses

    for cls in _parameter_classes():
        for item in dataclasses.fields(cls):
            try:
                made = cls(**{item.name: value})
            except WheelrailError as error:
                assert "\n" not in str(error) and item.name in str(error), (cls.__name__, item.name, str(error))
                continue
            kept = getattr(made, item.name)
            if item.name == "wheel_transverse_radius":
                assert isinstance(kept, float) and abs(kept) >= 0.05, kept
            else:
                assert isinstance(kept, int | float) and math.isfinite(kept) and abs(kept) < 1e20, (cls, item, kept)
            if isinstance(made, ContactParameters):
                assert all(math.isfinite(axis) and axis > 0 for axis in made.hertz_semi_axes())


def test_bounds_of_the_api_only_inputs_name_the_input_and_the_range():
    with pytest.raises(WheelrailError) as error:
        ContactParameters(youngs_modulus=1e308)
    assert str(error.value).startswith("ContactParameters.youngs_modulus 1e+308 Pa is outside the accepted")
    with pytest.raises(WheelrailError, match=r"TrackParameters.n_bays 1000000 is outside the accepted 4 to 1000"):
        from wheelrail.core.parameters import TrackParameters

        TrackParameters(n_bays=10**6)
    with pytest.raises(WheelrailError, match="WheelParameters.unsprung_mass"):
        WheelParameters(unsprung_mass=1e308)
    with pytest.raises(WheelrailError, match="ModelParameters.wheel must be a WheelParameters, got float"):
        from wheelrail.core.parameters import ModelParameters

        ModelParameters(wheel=1e308)
    with pytest.raises(WheelrailError, match="RunParameters.speed"):
        RunParameters(speed=10**400)
    # the paper's values and the stiff rail of the convergence tests stay accepted
    ContactParameters(youngs_modulus=100e9)
