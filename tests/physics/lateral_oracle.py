"""An independent model of the lateral track for the tests: the infinite, periodically supported rail solved exactly
within each bay (no finite elements), with Floquet waves along the bays.

The rail between supports is the continuum the FE model discretises: a Timoshenko beam in lateral bending (v, psi)
and a Vlasov bar in torsion (phi, with warping), coupled by the rail's mass acting at the centroid e_c above the
shear centre. In the frequency domain (e^{i w t}) the state y = (v, psi, Q, M, phi, phi', B, T) obeys y' = A y:

    v' = psi + Q / (kGA),     psi' = M / EI,     Q' = -w^2 m' (v - e_c phi),     M' = -Q - w^2 rho I_z psi,
    phi' = theta,  theta' = B / EI_w,  B' = (GJ - w^2 rho I_w) theta - T,  T' = w^2 m' e_c v - w^2 I_s phi,

with I_s = rho I_p + m' e_c^2 (polar, about the shear centre) and the rail's stiffnesses times (1 + i eta). A point
support at x_S adds jumps Q+ - Q- = S_vv v + S_vphi phi and T+ - T- = S_phiv v + S_phiphi phi, S the support's
dynamic stiffness on (v, phi): the pad's lateral stiffness, in series with the sleeper's mass on the ballast, acting
at the foot (v + z_s phi), and its roll stiffness on phi. The transfer matrix of a bay, from just after a support to
just after the next, P = J expm(A L), has eigenvalues in pairs lambda, 1/lambda: the four with |lambda| < 1 are the
waves decaying ahead, the other four those decaying behind. A load at x0 in the bay is the jump of (Q, T) there, the
response each side of it the sum of the waves that decay away from it.
"""

from __future__ import annotations

import numpy as np


class PeriodicLateralRail:
    """The infinite lateral track of a ``TrackParameters`` (point supports) at one frequency."""

    def __init__(self, track, frequency: float) -> None:
        sec, lat, sup = track.lateral.section, track.lateral, track.support
        w2 = (2 * np.pi * frequency) ** 2
        damp = 1 + 1j * track.rail.loss_factor
        m = track.rail.mass_per_length
        rho = m / sec.area
        e_c = sec.centroid_height - sec.shear_centre_height
        EI = sec.youngs_modulus * sec.lateral_second_moment * damp
        kGA = sec.lateral_shear_coefficient * sec.shear_modulus * sec.area * damp
        GJ = sec.shear_modulus * sec.torsion_constant * damp
        EIw = sec.youngs_modulus * sec.warping_constant * damp
        I_s = rho * sec.polar_second_moment + m * e_c**2
        A = np.zeros((8, 8), dtype=complex)
        A[0, 1], A[0, 2] = 1, 1 / kGA
        A[1, 3] = 1 / EI
        A[2, 0], A[2, 4] = -w2 * m, w2 * m * e_c
        A[3, 2], A[3, 1] = -1, -w2 * rho * sec.lateral_second_moment
        A[4, 5] = 1
        A[5, 6] = 1 / EIw
        A[6, 5], A[6, 7] = GJ - w2 * rho * sec.warping_constant, -1
        A[7, 0], A[7, 4] = w2 * m * e_c, -w2 * I_s
        sleeper = lat.ballast_lateral_stiffness * (1 + 1j * lat.ballast_lateral_loss_factor) - w2 * sup.sleeper_mass
        pad = lat.pad_lateral_stiffness * (1 + 1j * lat.pad_lateral_loss_factor)
        k_y = pad * sleeper / (pad + sleeper)
        k_r = lat.pad_rotational_stiffness * (1 + 1j * lat.pad_lateral_loss_factor)
        z_s = sec.shear_centre_height
        S = np.array([[k_y, k_y * z_s], [k_y * z_s, k_y * z_s**2 + k_r]])
        J = np.eye(8, dtype=complex)
        J[np.ix_([2, 7], [0, 4])] = S
        self.A, self.J, self.L = A, J, sup.sleeper_spacing
        self._wavenumbers, self._modes = np.linalg.eig(A)  # expm(A s) = V exp(D s) V^-1: the free rail's waves
        self._modes_inverse = np.linalg.inv(self._modes)
        self.head = sec.head_height - z_s
        values, vectors = np.linalg.eig(J @ self.expm(self.L))
        order = np.argsort(np.abs(values))
        self.ahead = (values[order[:4]], vectors[:, order[:4]])  # |lambda| < 1: decaying in +x
        self.behind = (values[order[4:]], vectors[:, order[4:]])  # decaying in -x

    def response(self, x0: float, x, lateral: float, torque: float) -> np.ndarray:
        """The state y(x) (8, len(x)) for a lateral force ``lateral`` at the railhead and a torque ``torque`` at x0
        in (0, L) of bay 0 (supports at j L); x anywhere (m), never at x0 itself."""
        right, left, a_b = self._waves(x0, lateral, torque)
        out = np.empty((8, len(np.atleast_1d(x))), dtype=complex)
        for i, xi in enumerate(np.atleast_1d(x)):
            bay = int(np.floor(xi / self.L))
            local = xi - bay * self.L
            if xi > x0 and bay == 0:
                start = right @ a_b[:4]
                out[:, i] = self.expm(xi - x0) @ start
            elif xi < x0 and bay == 0:
                out[:, i] = self.expm(xi - x0) @ (left @ a_b[4:])
            else:
                values, vectors = self.ahead if bay > 0 else self.behind
                coefficients = a_b[:4] if bay > 0 else a_b[4:]
                out[:, i] = self.expm(local) @ (vectors @ (coefficients * values**bay))
        return out

    def expm(self, s: float) -> np.ndarray:
        """The free rail's transfer matrix over ``s`` (m), expm(A s)."""
        return (self._modes * np.exp(self._wavenumbers * s)) @ self._modes_inverse

    def _waves(self, x0: float, lateral: float, torque: float):
        """The waves ahead and behind at x0 (8 x 4 each) and their amplitudes (8: ahead, then behind)."""
        to_x0 = self.expm(x0)
        right, left = to_x0 @ self.ahead[1], to_x0 @ self.behind[1]
        jump = np.zeros(8, dtype=complex)
        jump[2], jump[7] = -lateral, -(torque - self.head * lateral)  # a load P gives Q+ - Q- = -P (so T too)
        return right, left, np.linalg.solve(np.hstack([right, -left]), jump)

    def railhead(self, x0: float, x, lateral: float = 1.0, torque: float = 0.0) -> np.ndarray:
        """The railhead's lateral displacement, v - (z_h - z_s) phi, at x (m)."""
        y = self.response(x0, x, lateral, torque)
        return y[0] - self.head * y[4]

    def twist(self, x0: float, x, lateral: float = 0.0, torque: float = 1.0) -> np.ndarray:
        """The twist phi at x (rad)."""
        return self.response(x0, x, lateral, torque)[4]

    def railhead_ahead(self, x0: float, step: float, count: int) -> np.ndarray:
        """The railhead's lateral displacement per unit lateral force at the railhead at x0 (in bay 0), at
        x0 + k ``step`` for k = 0 .. count - 1 (a grid that puts x0 + k step on the supports' bay grid: ``step``
        divides the spacing and x0 is a multiple of it)."""
        per_bay = int(round(self.L / step))
        start = int(round(x0 / step))
        local = [self.expm(j * step) for j in range(per_bay)]
        right, _, a_b = self._waves(x0, 1.0, 0.0)
        values, vectors = self.ahead
        coefficients = a_b[:4]
        y0 = right @ coefficients  # just after the load
        index = start + np.arange(count)
        bay, j = np.divmod(index, per_bay)
        states = vectors @ (coefficients[:, None] * values[:, None] ** bay[None, :])  # (8, count) at each bay's start
        out = np.empty(count, dtype=complex)
        for k in range(count):
            if bay[k] == 0:
                y = self.expm((index[k] * step) - x0) @ y0
            else:
                y = local[j[k]] @ states[:, k]
            out[k] = y[0] - self.head * y[4]
        return out
