"""The modal wheel driven off its nominal rolling circle: the mode shapes at a point of the tread, the receptance and
the surface velocity through them (a single mode by hand), the axial modes a radial force there drives, and the
offsets refused."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.modal_wheel import WheelProfile, contact_receptance, mean_square_velocity, wheel_modes
from wheelrail.core.modal_wheel.receptance import tread_point, tread_shapes

COARSE = 0.016  # m: a small mesh for fast tests (the default is 12 mm)
# a flat web on the rim's midplane, no flange: the contact at the rolling circle lies on the plane of symmetry
FLAT = WheelProfile(wheel_radius=0.46, web_offset=0.0, hub_outer_radius=0.13)


@pytest.fixture(scope="module")
def modes():
    return wheel_modes(FLAT, max_frequency=4e3, max_harmonic=4, element_size=COARSE)


def _tread_nodes(modes):
    """The mesh's nodes on the tread (r = R), by z."""
    nodes = modes.mesh.nodes
    on = np.flatnonzero(np.isclose(nodes[:, 0], FLAT.wheel_radius, atol=1e-12))
    return on[np.argsort(nodes[on, 1])]


def test_at_the_rolling_circle_the_shapes_are_the_contact_nodes(modes):
    np.testing.assert_array_equal(tread_shapes(modes, 0.0), modes.contact_shapes())
    np.testing.assert_array_equal(contact_receptance(modes, [500.0]).radial,
                                  contact_receptance(modes, [500.0], tread_offset=0.0).radial)  # fmt: skip


def test_the_shapes_at_a_tread_point_are_the_edges_interpolation(modes):
    # at a node of the tread: that node's shapes (the quadratic edge is exact there)
    nodes = modes.mesh.nodes
    tread = _tread_nodes(modes)
    node = tread[np.argmin(np.abs(nodes[tread, 1] - 0.012))]
    offset = float(nodes[node, 1])
    np.testing.assert_allclose(tread_shapes(modes, offset)[:, 0], modes.shapes[:, 3 * node], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(tread_shapes(modes, offset)[:, 1], modes.shapes[:, 3 * node + 1], rtol=1e-12, atol=1e-15)
    # between nodes: the three nodes of the edge and Lagrange's quadratic weights, by hand
    edge, weights = tread_point(modes, 0.3 * offset)
    z = nodes[edge, 1]
    s = 2 * (0.3 * offset - z[0]) / (z[2] - z[0]) - 1
    assert z[0] <= 0.3 * offset <= z[2] and np.isclose(z[1], 0.5 * (z[0] + z[2]))
    np.testing.assert_allclose(weights, [s * (s - 1) / 2, 1 - s**2, s * (s + 1) / 2], rtol=1e-12)
    hand = modes.shapes[:, 3 * edge] @ weights
    np.testing.assert_allclose(tread_shapes(modes, 0.3 * offset)[:, 0], hand, rtol=1e-12)


def test_one_mode_by_hand_the_receptance_and_the_velocity_go_through_the_points_radial_shape(modes):
    # a single axial mode (n = 2, web bending): alpha_rr(y) = phi_r(y)^2 / (w_m^2 (1 + i eta) - w^2), and its
    # surface velocity, without the static correction, scales with phi_r(y)^2: both exactly (1e-12)
    k = int(np.flatnonzero((modes.family == "axial") & (modes.harmonic == 2))[0])
    one = dataclasses.replace(modes, frequency=modes.frequency[[k]], harmonic=modes.harmonic[[k]],
                              family=modes.family[[k]], shapes=modes.shapes[[k]])  # fmt: skip
    f = np.array([0.5, 0.99, 1.3]) * modes.frequency[k]
    w, wm, eta = 2 * np.pi * f, 2 * np.pi * modes.frequency[k], 1e-4
    y = 0.01
    phi_r = tread_shapes(modes, y)[k, 0]
    hand = phi_r**2 / (wm**2 * (1 + 1j * eta) - w**2)
    np.testing.assert_allclose(contact_receptance(one, f, tread_offset=y).radial, hand, rtol=1e-12)
    at = {offset: mean_square_velocity(one, f, residual=False, tread_offset=offset) for offset in (0.0, y)}
    ratio = (phi_r / tread_shapes(modes, 0.0)[k, 0]) ** 2
    np.testing.assert_allclose(at[y].axial[:, 2], ratio * at[0.0].axial[:, 2], rtol=1e-10)
    np.testing.assert_allclose(at[y].radial[:, 2], ratio * at[0.0].radial[:, 2], rtol=1e-10)


def test_an_offset_drives_the_axial_modes_a_centred_radial_force_leaves_alone(modes):
    # the flat web on the midplane: an axial mode's radial displacement at the rolling circle is nearly zero
    # (symmetric about the midplane, to the mesh's asymmetry), 10 mm along the tread it is the rim's turn times
    # 10 mm; so its peak in the radial receptance appears, growing as y^2 (+-10 mm alike to first order)
    axial = np.flatnonzero((modes.family == "axial") & (modes.harmonic >= 2))
    centred, off, other = (np.abs(tread_shapes(modes, y)[axial, 0]) for y in (0.0, 0.01, -0.01))
    assert np.all(off > 20 * centred)
    np.testing.assert_allclose(off, other, rtol=0.1)  # the rim turns about its midplane: +-y alike
    k = axial[0]
    f = np.array([modes.frequency[k]])
    peak = {y: abs(contact_receptance(modes, f, tread_offset=y).radial[0]) for y in (0.0, 0.01, 0.02)}
    assert peak[0.01] > 100 * peak[0.0]
    assert peak[0.02] == pytest.approx(4 * peak[0.01], rel=0.15)  # phi_r ~ theta y: the peak ~ y^2


@pytest.mark.parametrize(
    ("offset", "words"),
    [
        (0.05, "-40 to 40"),  # beyond the declared range
        (float("nan"), "not a number"),
    ],
)
def test_an_offset_beyond_its_range_is_refused_in_one_line(modes, offset, words):
    from wheelrail.cli.commands._common import cli_error_names

    with pytest.raises(WheelrailError) as caught:
        tread_shapes(modes, offset)
    assert caught.value.parameter == "contact_offset_wheel"
    text = caught.value.render(cli_error_names())
    assert "\n" not in text and "--contact-offset-wheel-mm" in text
    assert words in text


def test_an_offset_off_this_wheels_tread_is_refused_with_its_own_range(modes):
    # a 135 mm rim: the contact within 5 mm of its edges, so -62.5 to 62.5 mm; a 100 mm rim: -45 to 45 mm
    narrow = WheelProfile(wheel_radius=0.46, web_offset=0.0, hub_outer_radius=0.13, tyre_width=0.1, contact_offset=0.03)
    small = wheel_modes(narrow, max_frequency=1e3, max_harmonic=1, element_size=COARSE)
    with pytest.raises(WheelrailError) as caught:
        tread_shapes(small, 0.02)  # 50 mm from the midplane: beyond the 45 mm
    assert caught.value.parameter == "contact_offset_wheel"
    assert caught.value.maximum == pytest.approx(0.015)
    assert tread_shapes(small, 0.015).shape == (len(small.frequency), 2)
