"""Real contact geometry: elliptic patches from the wheel and rail radii in all five models."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wheelrail.core.contact.window import solve_normal_contact
from wheelrail.core.contact.winkler import _winkler_force, calibrated_bedding, wheel_profile
from wheelrail.core.engine import prepare_run, simulate
from wheelrail.core.models import MODELS
from wheelrail.core.parameters import ContactParameters, ModelParameters
from wheelrail.core.roughness import RoughnessSet

REAL = ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30)  # a long patch: a 6.20 mm, b 4.67 mm
CONCAVE = ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30, wheel_transverse_radius=-0.5)  # a wide one
CONVEX = ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30, wheel_transverse_radius=0.5)  # a narrow one
L_S = ModelParameters().track.support.sleeper_spacing


def _set(heights, kind="rail"):
    heights = np.atleast_2d(heights)
    n = heights.shape[0]
    y = (np.arange(n) - (n - 1) // 2) * 1e-3
    return RoughnessSet(heights=heights, dx=1e-3, y=y, kind=kind, description="test")


def _smooth(length, lines=19):
    return _set(np.zeros((lines, int(round(length / 1e-3)) + 1)))


def _halfspace_errors(contact: ContactParameters, dx: float) -> dict:
    """The 3D solver on the smooth elliptic gap against Johnson 4.2: relative errors."""
    hertz = contact.hertz()
    a, b = hertz.semi_axis_along, hertz.semi_axis_across
    nx, ny = math.ceil(1.3 * a / dx), math.ceil(1.3 * b / dx)
    x, y = np.arange(-nx, nx + 1) * dx, np.arange(-ny, ny + 1) * dx
    gap = x[None, :] ** 2 / (2 * contact.radius_along) + y[:, None] ** 2 / (2 * contact.radius_across)
    result = solve_normal_contact(gap, dx, load=contact.preload, contact=contact)
    p = result.pressure
    load = p.sum() * dx * dx
    # an ellipsoidal pressure has the second moments a^2/5 (along) and b^2/5 (across) per unit load
    moment_a = math.sqrt(5 * (p * x[None, :] ** 2).sum() * dx * dx / load)
    moment_b = math.sqrt(5 * (p * y[:, None] ** 2).sum() * dx * dx / load)
    return {
        "area": abs(result.contact.sum() * dx * dx / (math.pi * a * b) - 1),
        "peak_pressure": abs(p.max() / hertz.peak_pressure - 1),
        "approach": abs(result.approach / hertz.approach - 1),
        "a": abs(moment_a / a - 1),
        "b": abs(moment_b / b - 1),
    }


@pytest.mark.parametrize(
    ("contact", "axes_1mm"),
    [(REAL, 3e-3), (CONCAVE, 3e-3), (CONVEX, 5e-3)],
    ids=["0.46-on-0.30", "concave-tread", "convex-tread"],
)
def test_3d_solver_converges_to_the_hertz_ellipse(contact, axes_1mm):
    # Johnson, Contact Mechanics 4.2 (ContactParameters.hertz) against the half-space solver, which knows
    # nothing of elliptic integrals. Measured at 1 mm / 0.5 mm (validation/contact_geometry_accuracy.py):
    # p0 within 0.19 / 0.05 %, approach 0.21 / 0.05 %; a and b from the pressure's second moments 0.18 / 0.05 %
    # for 0.46 m on 0.30 m and the concave tread, but 0.36 / 0.06 % for the convex +0.5 m tread (and up to
    # 0.77 % at 1 mm for other convex treads and long patches: the semi-axis across spans fewer elements);
    # area 2.3-4.7 / 1.6-2.3 % (a staircase of whole elements around the ellipse). Bounds: 0.3 % (1 mm;
    # semi-axes 0.5 % for the convex tread) and 0.1 % (0.5 mm), area 5 % and 2.5 %.
    coarse, fine = _halfspace_errors(contact, 1e-3), _halfspace_errors(contact, 0.5e-3)
    for name in ("peak_pressure", "approach"):
        assert coarse[name] < 3e-3 and fine[name] < 1e-3, name
    for name in ("a", "b"):
        assert coarse[name] < axes_1mm and fine[name] < 1e-3, name
    assert coarse["area"] < 0.05 and fine["area"] < 0.025
    # refining the grid reduces every error (convergence, not a lucky grid)
    for name in ("peak_pressure", "approach", "area"):
        assert fine[name] < coarse[name], name


def test_hertz_law_is_the_ellipse():
    # The `hertz` law's contact length and area at each step are 2a and pi a b of the ellipse at that
    # step's force (to 1e-6: both come from the same semi-axis radii; the residue is the Newton tolerance).
    result = simulate(_smooth(2.1), model="hertz", length=2.0, params=ModelParameters(contact=REAL))
    for step in (0, result.n_steps // 2, result.n_steps - 1):
        hertz = REAL.hertz(result.force[step])
        assert result.contact_length[step] == pytest.approx(2 * hertz.semi_axis_along, rel=1e-6)
        assert result.contact_area[step] == pytest.approx(
            math.pi * hertz.semi_axis_along * hertz.semi_axis_across, rel=1e-6
        )


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.slow
def test_smooth_elliptic_patch_in_every_model(model):
    # Smooth surfaces, R_x = 0.46 m, R_y = 0.30 m: the mean force equals the preload within 0.5 % (the run
    # starts in static equilibrium on each model's own static approach; measured within 0.01 %).
    params = ModelParameters(contact=REAL)
    length = 4 * L_S if model == "3d" else 8 * L_S
    result = simulate(_smooth(length + 0.1), model=model, length=length, params=params)
    assert result.loss_of_contact_steps == 0
    assert result.force.mean() == pytest.approx(REAL.preload, rel=5e-3)
    a, b = REAL.hertz_semi_axes()
    if model == "3d":
        # the patch area (elements in contact x dx^2, a staircase around the ellipse) within 3 % of pi a b on
        # the 1 mm grid here (measured 2.3 %; 0.5-16 % over the geometries and loads of
        # validation/contact_geometry_accuracy.py)
        assert np.mean(result.contact_area) == pytest.approx(math.pi * a * b, rel=0.03)
        # the window follows the semi-axes: 2.2 a along the rail (29 columns here, 25 for the paper's circle)
        assert result.window_x[-1] == pytest.approx(round(2.2 * a / 1e-3) * 1e-3)
        rows, cols = np.nonzero(result.pressure[result.n_steps // 2] > 0)
        assert cols.max() - cols.min() > rows.max() - rows.min()  # long along the rail, as a > b
    if model == "2d":
        # the calibrated bedding's contact length is 2a within one element (13 springs for 2a = 12.4 mm)
        assert np.all(np.abs(result.contact_length - 2 * a) <= 1e-3 + 1e-12)


@pytest.mark.parametrize("contact", [ContactParameters(), REAL], ids=["paper-circle", "0.46-on-0.30"])
def test_calibrated_bedding_against_hertz_over_40_to_150_um(contact):
    # The 2D bedding (Ford & Thompson's criterion, eqs. 5-6 for the circle, applied to an ellipse:
    # R_m = rho_x / 2, k = 3 C / (4 sqrt(rho_x))) is exact for the continuous bedding; on the 1 mm grid the
    # midpoint rule leaves, over approaches of 40-150 um swept every 0.01 um (a 0.5 um sweep misses the worst
    # point), at most 1.56 % (circle) and 1.00 % (0.46 m on 0.30 m) from C delta^1.5 (2.78 % for a 0.2 m
    # wheel on a 0.8 m crown: fewer springs span its shorter patch). Bound 2 % (docs/physics.md).
    stiffness, radius = calibrated_bedding(contact)
    profile = wheel_profile(61, 1e-3, radius)
    worst = 0.0
    for approach in np.linspace(40e-6, 150e-6, 11001):
        force, _, _, edge = _winkler_force(approach, np.zeros(61), profile, stiffness * 1e-3)
        assert not edge
        worst = max(worst, abs(force / (contact.hertz_constant * approach**1.5) - 1))
    assert worst < 0.02


def _amplitude(model: str, wavelength: float, params: ModelParameters, r0: float = 0.2e-6) -> float:
    x = np.arange(1200) * 1e-3
    result = simulate(_set(r0 * np.sin(2 * np.pi * x / wavelength)), model=model, length=1.0, params=params)
    f = params.run.speed / wavelength
    t = result.time[200:]
    basis = np.stack([np.sin(2 * np.pi * f * t), np.cos(2 * np.pi * f * t), np.ones_like(t)], axis=1)
    coeff, *_ = np.linalg.lstsq(basis, result.force[200:], rcond=None)
    return math.hypot(coeff[0], coeff[1])


@pytest.mark.parametrize("contact", [ContactParameters(), REAL], ids=["paper-circle", "0.46-on-0.30"])
@pytest.mark.slow
def test_2d_filter_dip_follows_the_semi_axis_along_the_rail(contact):
    # Laterally uniform sinusoidal roughness (0.2 um: linear regime) swept in wavelength: the `2d` force
    # relative to `hertz` dips deepest where one wavelength fills the patch, lambda = 2a (eq. 19, n = 1;
    # f = v / (2a)). The bedding's contact is a whole number of springs, within one element of 2a, and the
    # sweep steps by 0.25 mm, so the dip lies within 1.125 mm of 2a (measured: 0.04 mm for the circle,
    # 2a = 10.96 mm; 0.84 mm for the ellipse, 2a = 12.41 mm, 13 springs). The dip is deep (> 25 dB).
    params = ModelParameters(contact=contact)
    two_a = 2 * contact.hertz_semi_axes()[0]
    wavelengths = np.arange(-12, 13) * 0.25e-3 + round(two_a / 0.25e-3) * 0.25e-3
    levels = [20 * math.log10(_amplitude("2d", w, params) / _amplitude("hertz", w, params)) for w in wavelengths]
    deepest = int(np.argmin(levels))
    assert abs(wavelengths[deepest] - two_a) <= 1.125e-3
    assert levels[deepest] < -25.0


def test_window_lines_use_the_semi_axis_across():
    # A wide patch (concave tread: b = 7.37 mm) needs data for b + 1 element on each side of its line: on
    # the 19-line (+-9 mm) set only line 0 qualifies (8 + 1 <= 9); the paper's circle (b = 5.48 mm) allows
    # -2..2 (7 mm each side).
    from wheelrail.core.engine.track_lines import window_lines

    rough = _smooth(0.2)
    assert window_lines(rough, ModelParameters()) == (-2, -1, 0, 1, 2)
    assert window_lines(rough, ModelParameters(contact=CONCAVE)) == (0,)
    run = prepare_run(_smooth(0.3), model="3d", length=0.05, params=ModelParameters(contact=CONCAVE))
    # across the rail the window spans 2.2 b (16 elements each side), cut to the data's 9
    assert run.window_y[-1] == pytest.approx(9e-3) and run.window_x[-1] == pytest.approx(12e-3)
