"""The irregularities' geometry and the wheel-centre trajectory against known answers (core/irregularities)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from wheelrail.core.irregularities import (
    DippedWeld,
    RailJoint,
    Squat,
    WheelFlat,
    flat_depth,
    raw_profile,
    surface_deviation,
    wheel_centre_trajectory,
)

R = 0.39  # m, the paper's wheel radius
DX = 1e-4  # m


def _line(length: float, start: float = 0.0) -> np.ndarray:
    return start + np.arange(int(round(length / DX)) + 1) * DX


def test_a_new_flat_puts_the_wheel_on_its_chord_exactly_its_depth_down():
    x = _line(0.4)
    flat = WheelFlat(length=0.05, shape="new", position=0.2)
    depth = flat_depth(flat, R)
    assert depth == pytest.approx(R - math.sqrt(R**2 - 0.025**2), rel=1e-15)  # the chord's sagitta
    trajectory = wheel_centre_trajectory(raw_profile([flat], x, wheel_radius=R), DX, R)
    centre = int(round(0.2 / DX))
    # while the chord lies on the rail the wheel sits on it: the centre is exactly D low (rounding only)
    assert trajectory[centre] == pytest.approx(-depth, abs=1e-15)
    assert trajectory.min() == pytest.approx(-depth, abs=1e-15)


def _rounded_reference(depth: float, length: float) -> float:
    """The continuous z_c at a rounded flat's centre: the wheel touches both flanks where the circle's slope
    equals the profile's, r'(s) = s / sqrt(R^2 - s^2) (brentq), or rests on its edges."""

    def lift(s):
        return -0.5 * depth * (1 + math.cos(2 * math.pi * s / length)) - (R - math.sqrt(R**2 - s**2))

    def slope(s):
        return depth * math.pi / length * math.sin(2 * math.pi * s / length) - s / math.sqrt(R**2 - s**2)

    touching = brentq(slope, 1e-6, 0.5 * length - 1e-9)  # slope > 0 near the centre, < 0 at the edge
    return max(lift(touching), lift(0.5 * length))


@pytest.mark.parametrize("length", [0.03, 0.05, 0.1])
def test_a_rigid_wheel_bridges_a_rounded_flat_and_stays_shallower_than_its_depth(length):
    x = _line(0.4)
    flat = WheelFlat(length=length, position=0.2)
    depth = flat_depth(flat, R)
    assert depth == pytest.approx(length**2 / (16 * R))  # the default depth
    trajectory = wheel_centre_trajectory(raw_profile([flat], x, wheel_radius=R), DX, R)
    reference = _rounded_reference(depth, length)
    assert -depth < reference < -0.9 * depth
    # the grid's maximum is below the continuous one by at most max|z''| DX^2 / 8 (< 2 nm: curvature
    # (2 pi^2 D / L^2 + 1/R) < 6 / m), and the touching point can fall between samples
    assert trajectory[int(round(0.2 / DX))] == pytest.approx(reference, abs=2e-9)
    assert trajectory.min() > -depth


def test_a_convex_bump_gentler_than_the_wheel_is_followed_on_its_parallel_curve():
    # a cosine bump 20 um high and 60 mm long curves upwards at most 10e-6 (2 pi / 0.06)^2 = 0.11 / m < 1/R: the
    # wheel touches it at one point everywhere, so its centre runs on the bump's parallel curve at distance R,
    # (xi - R r' / n, r + R / n - R) with n = sqrt(1 + r'^2): the bump lifted by R r'^2 / 2 (up to 0.2 um) and
    # shifted by R r'. Reference on a 100x finer xi; the grid's maximum is low by at most max|z''| DX^2 / 8 (< 4 nm)
    x = _line(0.3)

    def bump(s):
        return 10e-6 * (1 + np.cos(2 * np.pi * (s - 0.15) / 0.06)) * (np.abs(s - 0.15) < 0.03)

    xi = np.linspace(0.0, 0.3, 300_001)
    slope = -10e-6 * 2 * np.pi / 0.06 * np.sin(2 * np.pi * (xi - 0.15) / 0.06) * (np.abs(xi - 0.15) < 0.03)
    norm = np.sqrt(1 + slope**2)
    centre_x, centre_z = xi - R * slope / norm, bump(xi) + R / norm - R
    trajectory = wheel_centre_trajectory(bump(x), DX, R)
    inner = (x > 0.01) & (x < 0.29)
    np.testing.assert_allclose(trajectory[inner], np.interp(x, centre_x, centre_z)[inner], rtol=0, atol=4e-9)
    assert np.max(np.abs(trajectory - bump(x))) > 1e-7  # the shift is seen (r' up to 1 mrad: ~0.2 um)


def test_a_step_up_is_climbed_along_the_wheels_circle():
    x = _line(0.2)
    step = 0.5e-3
    index = 1000  # the step at x = 0.1 m, on a sample
    profile = np.where(np.arange(x.size) >= index, step, 0.0)
    trajectory = wheel_centre_trajectory(profile, DX, R)
    distance = x[index] - x[:index]
    climb = np.maximum(0.0, step - (R - np.sqrt(R**2 - distance**2)))
    np.testing.assert_allclose(trajectory[:index], climb, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(trajectory[index:], step)
    assert climb[-200] == 0.0 and 0.0 < climb[-100] < step  # the climb starts sqrt(2 R h) = 19.7 mm before


def test_a_flat_comes_back_every_revolution():
    circumference = 2 * math.pi * R
    step = circumference / round(circumference / DX)  # a whole number of samples per revolution
    x = np.arange(int(2.2 * circumference / step)) * step
    flat = WheelFlat(length=0.05, position=400 * step)
    profile = raw_profile([flat], x, wheel_radius=R)
    trajectory = wheel_centre_trajectory(profile, step, R)
    per_turn = round(circumference / step)
    near = np.arange(800)  # the first meeting and 15 mm either side of it
    for k in (1, 2):
        np.testing.assert_allclose(trajectory[near + k * per_turn], trajectory[near], rtol=0, atol=1e-12)
    assert trajectory[400] < -0.9 * flat_depth(flat, R)
    assert np.count_nonzero(np.diff((profile < 0).astype(int)) == 1) == 3  # three meetings, no more


def test_several_irregularities_superpose_by_position_and_a_squat_only_on_its_lines():
    x, y = _line(2.0), np.array([-0.01, 0.0, 0.01, 0.02])
    weld = DippedWeld(position=0.5, length=0.3, depth=0.2e-3)
    joint = RailJoint(position=1.2, gap=0.01, step=0.1e-3, dip_angle=2e-3, dip_length=0.3)
    squat = Squat(position=0.5, length=0.03, width=0.02, depth=0.1e-3, lateral_position=0.01)
    grid = surface_deviation([weld, joint, squat], x, y, wheel_radius=R)
    assert grid.shape == (4, x.size)
    at = int(round(0.5 / DX))
    np.testing.assert_allclose(grid[:, at], [-0.2e-3, -0.2e-3, -0.3e-3, -0.2e-3], rtol=1e-12)
    alone = surface_deviation([weld], x, y, wheel_radius=R) + surface_deviation([joint], x, y, wheel_radius=R)
    np.testing.assert_allclose(grid[[0, 3]], alone[[0, 3]], rtol=0, atol=1e-18)  # squat's lines aside
    # the joint: dipped ends alpha * dip_length = 0.6 mm below, the far side 0.1 mm higher, the gap bridged
    before, after = int(round((1.2 - 0.005) / DX)) - 1, int(round((1.2 + 0.005) / DX)) + 1
    assert grid[1, before] == pytest.approx(-0.6e-3, abs=3e-7)
    assert grid[1, after] == pytest.approx(0.1e-3 - 0.6e-3, abs=3e-7)
    assert grid[1, -1] == pytest.approx(0.1e-3)
    line = raw_profile([joint], x, wheel_radius=R)
    trajectory = wheel_centre_trajectory(line, DX, R)
    assert trajectory.min() > -0.6e-3 - 0.01**2 / (8 * R) - 1e-9  # never into the gap deeper than its sag
