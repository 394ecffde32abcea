"""The deformed gap outside the contact set for the active set (``contact.active_set``), compiled: u = C p (eq. 8).

An element outside the set penetrates (eq. 10) where d = h - delta + u < 0 (eq. 11). The solver computes u only
where that can happen: in the rigid overlap (h < delta; u >= 0 elsewhere), less the elements that
:func:`screen` shows cannot penetrate (a lower bound of u from block sums of the pressure). u is one contiguous
dot product per element, from the window's influence matrix (:func:`displacement_matrix`, small windows) or from
the kernel of eq. 8 laid out with the stride of the set's bounding box (:func:`displacement_kernel`). Design and
measured figures: ``docs/benchmarks.md``, "The contact solver". Conventions as in ``contact.active_set``: the
window of ny x nx elements flattened row by row, ``grid`` = (kernel, kernel reversed, C or 0 x 0, row and column
of each element), the set ``order[:m]``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = [
    "KERNEL_GROUP_COLUMNS",
    "SCREEN_BLOCKS",
    "displacement_decided",
    "displacement_kept",
    "displacement_kernel",
    "displacement_kernel32",
    "displacement_matrix",
    "float32_error",
    "screen",
]

SCREEN_BLOCKS = 4  # blocks per side of the set's bounding box in the lower bound of u = C p (screen)
KERNEL_GROUP_COLUMNS = 8  # candidates' columns per group in u = C p from the kernel (displacement_kernel)


@njit(cache=True, fastmath=True)
def displacement_matrix(full, order, m, pressure, candidates, count, u):
    """u = C p at ``candidates[:count]`` from C's rows over the span of flat indices the set covers (zero
    between its elements), four rows at a time."""
    lo, hi = pressure.size, 0
    for a in range(m):
        lo = min(lo, order[a])
        hi = max(hi, order[a] + 1)
    span = pressure[lo : max(lo, hi)]
    size = span.size
    for c in range(0, count, 4):
        i0, i1 = candidates[c], candidates[min(c + 1, count - 1)]
        i2, i3 = candidates[min(c + 2, count - 1)], candidates[min(c + 3, count - 1)]
        r0, r1, r2, r3 = (
            full[i0, lo : lo + size],
            full[i1, lo : lo + size],
            full[i2, lo : lo + size],
            full[i3, lo : lo + size],
        )
        u0 = u1 = u2 = u3 = 0.0
        for k in range(size):
            x = span[k]
            u0 += r0[k] * x
            u1 += r1[k] * x
            u2 += r2[k] * x
            u3 += r3[k] * x
        u[c] = u0
        for b, value in ((1, u1), (2, u2), (3, u3)):
            if c + b < count:
                u[c + b] = value


@njit(cache=True, fastmath=True)
def _bounding_box(rows, columns, elements, count, ny, nx):
    """(first row, last row, first column, last column) of ``elements[:count]``; (ny, -1, nx, -1) if none."""
    r0, r1, c0, c1 = ny, -1, nx, -1
    for a in range(count):
        r0 = min(r0, rows[elements[a]])
        r1 = max(r1, rows[elements[a]])
        c0 = min(c0, columns[elements[a]])
        c1 = max(c1, columns[elements[a]])
    return r0, r1, c0, c1


@njit(cache=True, fastmath=True)
def _dot_rows(band, span, starts, group, size, u, zero):
    """u[group[g]] = band[starts[g] : starts[g] + size] . span, four at a time (sharing the loads of span), summed
    in the type of ``zero`` (that of ``band`` and ``span``)."""
    count = group.size
    for c in range(0, count, 4):
        s0, s1 = starts[c], starts[min(c + 1, count - 1)]
        s2, s3 = starts[min(c + 2, count - 1)], starts[min(c + 3, count - 1)]
        k0, k1, k2, k3 = band[s0 : s0 + size], band[s1 : s1 + size], band[s2 : s2 + size], band[s3 : s3 + size]
        u0 = u1 = u2 = u3 = zero
        for k in range(size):
            x = span[k]
            u0 += k0[k] * x
            u1 += k1[k] * x
            u2 += k2[k] * x
            u3 += k3[k] * x
        u[group[c]] = u0
        for b, value in ((1, u1), (2, u2), (3, u3)):
            if c + b < count:
                u[group[c + b]] = value


@njit(cache=True)
def displacement_kernel(grid, order, m, pressure, candidates, count, u):
    """u = C p at ``candidates[:count]`` from the reversed kernel: one contiguous dot product per element.

    The candidates go in groups of ``KERNEL_GROUP_COLUMNS`` columns. For a group whose columns spread over
    g, the set's bounding box of pressures (H x W) is laid out with the row stride S = W + g - 1, zero beyond
    column W, and the kernel's offsets that occur are copied with the same stride: the terms of an element
    are then one contiguous slice of that copy, of (H - 1) S + W terms (the zeros drop those that wrap into
    the next row); groups of the same spread share the layout of the pressures. Measured at 0.5 mm:
    ``docs/benchmarks.md``, "The contact solver".
    """
    _kernel_products(grid, order, m, pressure, candidates, count, u, 0.0)


@njit(cache=True)
def displacement_kernel32(grid, order, m, pressure, candidates, count, u):
    """u = C p at ``candidates[:count]`` as :func:`displacement_kernel`, with the kernel, the pressures and the
    sums in float32 (twice the lanes a vector instruction holds); the error bound is :func:`float32_error`."""
    _kernel_products(grid, order, m, pressure, candidates, count, u, np.float32(0.0))


@njit(cache=True, inline="always")
def float32_error(u, terms, scale):
    """Bound of |u - C p| for u from :func:`displacement_kernel32`: 2 gamma (|u| + ``scale``) with gamma =
    k 2^-24 / (1 - k 2^-24), k = ``terms`` + 8 (the nonzero pressures; each term's kernel value, pressure and
    product rounded once, each partial sum it enters once, in any order of summation; Higham, *Accuracy and
    Stability of Numerical Algorithms*, 2nd ed., section 3.1), twice for margin. ``scale`` = 2 C_0 P- bounds
    what the negative pressures P- add to sum |C_ij p_j| beyond |u| (C_ij <= C_0)."""
    k = (terms + 8) * 5.9604644775390625e-08
    return 2.0 * k / (1.0 - k) * (abs(u) + scale)


@njit(cache=True, inline="always")
def _kernel_products(grid, order, m, pressure, candidates, count, u, zero):
    """:func:`displacement_kernel` with the layouts and sums in the type of ``zero``."""
    kernel, flipped, _, rows, columns = grid
    ny = (kernel.shape[0] + 1) // 2
    nx = (kernel.shape[1] + 1) // 2
    r0, r1, c0, c1 = _bounding_box(rows, columns, order, m, ny, nx)
    if r1 < 0 or count == 0:
        for c in range(count):
            u[c] = 0.0
        return
    height, width = r1 + 1 - r0, c1 + 1 - c0
    band = np.full((height + ny - 1) * (width + KERNEL_GROUP_COLUMNS), zero)
    span = np.full(height * (width + KERNEL_GROUP_COLUMNS), zero)
    group = np.empty(count, dtype=np.int64)  # the candidates by group (ascending within one)
    elements = np.empty(count, dtype=np.int64)
    starts = np.empty(count, dtype=np.int64)
    _, _, first, last = _bounding_box(rows, columns, candidates, count, ny, nx)
    groups = (last - first) // KERNEL_GROUP_COLUMNS + 1
    ends = np.zeros(groups + 1, dtype=np.int64)  # the candidates of group k: group[ends[k] : ends[k + 1]]
    for c in range(count):
        ends[(columns[candidates[c]] - first) // KERNEL_GROUP_COLUMNS + 1] += 1
    for k in range(groups):
        ends[k + 1] += ends[k]
    for c in range(count):
        k = (columns[candidates[c]] - first) // KERNEL_GROUP_COLUMNS
        group[ends[k]] = c
        elements[ends[k]] = candidates[c]
        ends[k] += 1
    laid = -1  # the stride the pressures are laid out with (groups of the same spread share it)
    begin = 0
    for k in range(groups):
        end = ends[k]  # (moved on to the next group's start by the fill above)
        size = end - begin
        if size == 0:
            continue
        members = elements[begin:end]
        q0, q1, d0, d1 = _bounding_box(rows, columns, members, size, ny, nx)
        stride, depth = width + d1 - d0, height + q1 - q0
        # band[a S + b] = reversed[r0 - q1 + a + ny - 1, c0 - d1 + b + nx - 1]: offset (rj - ri, cj - ci)
        for a in range(depth):  # (loops, not slice assignments: those cost numba seconds of compilation)
            row = flipped[r0 - q1 + a + ny - 1]
            for b in range(stride):
                band[a * stride + b] = row[c0 - d1 + nx - 1 + b]
        if stride != laid:
            for a in range(height):
                line = pressure[(r0 + a) * nx + c0 : (r0 + a) * nx + c0 + width]
                for b in range(width):
                    span[a * stride + b] = line[b]
                for b in range(width, stride):
                    span[a * stride + b] = zero
            laid = stride
        for g in range(size):
            starts[begin + g] = (q1 - rows[members[g]]) * stride + d1 - columns[members[g]]
        _dot_rows(band, span, starts[begin:end], group[begin:end], (height - 1) * stride + width, u, zero)
        begin = end


@njit(cache=True)
def screen(grid, order, m, pressure, gap, candidates, count, limit):
    """Keep of ``candidates[:count]`` those that may penetrate (h + C p below ``limit``); their count.

    A lower bound of u_i = C_i p: the set's bounding box is cut into ``SCREEN_BLOCKS`` x ``SCREEN_BLOCKS``
    blocks; the kernel decreases with each offset, so C_ij >= C at a block's farthest corner from i for
    every j of the block, and u_i >= sum over blocks of C_far P+ (block) - C_0 P- (P+, P-: the sums of the
    positive and negative pressures). An element whose h_i + bound is not below the limit does not penetrate
    and is not computed (most of the rigid overlap outside the set, away from its border).

    The block of each row and column and the farthest offset of each block from each row and column of the
    window are tabulated once per call; the candidates' bounds are summed four at a time (independent chains
    of multiply-adds, each in the order of the blocks).
    """
    kernel, _, _, rows, columns = grid
    ny = (kernel.shape[0] + 1) // 2
    nx = (kernel.shape[1] + 1) // 2
    r0, r1, c0, c1 = _bounding_box(rows, columns, order, m, ny, nx)
    if r1 < 0:
        return count
    blocks = SCREEN_BLOCKS
    edges = np.empty((2, blocks + 1), dtype=np.int64)  # first row / column of each block, and one past the last
    for b in range(blocks + 1):
        edges[0, b] = r0 + ((r1 + 1 - r0) * b) // blocks
        edges[1, b] = c0 + ((c1 + 1 - c0) * b) // blocks
    row_block = np.empty(r1 + 1 - r0, dtype=np.int64)  # the block b with edges[b] <= row < edges[b + 1], times blocks
    column_block = np.empty(c1 + 1 - c0, dtype=np.int64)
    for b in range(blocks):
        for r in range(edges[0, b], edges[0, b + 1]):
            row_block[r - r0] = b * blocks
        for c in range(edges[1, b], edges[1, b + 1]):
            column_block[c - c0] = b
    sums = np.zeros(blocks * blocks)  # positive pressure per block, row-major
    negative = 0.0
    for a in range(m):
        i = order[a]
        value = pressure[i]
        if value > 0.0:
            sums[row_block[rows[i] - r0] + column_block[columns[i] - c0]] += value
        else:
            negative -= value
    slack = kernel[ny - 1, nx - 1] * negative
    # the farthest offset of each block from every row (flat index of the kernel's row) and every column
    width = kernel.shape[1]
    far_rows = np.empty((ny, blocks), dtype=np.int64)
    far_columns = np.empty((nx, blocks), dtype=np.int64)
    for b in range(blocks):
        last_row, last_column = max(edges[0, b], edges[0, b + 1] - 1), max(edges[1, b], edges[1, b + 1] - 1)
        for r in range(ny):
            far_rows[r, b] = (ny - 1 + max(abs(r - edges[0, b]), abs(r - last_row))) * width
        for c in range(nx):
            far_columns[c, b] = nx - 1 + max(abs(c - edges[1, b]), abs(c - last_column))
    flat = kernel.ravel()
    kept = 0
    for c in range(0, count, 4):
        i0, i1 = candidates[c], candidates[min(c + 1, count - 1)]
        i2, i3 = candidates[min(c + 2, count - 1)], candidates[min(c + 3, count - 1)]
        fr0, fr1, fr2, fr3 = far_rows[rows[i0]], far_rows[rows[i1]], far_rows[rows[i2]], far_rows[rows[i3]]
        fc0, fc1 = far_columns[columns[i0]], far_columns[columns[i1]]
        fc2, fc3 = far_columns[columns[i2]], far_columns[columns[i3]]
        b0, b1, b2, b3 = gap[i0] - slack, gap[i1] - slack, gap[i2] - slack, gap[i3] - slack
        for br in range(blocks):
            for bc in range(blocks):
                weight = sums[br * blocks + bc]
                b0 += flat[fr0[br] + fc0[bc]] * weight
                b1 += flat[fr1[br] + fc1[bc]] * weight
                b2 += flat[fr2[br] + fc2[bc]] * weight
                b3 += flat[fr3[br] + fc3[bc]] * weight
        for b, bound, i in ((0, b0, i0), (1, b1, i1), (2, b2, i2), (3, b3, i3)):
            if c + b < count and bound < limit:  # (kept <= c + b: the candidates still to read are not overwritten)
                candidates[kept] = i
                kept += 1
    return kept


@njit(cache=True)
def displacement_decided(grid, order, m, pressure, gap, elements, count, u, lower, limits):
    """u = C p at ``elements[:count]`` into ``u``, in float32 (``displacement_kernel32``) where that decides
    d = h - delta + u against ``glimit`` as float64 would, else in float64; a lower bound of each exact u into
    ``lower``.

    An element is computed again in float64 where d is within the float32 sum's error bound
    (:func:`float32_error`) plus 1e-12 of |h| + |delta| + |u| (float64's own rounding) of ``glimit``:
    the decisions are float64's. ``limits`` = (delta, glimit).
    """
    delta, glimit = limits
    kernel = grid[0]
    displacement_kernel32(grid, order, m, pressure, elements, count, u)
    negative = 0.0
    for a in range(m):
        negative -= min(pressure[order[a]], 0.0)
    scale = 2.0 * kernel[kernel.shape[0] // 2, kernel.shape[1] // 2] * negative
    again = np.empty(count, dtype=np.int64)
    n_again = 0
    for c in range(count):
        i = elements[c]
        d = gap[i] - delta + u[c]
        bound = float32_error(u[c], m, scale) + 1e-12 * (abs(gap[i]) + abs(delta) + abs(u[c]))
        lower[c] = u[c] - bound
        if abs(d - glimit) <= bound:
            again[n_again] = c
            n_again += 1
    if n_again > 0:
        chosen = np.empty(n_again, dtype=np.int64)
        exact = np.empty(n_again)
        for e in range(n_again):
            chosen[e] = elements[again[e]]
        displacement_kernel(grid, order, m, pressure, chosen, n_again, exact)
        for e in range(n_again):
            u[again[e]] = exact[e]


@njit(cache=True)
def displacement_kept(grid, order, m, work, count, limits):
    """u = C p at the candidates ``work[3][:count]`` into ``work[5]`` where a step's earlier check leaves it
    undecided (:func:`displacement_decided`), else a lower bound of u that shows d = h - delta + u >= glimit.

    ``work[7]`` = (a lower bound of u per element as of the step's last check or NaN, the elements that have
    one, [sum of the pressures' decreases since, how many have one]). A pressure change lowers u_i (i outside the
    set) by at most C_1 times the sum of the decreases, C_1 the kernel's largest value off its centre (the
    kernel decreases with each offset): a kept bound less that is a bound now. ``limits`` = (delta, glimit).
    """
    pressure, gap, _, changes, _, u, _, bounds = work
    known, listed, since = bounds
    delta, glimit = limits
    kernel = grid[0]
    cy, cx = kernel.shape[0] // 2, kernel.shape[1] // 2
    nearest = 0.0
    if cy > 0:
        nearest = max(kernel[cy - 1, cx], kernel[cy + 1, cx])
    if cx > 0:
        nearest = max(nearest, kernel[cy, cx - 1], kernel[cy, cx + 1])
    fall = nearest * since[0]
    if since[1] == 0.0:  # no bounds kept (a step's first check): all computed, in place
        lower = np.empty(count)
        displacement_decided(grid, order, m, pressure, gap, changes[:count], count, u, lower, limits)
        for c in range(count):
            listed[c] = changes[c]
            known[changes[c]] = lower[c]
        since[0] = 0.0
        since[1] = count
        return
    compute = np.empty(count, dtype=np.int64)
    n_compute = 0
    for c in range(count):
        i = changes[c]
        bound = known[i] - fall
        slack = 1e-12 * (abs(gap[i]) + abs(delta) + abs(known[i]) + fall)
        if bound == bound and gap[i] - delta + bound >= glimit + slack:
            u[c] = bound  # (NaN fails the test: no bound kept)
            known[i] = bound
        else:
            compute[n_compute] = c
            n_compute += 1
    if n_compute > 0:
        elements = np.empty(n_compute, dtype=np.int64)
        values = np.empty(n_compute)
        lower = np.empty(n_compute)
        for e in range(n_compute):
            elements[e] = changes[compute[e]]
        displacement_decided(grid, order, m, pressure, gap, elements, n_compute, values, lower, limits)
        n_listed = int(since[1])
        for e in range(n_compute):
            i = elements[e]
            u[compute[e]] = values[e]
            if known[i] != known[i]:
                listed[n_listed] = i
                n_listed += 1
            known[i] = lower[e]
        since[1] = n_listed
    since[0] = 0.0
