"""Bad input to the contact models gives one clear WheelrailError line (docs/user_guide.md, Errors)."""

import numpy as np
import pytest

from wheelrail.core.contact import (
    HalfSpaceWindow,
    average_roughness,
    hertz_approach,
    hertz_constant,
    hertz_force,
    solve_coupled_contact,
    solve_normal_contact,
    winkler_contact,
    winkler_equivalent_roughness,
)
from wheelrail.core.errors import WheelrailError


def sphere(n=24, dx=1e-3):
    c = (np.arange(n) - (n - 1) / 2) * dx
    return (c[:, None] ** 2 + c[None, :] ** 2) / (2 * 0.39)


def one_line(excinfo) -> str:
    message = str(excinfo.value)
    assert "\n" not in message
    return message


def test_non_finite_gap():
    gap = sphere()
    gap[3, 5] = np.nan
    with pytest.raises(WheelrailError, match=r"gap must be finite.*element \(3, 5\)") as excinfo:
        solve_normal_contact(gap, 1e-3, load=65e3)
    one_line(excinfo)


@pytest.mark.parametrize("gap", [np.zeros((0, 0)), np.zeros((1, 1)), np.zeros((1, 24)), np.zeros(24)])
def test_empty_or_degenerate_window(gap):
    with pytest.raises(WheelrailError, match="gap") as excinfo:
        solve_normal_contact(gap, 1e-3, load=65e3)
    one_line(excinfo)


def test_window_too_small_for_the_load():
    with pytest.raises(WheelrailError, match="window is too small for the load") as excinfo:
        solve_normal_contact(sphere(6), 1e-3, load=65e3)
    one_line(excinfo)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"element_size": 0.0}, "element_size must be positive"),
        ({"element_size": -1e-3}, "element_size must be positive"),
        ({"load": 0.0}, "load must be positive"),
        ({"load": float("inf")}, "load must be positive"),
        ({"contact": {"poisson_ratio": 0.3}}, "contact must be ContactParameters"),
        ({"max_iterations": 0}, "max_iterations"),
        ({"initial": np.zeros((3, 3), dtype=bool)}, "initial must be"),
    ],
)
def test_bad_parameters(kwargs, match):
    arguments = {"element_size": 1e-3, "load": 65e3} | kwargs
    element_size = arguments.pop("element_size")
    with pytest.raises(WheelrailError, match=match):
        solve_normal_contact(sphere(), element_size, **arguments)


def test_coupled_bad_compliance_and_approach():
    with pytest.raises(WheelrailError, match="compliance must be finite and >= 0"):
        solve_coupled_contact(sphere(), 1e-3, approach_known=1e-5, compliance=-1.0)
    with pytest.raises(WheelrailError, match="approach_known must be finite"):
        solve_coupled_contact(sphere(), 1e-3, approach_known=np.nan, compliance=0.0)


def test_hertz_and_winkler_inputs():
    with pytest.raises(WheelrailError, match="hertz_constant: contact must be ContactParameters"):
        hertz_constant(0.39)
    with pytest.raises(WheelrailError, match="compression must be finite"):
        hertz_force([1e-6, np.nan], 1e11)
    with pytest.raises(WheelrailError, match="force must be >= 0"):
        hertz_approach(-1.0, 1e11)
    with pytest.raises(WheelrailError, match="at least 3 samples"):
        winkler_contact(1e-5, [0.0], 1e-3)
    with pytest.raises(WheelrailError, match="end of the 5-sample roughness segment"):
        winkler_contact(77e-6, np.zeros(5), 1e-3)
    with pytest.raises(WheelrailError, match="roughness must be finite"):
        winkler_equivalent_roughness([0.0, np.inf, 0.0, 0.0], 1e-3)
    with pytest.raises(WheelrailError, match="boundary must be one of"):
        average_roughness(np.zeros(10), 1e-3, boundary="reflect")
    with pytest.raises(WheelrailError, match="too large"):
        # a 2 mm half window under a 5.5 mm wide nominal contact: the bedding contact must reach the end
        winkler_equivalent_roughness(np.zeros(100), 1e-3, half_window=2e-3)


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: HalfSpaceWindow((1, 24), 1e-3), "at least 2 x 2"),
        (lambda: HalfSpaceWindow(24, 1e-3), "shape must be two integers"),
        (lambda: HalfSpaceWindow((24, 24), 0.0), "element_size must be positive"),
        (lambda: HalfSpaceWindow((24, 24), 1e-3, max_iterations=0), "max_iterations"),
        (lambda: HalfSpaceWindow((24, 24), 1e-3).solve(sphere(12), load=65e3), r"window's shape \(24, 24\)"),
        (lambda: HalfSpaceWindow((24, 24), 1e-3).solve(sphere(), load=-1.0), "load must be positive"),
        (
            lambda: HalfSpaceWindow((24, 24), 1e-3).solve_coupled(sphere(), approach_known=1e-5, compliance=-1.0),
            "compliance must be finite and >= 0",
        ),
        (lambda: HalfSpaceWindow((24, 24), 1e-3).start_from(np.ones((3, 3), dtype=bool)), "contact must be"),
    ],
)
def test_half_space_window_inputs(make, match):
    with pytest.raises(WheelrailError, match=match) as excinfo:
        make()
    one_line(excinfo)
