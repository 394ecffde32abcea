"""The contact set's solve through a reference factor and a small capacitance system (``contact.active_set``).

Large windows (0.5 mm elements: ~385 of 1 813 elements in contact, changing by 2-4 a step) solve on the contact
set A without a factor of C_AA. A *reference* set R keeps its Cholesky factor C_RR = U^T U; A differs from R by
the elements D of R that left it and the elements E that joined it, k = |D| + |E| of them (the set's *members* of
the capacitance system). With x_R = C_RR^-1 (b_R - C_RE x_E - I_D lambda) and x_D = 0, the solve on A is

    [ C_EE - C_ER C_RR^-1 C_RE    -(C_RR^-1 C_RE)_D^T ] [x_E   ]   [ b_E - C_ER C_RR^-1 b_R ]
    [ -(C_RR^-1 C_RE)_D           -(C_RR^-1)_DD       ] [lambda] = [ -(C_RR^-1 b_R)_D       ]

(the Schur-complement active-set method: Gill, Murray, Saunders and Wright, "A Schur-complement method for
sparse quadratic programming", 1990; Bartlett and Biegler, "QPSchur", Optimization and Engineering 7, 2006). Per
member one *kept vector*, C_RR^-1 c_Rj for j in E (with c_Rj and c_jj - c_Rj^T C_RR^-1 c_Rj) or C_RR^-1 e_j for j
in D, is computed the first time j becomes a member and kept until R changes, so elements that leave and join
again cost nothing new. The inverse of the k x k matrix is kept and bordered (O(k^2)) as members come and go.
With b = delta 1 - h the pressure is p = delta q_1 - q_h: x_1 = C_RR^-1 1 is kept per reference and x_h =
C_RR^-1 h_R computed once per gap, so an iteration of the active set costs O(k m + k^2) instead of a
substitution with an m x m factor, and a change of the set O(k^2) instead of a new factor row or a downdate.
C_RR^-1 itself is kept, computed from the factor when R is factored (``cholesky.invert``, O(m^3)): x_h is one
symmetric matrix-vector product that reads its upper triangle once (``cholesky.symmetric_product``) instead of
a forward and a backward substitution, the kept vector of a D member is a row of it, that of an E member one
product.

R becomes the current set (a fresh factor) when a member has no room
(``CAPACITANCE_MEMBERS``, ``CAPACITANCE_VECTORS``), after ``CAPACITANCE_REFRESH`` changes of members (the
bordered inverse's round-off) or where a bordering pivot is not clearly nonzero. Design and measured figures:
``docs/benchmarks.md``, "The contact solver".

The state (:func:`capacitance_state`) is a tuple of arrays: (info, reference, position in R, slot of each
element, kept vectors, c_Rj of E members, per-slot scalars, E-E entries of the matrix, members, their slots,
the inverse, (x_1, x_h, scratch), the small system's scratch, (1^T x_1, 1^T x_h), C_RR^-1); info = [on, |R|, k, slots
used, member changes since R was factored, references factored, kept vectors computed, 0].
"""

from __future__ import annotations

import numpy as np
from numba import njit, types
from numba.extending import overload

from wheelrail.core.contact.cholesky import factorize, invert, symmetric_product

__all__ = [
    "CAPACITANCE_MEMBERS",
    "CAPACITANCE_REFRESH",
    "CAPACITANCE_VECTORS",
    "capacitance_on",
    "capacitance_state",
    "change",
    "prepare_gap",
    "pressure_on_set",
    "rebase",
]

CAPACITANCE_MEMBERS = 128  # largest k (elements by which the set differs from the reference)
CAPACITANCE_VECTORS = 384  # kept vectors per reference
CAPACITANCE_REFRESH = 1 << 16  # changes of members after which the reference is factored afresh

# info's fields
_ON, _SIZE, _K, _SLOTS, _CHANGES, _REFERENCES, _VECTORS = 0, 1, 2, 3, 4, 5, 6


def capacitance_state(n: int, rows: int, enabled: bool) -> tuple:
    """The arrays of the capacitance solve for a window of ``n`` elements and a factor buffer of ``rows`` rows;
    where not ``enabled``, placeholders (one row, no slots) whose ``info`` is int32: :func:`capacitance_on` is
    then False at compile time, and the solver's branches for the capacitance solve fold away when compiled."""
    slots, members = (CAPACITANCE_VECTORS, CAPACITANCE_MEMBERS) if enabled else (1, 1)
    rows = rows if enabled else 1
    size = n if enabled else 1
    return (
        np.zeros(8, dtype=np.int64 if enabled else np.int32),
        np.zeros(size, dtype=np.int64),
        np.full(size, -1, dtype=np.int64),
        np.full(size, -1, dtype=np.int64),
        np.empty((slots, rows)),
        np.empty((slots, rows)),
        np.empty((4, slots)),  # 1^T v, c_jj - c_Rj^T w_j, c_Rj^T x_h, the slot's element
        np.full((slots, slots), np.nan),
        np.empty(members, dtype=np.int64),
        np.empty(members, dtype=np.int64),
        np.empty((members, members)),
        np.empty((3, rows)),
        np.empty((7, members)),
        np.zeros(2),
        np.empty((rows, rows)),
    )


def capacitance_on(cap) -> bool:
    """Whether the capacitance solve is on for this state (:func:`capacitance_state`); in compiled code a
    constant False for the placeholder's type."""
    return cap[0].dtype == np.int64 and bool(cap[0][0])


@overload(capacitance_on, inline="always")
def _capacitance_on(cap):
    if cap[0].dtype == types.int64:
        return lambda cap: cap[0][0] != 0
    return lambda cap: False


@njit(cache=True, fastmath=True)
def _dot(a, b, m):
    total = 0.0
    for i in range(m):
        total += a[i] * b[i]
    return total


@njit(cache=True, fastmath=True)
def _combine(vectors, slots, k, coefficients, m, out):
    """out[:m] -= sum over q < k of coefficients[q] vectors[slots[q], :m], four vectors at a time."""
    q = 0
    while q + 4 <= k:
        v0, v1, v2, v3 = (
            vectors[slots[q], :m],
            vectors[slots[q + 1], :m],
            vectors[slots[q + 2], :m],
            vectors[slots[q + 3], :m],
        )
        a0, a1, a2, a3 = coefficients[q], coefficients[q + 1], coefficients[q + 2], coefficients[q + 3]
        for a in range(m):
            out[a] -= a0 * v0[a] + a1 * v1[a] + a2 * v2[a] + a3 * v3[a]
        q += 4
    for r in range(q, k):
        v = vectors[slots[r], :m]
        coefficient = coefficients[r]
        for a in range(m):
            out[a] -= coefficient * v[a]


@njit(cache=True)
def rebase(grid3, order, m, upper, cap):
    """The set ``order[:m]`` as the reference: its factor into ``upper``, C_RR^-1 from it, x_1 = C_RR^-1 1, no
    members, no kept vectors. ``grid3`` = (kernel, rows, columns). Returns False if C_RR is not positive definite."""
    info, reference, position, slot, _, _, scalars, pair, _, _, _, vectors, _, sums, inverse_rr = cap
    for a in range(info[_SIZE]):
        position[reference[a]] = -1
    for s in range(info[_SLOTS]):
        slot[int(scalars[3, s])] = -1
        for t in range(info[_SLOTS]):
            pair[s, t] = np.nan
    info[_SIZE] = info[_K] = info[_SLOTS] = info[_CHANGES] = 0
    for a in range(m):
        reference[a] = order[a]
        position[order[a]] = a
    if not factorize(grid3, reference, m, upper):
        for a in range(m):
            position[order[a]] = -1
        return False
    info[_SIZE] = m
    info[_REFERENCES] += 1
    invert(upper, m, inverse_rr)
    x1 = vectors[0]
    for a in range(m):
        row = inverse_rr[a, :m]
        x1[a] = 0.0
        for b in range(m):
            x1[a] += row[b]
    sums[0] = 0.0
    for a in range(m):
        sums[0] += x1[a]
    return True


@njit(cache=True)
def prepare_gap(gap, upper, cap):
    """x_h = C_RR^-1 h_R for the gap ``gap`` (m, the flattened window), 1^T x_h and c_Rj^T x_h of the E members."""
    info, reference, position, _, _, columns, scalars, _, members, slots, _, vectors, _, sums, inverse_rr = cap
    m = info[_SIZE]
    xh, h = vectors[1], vectors[2]
    for a in range(m):
        h[a] = gap[reference[a]]
    symmetric_product(inverse_rr, m, h, xh)
    sums[1] = 0.0
    for a in range(m):
        sums[1] += xh[a]
    for q in range(info[_K]):
        if position[members[q]] < 0:
            scalars[2, slots[q]] = _dot(columns[slots[q]], xh, m)


@njit(cache=True)
def _kept_vector(grid, upper, cap, element):
    """The slot of ``element``'s kept vector, computed if it has none; -1 if no slot is free."""
    info, reference, position, slot, kept, columns, scalars, _, _, _, _, _, _, _, inverse_rr = cap
    if slot[element] >= 0:
        return slot[element]
    s = info[_SLOTS]
    if s == kept.shape[0]:
        return -1
    m = info[_SIZE]
    v = kept[s]
    if position[element] >= 0:  # in R: C_RR^-1 e_j, a row of the inverse
        row = inverse_rr[position[element]]
        for a in range(m):
            v[a] = row[a]
        scalars[1, s] = -v[position[element]]
    else:  # outside R: C_RR^-1 c_Rj, c_Rj kept
        kernel, _, _, rows, cols = grid
        ny, nx = (kernel.shape[0] + 1) // 2, (kernel.shape[1] + 1) // 2
        column = columns[s]
        for a in range(m):
            j = reference[a]
            column[a] = kernel[rows[element] - rows[j] + ny - 1, cols[element] - cols[j] + nx - 1]
        symmetric_product(inverse_rr, m, column, v)
        scalars[1, s] = kernel[ny - 1, nx - 1] - _dot(column, v, m)
    scalars[0, s] = 0.0
    for a in range(m):
        scalars[0, s] += v[a]
    scalars[3, s] = element
    slot[element] = s
    info[_SLOTS] = s + 1
    info[_VECTORS] += 1
    return s


@njit(cache=True)
def _enter(grid, upper, cap, element):
    """``element`` becomes a member: the inverse bordered by its row. Returns False where it cannot (no room, or
    a pivot not clearly nonzero): the reference must be factored afresh."""
    info, _, position, _, kept, columns, scalars, pair, members, slots, inverse, vectors, small, _, _ = cap
    k = info[_K]
    if k == members.size:
        return False
    s = _kept_vector(grid, upper, cap, element)
    if s < 0:
        return False
    kernel, _, _, rows, cols = grid
    ny, nx = (kernel.shape[0] + 1) // 2, (kernel.shape[1] + 1) // 2
    m = info[_SIZE]
    row, w = small[0], small[1]
    inside = position[element] >= 0
    for q in range(k):
        j, t = members[q], slots[q]
        if not inside and position[j] < 0:
            if pair[s, t] != pair[s, t]:
                coupling = kernel[rows[element] - rows[j] + ny - 1, cols[element] - cols[j] + nx - 1]
                pair[s, t] = pair[t, s] = coupling - _dot(columns[s], kept[t], m)
            row[q] = pair[s, t]
        elif not inside:
            row[q] = -kept[s, position[j]]
        else:
            row[q] = -kept[t, position[element]]
    pivot = scalars[1, s]
    for q in range(k):
        w[q] = _dot(inverse[q], row, k)
        pivot -= row[q] * w[q]
    if not abs(pivot) > 1e-9 * abs(scalars[1, s]):
        return False
    for q in range(k):
        scale = w[q] / pivot
        line = inverse[q]
        for r in range(k):
            line[r] += scale * w[r]
        line[k] = -scale
        inverse[k, q] = -scale
    inverse[k, k] = 1.0 / pivot
    members[k], slots[k] = element, s
    info[_K] = k + 1
    if not inside:
        scalars[2, s] = _dot(columns[s], vectors[1], m)
    return True


@njit(cache=True)
def _leave(cap, element):
    """``element`` is no longer a member: the inverse with its row and column eliminated; the last member takes
    its place. Returns False if its diagonal entry of the inverse is zero."""
    info, _, _, _, _, _, _, _, members, slots, inverse, _, _, _, _ = cap
    k = info[_K]
    q0 = 0
    while members[q0] != element:
        q0 += 1
    pivot = inverse[q0, q0]
    if pivot == 0.0:
        return False
    for q in range(k):
        if q != q0:
            scale = inverse[q, q0] / pivot
            line, source = inverse[q], inverse[q0]
            for r in range(k):
                line[r] -= scale * source[r]
    last = k - 1
    members[q0], slots[q0] = members[last], slots[last]
    for q in range(k):
        inverse[q, q0] = inverse[q, last]
    for q in range(k):
        inverse[q0, q] = inverse[last, q]
    inverse[q0, q0] = inverse[last, last]
    info[_K] = last
    return True


@njit(cache=True)
def change(grid, upper, cap, element, joins):
    """``element`` joins the set (``joins``) or leaves it. Returns False where the reference must be factored
    afresh before the next solve (no room for a member, a pivot, or ``CAPACITANCE_REFRESH`` changes since)."""
    info, _, position, _, _, _, _, _, _, _, _, _, _, _, _ = cap
    info[_CHANGES] += 1
    if info[_CHANGES] > CAPACITANCE_REFRESH:
        return False
    if (position[element] >= 0) == joins:  # back to what the reference has
        return _leave(cap, element)
    return _enter(grid, upper, cap, element)


@njit(cache=True, fastmath=True)
def pressure_on_set(cap, gap, active, pressure, law):
    """Pressure on the set (R less D, with E) with d = 0 there (eqs. 8, 11) and the approach from ``law`` (as
    ``active_set._pressure_on_set``); returns (delta, max pressure, the sum of the decreases of the pressures
    it changed). Needs :func:`prepare_gap` for this gap."""
    coupled, target, compliance_area = law
    info, reference, position, _, kept, _, scalars, _, members, slots, inverse, vectors, small, sums, _ = cap
    m, k = info[_SIZE], info[_K]
    x1, xh, p = vectors[0], vectors[1], vectors[2]
    r1, rh, s1, sh, coefficients = small[2], small[3], small[4], small[5], small[6]
    for q in range(k):
        i, s = members[q], slots[q]
        if position[i] < 0:
            r1[q] = 1.0 - scalars[0, s]
            rh[q] = gap[i] - scalars[2, s]
        else:
            r1[q] = -x1[position[i]]
            rh[q] = -xh[position[i]]
    total1, totalh = sums[0], sums[1]  # 1^T C_AA^-1 1 and 1^T C_AA^-1 h_A
    for q in range(k):
        line = inverse[q]
        a1 = 0.0
        ah = 0.0
        for r in range(k):
            a1 += line[r] * r1[r]
            ah += line[r] * rh[r]
        s1[q], sh[q] = a1, ah
        total1 -= scalars[0, slots[q]] * a1
        totalh -= scalars[0, slots[q]] * ah
        if position[members[q]] < 0:
            total1 += a1
            totalh += ah
    if coupled:
        delta = (target + compliance_area * totalh) / (1.0 + compliance_area * total1)
    else:
        delta = (target + totalh) / total1
    for a in range(m):
        p[a] = delta * x1[a] - xh[a]
    for q in range(k):
        coefficients[q] = delta * s1[q] - sh[q]
    _combine(kept, slots, k, coefficients, m, p)
    pmax = 0.0
    decrease = 0.0
    for a in range(m):
        i = reference[a]
        if active[i]:
            decrease += max(pressure[i] - p[a], 0.0)
            pressure[i] = p[a]
            pmax = max(pmax, p[a])
    for q in range(k):
        i = members[q]
        if position[i] < 0:
            decrease += max(pressure[i] - coefficients[q], 0.0)
            pressure[i] = coefficients[q]
            pmax = max(pmax, coefficients[q])
    return delta, pmax, decrease
