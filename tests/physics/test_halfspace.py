"""3D elastic half-space contact (paper eqs. 8-11) against Hertz and the contact conditions."""

import numpy as np
import pytest

from wheelrail.core.contact import HalfSpaceWindow, influence_kernel, solve_coupled_contact, solve_normal_contact
from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import ContactParameters

CONTACT = ContactParameters()
LOAD = CONTACT.preload
RADIUS = CONTACT.radius


def sphere_gap(n: int, dx: float) -> tuple[np.ndarray, np.ndarray]:
    """Gap (x^2 + y^2) / (2R) of the crossed cylinders on an n x n window centred on the contact."""
    c = (np.arange(n) - (n - 1) / 2) * dx
    r2 = c[:, None] ** 2 + c[None, :] ** 2
    return r2 / (2 * RADIUS), r2


def rough_gap(n: int, dx: float, seed: int = 7, rms: float = 3e-6) -> np.ndarray:
    """Sphere plus a seeded, laterally smoothed random roughness (r positive pushes the bodies together)."""
    rng = np.random.default_rng(seed)
    noise = rng.normal(size=(n, n))
    smooth = (noise + np.roll(noise, 1, 0) + np.roll(noise, 1, 1) + np.roll(noise, (1, 1), (0, 1))) / 2
    roughness = rms * smooth / smooth.std()
    return sphere_gap(n, dx)[0] - roughness


def hertz_errors(dx: float, n: int) -> dict[str, float]:
    gap, r2 = sphere_gap(n, dx)
    result = solve_normal_contact(gap, dx, load=LOAD)
    a, p0, delta = CONTACT.hertz_radius(), CONTACT.hertz_peak_pressure(), CONTACT.hertz_approach()
    # radius from the pressure's second moment: for Hertz sum(r^2 p) / sum(p) = (2/5) a^2; each element's
    # mean of r^2 is r_c^2 + dx^2 / 6. It converges smoothly, unlike the staircase of the contact area.
    moment = ((r2 + dx * dx / 6) * result.pressure).sum() / result.pressure.sum()
    return {
        "area_radius": abs(np.sqrt(result.contact_area / np.pi) / a - 1),
        "moment_radius": abs(np.sqrt(2.5 * moment) / a - 1),
        "peak_pressure": abs(result.pressure.max() / p0 - 1),
        "approach": abs(result.approach / delta - 1),
        "force": abs(result.force / LOAD - 1),
    }


def test_influence_kernel_centre_value_matches_love():
    # Johnson eq. 3.25 at the centre of a square of side s: integral of 1/rho = 4 s asinh(1); two bodies.
    dx = 1e-3
    kernel = influence_kernel((3, 3), dx)
    e_star = CONTACT.reduced_modulus
    expected = 4 * dx * np.arcsinh(1.0) / (np.pi * e_star)
    assert kernel[2, 2] == pytest.approx(expected, rel=1e-12)  # closed form, round-off only
    # far field: a point load A_e p at distance rho gives A_e / (pi E* rho); 2 elements away is already
    # within 1 % (the element is 0.5 rad wide seen from there)
    assert kernel[2, 4] == pytest.approx(dx * dx / (np.pi * e_star * 2 * dx), rel=0.01)


def test_hertz_sphere_on_flat_and_grid_convergence():
    coarse = hertz_errors(1e-3, 24)
    fine = hertz_errors(0.5e-3, 48)
    for errors in (coarse, fine):
        assert errors["force"] < 1e-9  # the load is an equation of the solve (round-off only)
        # contact radius sqrt(A/pi): the contact area is a staircase of whole elements, so it is off by up to
        # about a quarter element over a radius of 5.5 (1 mm) or 11 (0.5 mm) elements: measured 0.8 %, 1.9 %
        assert errors["area_radius"] < 0.03
        # element-averaged pressure at the centre is below the point value p0 by O(dx^2 / a^2)
        assert errors["peak_pressure"] < 0.01
        assert errors["moment_radius"] < 0.005  # measured 0.23 % (1 mm) and 0.14 % (0.5 mm)
        # approach: the collocation at element centres is very accurate, measured < 0.05 %
        assert errors["approach"] < 0.002
    # refining the grid reduces the discretisation error of the smoothly converging measures
    assert fine["peak_pressure"] < coarse["peak_pressure"]
    assert fine["moment_radius"] < coarse["moment_radius"]


def assert_contact_conditions(result, gap_scale: float):
    p = result.pressure
    d = result.separation
    pmax = p.max()
    assert result.converged
    # eq. 10 to the solver tolerance (1e-9 relative) plus round-off: pressures >= -1e-9 p_max,
    # gaps >= -1e-9 of the approach scale (8e-14 m here)
    assert p.min() >= -1e-9 * pmax
    assert d.min() >= -1e-9 * gap_scale
    # complementarity: outside the contact set p is exactly 0; inside it the gap is 0 up to round-off
    # of u = C p (~1e-15 relative to 77 um, allow 1e-9)
    assert np.all(p[~result.contact] == 0.0)
    assert np.abs(d[result.contact]).max() <= 1e-9 * gap_scale
    assert np.abs(p * d).max() <= 1e-9 * pmax * gap_scale
    # the solver checks gaps only where the surfaces overlap (elsewhere d >= h - delta > 0); its reported
    # penetration must agree with the full separation (round-off of two summation orders, 1e-15 m)
    assert result.max_gap_violation == pytest.approx(max(0.0, -d.min()), abs=1e-15)
    assert result.min_pressure == p.min()


def test_rough_contact_conditions_force_and_warm_start():
    dx, n = 1e-3, 24
    gap = rough_gap(n, dx)
    cold = solve_normal_contact(gap, dx, load=LOAD)
    assert_contact_conditions(cold, CONTACT.hertz_approach())
    assert cold.force == pytest.approx(LOAD, rel=1e-10)  # eq. 9 is solved exactly (round-off only)
    # warm starts give the same answer as cold: from 98 % of the load (elements are added to the factor),
    # from 105 % (elements are removed from it by rank-1 updates) and from a deliberately poor mask;
    # differences are round-off of different factorisation orders (measured 4e-15, allow 1e-9)
    below = solve_normal_contact(gap, dx, load=0.98 * LOAD)
    above = solve_normal_contact(gap, dx, load=1.05 * LOAD)
    assert above.contact.sum() > cold.contact.sum() > below.contact.sum()
    for initial in (below, above, np.ones((n, n), dtype=bool) & (gap < gap.min() + 2e-6)):
        warm = solve_normal_contact(gap, dx, load=LOAD, initial=initial)
        assert np.array_equal(warm.contact, cold.contact)
        np.testing.assert_allclose(warm.pressure, cold.pressure, rtol=0, atol=1e-9 * cold.pressure.max())
        assert warm.approach == pytest.approx(cold.approach, rel=1e-9)
    # the rough surface really differs from Hertz (else this test would not test the active set)
    smooth = solve_normal_contact(sphere_gap(n, dx)[0], dx, load=LOAD)
    assert not np.array_equal(smooth.contact, cold.contact)


def test_rolling_warm_start_from_shifted_gap():
    dx, n = 0.5e-3, 48
    rough = rough_gap(n + 1, dx, seed=3, rms=1e-6)
    sphere = sphere_gap(n, dx)[0]
    roughness = sphere_gap(n + 1, dx)[0] - rough
    previous = solve_normal_contact(sphere - roughness[:n, :n], dx, load=LOAD)
    gap = sphere - roughness[:n, 1:]  # the roughness moved by one element under the wheel
    warm = solve_normal_contact(gap, dx, load=LOAD, initial=previous)
    cold = solve_normal_contact(gap, dx, load=LOAD)
    assert np.array_equal(warm.contact, cold.contact)
    np.testing.assert_allclose(warm.pressure, cold.pressure, rtol=0, atol=1e-9 * cold.pressure.max())
    assert_contact_conditions(warm, CONTACT.hertz_approach())


def test_coupled_form_is_consistent():
    dx, n = 1e-3, 24
    gap = rough_gap(n, dx, seed=11)
    compliance = 1.0 / 5e8  # m/N, of the order of wheel + rail at high frequency
    approach_known = 1.5 * CONTACT.hertz_approach()
    result = solve_coupled_contact(gap, dx, approach_known=approach_known, compliance=compliance)
    assert_contact_conditions(result, CONTACT.hertz_approach())
    # delta = delta_known - c F is one equation of the solve: round-off only
    assert result.approach == pytest.approx(approach_known - compliance * result.force, rel=1e-10)
    assert result.force > 0
    # the same force, imposed as a load, gives the same approach and pressure
    loaded = solve_normal_contact(gap, dx, load=result.force)
    assert loaded.approach == pytest.approx(result.approach, rel=1e-9)
    np.testing.assert_allclose(loaded.pressure, result.pressure, rtol=0, atol=1e-9 * result.pressure.max())
    # warm start of the coupled form from a slightly different step
    again = solve_coupled_contact(gap, dx, approach_known=approach_known * 1.01, compliance=compliance, initial=result)
    assert again.approach == pytest.approx(1.01 * approach_known - compliance * again.force, rel=1e-10)
    assert again.force > result.force


def test_coupled_form_loses_and_regains_contact():
    dx, n = 1e-3, 24
    gap = sphere_gap(n, dx)[0]
    lifted = solve_coupled_contact(gap, dx, approach_known=-1e-6, compliance=1e-9)
    assert lifted.force == 0.0 and not lifted.contact.any()  # loss of contact is physics: F = 0
    assert lifted.approach == -1e-6
    regained = solve_coupled_contact(gap, dx, approach_known=50e-6, compliance=1e-9, initial=lifted)
    assert regained.force > 0
    # zero compliance: displacement control; Hertz F = C_H delta^1.5 within the 1 mm grid error (~1 %)
    rigid = solve_coupled_contact(gap, dx, approach_known=CONTACT.hertz_approach(), compliance=0.0)
    assert rigid.force == pytest.approx(LOAD, rel=0.01)


def test_non_convergence_is_reported():
    dx, n = 1e-3, 24
    gap = rough_gap(n, dx)
    empty = np.zeros((n, n), dtype=bool)
    # one iteration from an empty set cannot converge (the first one only picks a contact element)
    with pytest.raises(WheelrailError, match="did not converge"):
        solve_normal_contact(gap, dx, load=LOAD, initial=empty, max_iterations=1)
    result = solve_normal_contact(gap, dx, load=LOAD, initial=empty, max_iterations=1, raise_on_failure=False)
    assert not result.converged


def test_window_edge_is_reported():
    dx, n = 1e-3, 8  # 8 mm window, Hertz patch 11 mm wide
    gap = sphere_gap(n, dx)[0]
    with pytest.raises(WheelrailError, match="edge of the 8 x 8 window"):
        solve_normal_contact(gap, dx, load=LOAD)
    result = solve_normal_contact(gap, dx, load=LOAD, raise_on_failure=False)
    assert result.at_edge


def test_one_element_at_a_time_mode_reaches_the_same_answer():
    # the anti-cycling mode (used after 30 iterations) adds / drops only the worst element per iteration;
    # forced from the start here it must still end at the same solution, only in more iterations
    dx, n = 1e-3, 24
    gap = rough_gap(n, dx, seed=21)
    reference = solve_normal_contact(gap, dx, load=LOAD)
    window = HalfSpaceWindow((n, n), dx, max_iterations=1000)
    window._cautious = 0  # one element at a time from the first iteration
    window.start_from(gap == gap.min())
    cautious = window.solve(gap, load=LOAD)
    assert cautious.iterations > reference.iterations
    # same solution up to round-off of different factorisation histories (allow 1e-9 relative)
    np.testing.assert_allclose(cautious.pressure, reference.pressure, rtol=0, atol=1e-9 * reference.pressure.max())
    assert cautious.approach == pytest.approx(reference.approach, rel=1e-9)


def assert_same_result(first, second):
    """Bit-identical: the same solve from the same start (no tolerance: same arithmetic in the same order)."""
    assert np.array_equal(first.pressure, second.pressure)
    assert np.array_equal(first.contact, second.contact)
    assert (first.force, first.approach, first.iterations) == (second.force, second.approach, second.iterations)
    assert (first.converged, first.at_edge) == (second.converged, second.at_edge)


def rolling_steps(n: int, dx: float):
    """Gaps and known approaches of a short rolling run: roughness moving one element per step, one lift-off."""
    sphere = sphere_gap(n, dx)[0]
    roughness = sphere - rough_gap(n, dx, seed=5, rms=2e-6)
    factors = (1.4, 1.45, -0.05, 1.5, 1.3)  # x the Hertz approach; step 2 lifts off (no contact)
    return [(sphere + np.roll(roughness, k, 1), f * CONTACT.hertz_approach()) for k, f in enumerate(factors)]


def test_window_reproduces_the_one_off_solves_and_keeps_the_last_loaded_state():
    dx, n = 1e-3, 24
    compliance = 1.0 / 5e8  # m/N
    window = HalfSpaceWindow((n, n), dx)
    assert not window.warm and window.last is None
    warm = None  # the interaction loop's rule before the window: keep a result only if it carries load
    for step, (gap, approach_known) in enumerate(rolling_steps(n, dx)):
        result = window.solve_coupled(gap, approach_known=approach_known, compliance=compliance)
        expected = solve_coupled_contact(gap, dx, approach_known=approach_known, compliance=compliance, initial=warm)
        assert_same_result(result, expected)
        assert window.last is result
        if step == 2:
            assert result.force == 0.0  # the lift-off step really lifts off
            # the window did not take the empty set as its warm state: from it, the next step would differ
            gap3, approach3 = rolling_steps(n, dx)[3]
            following = {"approach_known": approach3, "compliance": compliance}
            from_empty = solve_coupled_contact(gap3, dx, initial=result, **following)
            from_loaded = solve_coupled_contact(gap3, dx, initial=warm, **following)
            assert from_empty.iterations != from_loaded.iterations
        if result.force > 0:
            warm = result
        assert window.warm
    # load-controlled solves go through the same warm state
    gap = rolling_steps(n, dx)[0][0]
    assert_same_result(window.solve(gap, load=LOAD), solve_normal_contact(gap, dx, load=LOAD, initial=warm))
    # reset: cold again, as a one-off solve without initial
    window.reset()
    assert not window.warm and window.last is None
    assert_same_result(window.solve(gap, load=LOAD), solve_normal_contact(gap, dx, load=LOAD))
    # a given contact set (here a poor one) as the start, as initial=mask does
    mask = gap < gap.min() + 2e-6
    window.start_from(mask)
    assert_same_result(window.solve(gap, load=LOAD), solve_normal_contact(gap, dx, load=LOAD, initial=mask))


def test_window_hertz_and_failed_solve_leaves_state():
    dx, n = 1e-3, 24
    window = HalfSpaceWindow((n, n), dx, contact=CONTACT)
    gap, r2 = sphere_gap(n, dx)
    smooth = window.solve(gap, load=LOAD)
    # Hertz through the window as through solve_normal_contact (tolerances of test_hertz_sphere_on_flat...)
    assert np.sqrt(smooth.contact_area / np.pi) == pytest.approx(CONTACT.hertz_radius(), rel=0.03)  # 5.48 mm
    assert smooth.approach == pytest.approx(CONTACT.hertz_approach(), rel=0.002)
    assert window.kernel is influence_kernel((n, n), dx)  # the one cached kernel of eq. 8
    # a solve that raises (here: 10 x the load pushes the patch to the window's edge) changes nothing
    with pytest.raises(WheelrailError, match="edge of the 24 x 24 window"):
        window.solve(gap, load=10 * LOAD)
    assert window.last is smooth
    assert_same_result(window.solve(gap, load=LOAD), solve_normal_contact(gap, dx, load=LOAD, initial=smooth))
    # without raising, the failed result is returned and kept as the last one (the caller checks it)
    edge = window.solve(gap, load=10 * LOAD, raise_on_failure=False)
    assert edge.at_edge and window.last is edge


def test_window_solves_agree_with_the_dense_oracle():
    # the same discrete problem (eqs. 8-11) solved by a dense NNLS (tests/physics/halfspace_oracle.py): the
    # solver's eq. 10 holds to 1e-9 relative and NNLS solves to round-off, so pressures agree to 1e-9 of the
    # largest (measured 3e-15 and 5e-15) and the contact sets are the same
    from halfspace_oracle import coupled_pressure, influence_matrix, loaded_pressure

    dx, n = 1e-3, 24
    gap = rough_gap(n, dx, seed=13)
    matrix = influence_matrix((n, n), dx, CONTACT)
    loaded = solve_normal_contact(gap, dx, load=LOAD)
    pressure, approach = loaded_pressure(matrix, gap, LOAD, dx * dx)
    np.testing.assert_allclose(loaded.pressure.ravel(), pressure, rtol=0, atol=1e-9 * pressure.max())
    assert loaded.approach == pytest.approx(approach, rel=1e-9)
    known, compliance = 1.5 * CONTACT.hertz_approach(), 1.0 / 5e8
    coupled = solve_coupled_contact(gap, dx, approach_known=known, compliance=compliance)
    pressure, approach = coupled_pressure(matrix, gap, known, compliance, dx * dx)
    np.testing.assert_allclose(coupled.pressure.ravel(), pressure, rtol=0, atol=1e-9 * pressure.max())
    assert np.array_equal(coupled.contact.ravel(), pressure > 0)
    assert coupled.approach == pytest.approx(approach, rel=1e-9)
