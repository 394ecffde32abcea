"""Cholesky factor of the contact set's influence matrix for the active set (``contact.active_set``), compiled.

The factor C_AA = U^T U of the contact set (rows in the set's order), its updates when an element joins (a new
row, O(m^2)) or leaves (a rank-1 downdate by rotations, O(m^2)), with z = U^-T 1 kept alongside, and the two
triangular solves. Hand-written loops over views that start at index 0 (numba vectorises them); why and
measured figures: ``docs/benchmarks.md``, "The contact solver". :func:`factorize` takes ``grid`` = (kernel, rows,
columns), :func:`append` the solver's grid (``active_set.influence_grid``): C's elements come from the kernel of
eq. 8 or the influence matrix; ``order[:m]`` is the set.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["append", "backward", "factorize", "forward", "invert", "remove", "symmetric_product"]


@njit(cache=True, fastmath=True)
def factorize(grid, order, m, upper):
    """Upper Cholesky factor U (C_AA = U^T U) of the contact set ``order[:m]`` into ``upper[:m, :m]``.

    ``grid`` = (kernel, rows, columns). Computed as the lower factor L = U^T with row-wise dot products, then
    transposed. Returns False if C_AA is not positive definite.
    """
    kernel, rows, columns = grid
    ny = (kernel.shape[0] + 1) // 2
    nx = (kernel.shape[1] + 1) // 2
    lower = np.empty((m, m))
    for a in range(m):
        row = rows[order[a]] + ny - 1
        column = columns[order[a]] + nx - 1
        for b in range(a + 1):
            lower[a, b] = kernel[row - rows[order[b]], column - columns[order[b]]]
    for j in range(m):
        pivot = lower[j, j]
        for k in range(j):
            pivot -= lower[j, k] * lower[j, k]
        if pivot <= 0.0:
            return False
        d = math.sqrt(pivot)
        lower[j, j] = d
        for i in range(j + 1, m):
            t = lower[i, j]
            for k in range(j):
                t -= lower[i, k] * lower[j, k]
            lower[i, j] = t / d
    for a in range(m):
        for b in range(a + 1):
            upper[b, a] = lower[a, b]
    return True


@njit(cache=True, fastmath=True)
def forward(upper, m, rhs):
    """Solve U^T y = rhs in place: rows of U contiguous, axpys on the unsolved tail, four rows at a time."""
    k = 0
    while k + 4 <= m:
        y0 = rhs[k] / upper[k, k]
        y1 = (rhs[k + 1] - upper[k, k + 1] * y0) / upper[k + 1, k + 1]
        y2 = (rhs[k + 2] - upper[k, k + 2] * y0 - upper[k + 1, k + 2] * y1) / upper[k + 2, k + 2]
        y3 = (rhs[k + 3] - upper[k, k + 3] * y0 - upper[k + 1, k + 3] * y1 - upper[k + 2, k + 3] * y2) / upper[
            k + 3, k + 3
        ]
        rhs[k], rhs[k + 1], rhs[k + 2], rhs[k + 3] = y0, y1, y2, y3
        r0, r1, r2, r3 = upper[k, k + 4 : m], upper[k + 1, k + 4 : m], upper[k + 2, k + 4 : m], upper[k + 3, k + 4 : m]
        tail = rhs[k + 4 : m]
        for j in range(tail.size):
            tail[j] -= r0[j] * y0 + r1[j] * y1 + r2[j] * y2 + r3[j] * y3
        k += 4
    for i in range(k, m):
        y = rhs[i] / upper[i, i]
        rhs[i] = y
        row = upper[i, i + 1 : m]
        tail = rhs[i + 1 : m]
        for j in range(tail.size):
            tail[j] -= row[j] * y


@njit(cache=True, fastmath=True)
def backward(upper, m, rhs):
    """Solve U x = rhs in place: dot products of rows of U with the solved tail, four rows at a time."""
    k = m
    while k >= 4:
        r0, r1, r2, r3 = upper[k - 4, k:m], upper[k - 3, k:m], upper[k - 2, k:m], upper[k - 1, k:m]
        tail = rhs[k:m]
        s0 = s1 = s2 = s3 = 0.0
        for j in range(tail.size):
            x = tail[j]
            s0 += r0[j] * x
            s1 += r1[j] * x
            s2 += r2[j] * x
            s3 += r3[j] * x
        x3 = (rhs[k - 1] - s3) / upper[k - 1, k - 1]
        x2 = (rhs[k - 2] - s2 - upper[k - 2, k - 1] * x3) / upper[k - 2, k - 2]
        x1 = (rhs[k - 3] - s1 - upper[k - 3, k - 2] * x2 - upper[k - 3, k - 1] * x3) / upper[k - 3, k - 3]
        x0 = (rhs[k - 4] - s0 - upper[k - 4, k - 3] * x1 - upper[k - 4, k - 2] * x2 - upper[k - 4, k - 1] * x3) / upper[
            k - 4, k - 4
        ]
        rhs[k - 4], rhs[k - 3], rhs[k - 2], rhs[k - 1] = x0, x1, x2, x3
        k -= 4
    for i in range(k - 1, -1, -1):
        row = upper[i, i + 1 : m]
        tail = rhs[i + 1 : m]
        s = 0.0
        for j in range(tail.size):
            s += row[j] * tail[j]
        rhs[i] = (rhs[i] - s) / upper[i, i]


@njit(cache=True, fastmath=True)
def append(grid, order, m, upper, vectors, column, element):
    """Add ``element`` as row/column m of the factor and entry m of z = U^-T 1 and y = U^-T h, O(m^2): U^T w =
    C_Ae, U[m, m] = sqrt(C_ee - w.w), z_m = (1 - w.z) / U[m, m], y_m = (h_e - w.y) / U[m, m]. ``vectors`` =
    (z, y, h on the window). Returns False if not positive definite."""
    z, y, h = vectors
    kernel, _, full, rows, columns = grid
    ny = (kernel.shape[0] + 1) // 2
    nx = (kernel.shape[1] + 1) // 2
    if full.shape[0] > 0:
        row = full[element]
        for a in range(m):
            column[a] = row[order[a]]
    else:
        for a in range(m):
            column[a] = kernel[rows[element] - rows[order[a]] + ny - 1, columns[element] - columns[order[a]] + nx - 1]
    forward(upper, m, column)
    square = kernel[ny - 1, nx - 1]
    s = 1.0
    t = h[element]
    for k in range(m):
        upper[k, m] = column[k]
        square -= column[k] * column[k]
        s -= column[k] * z[k]
        t -= column[k] * y[k]
    if square <= 0.0:
        return False
    upper[m, m] = math.sqrt(square)
    z[m] = s / upper[m, m]
    y[m] = t / upper[m, m]
    order[m] = element
    return True


@njit(cache=True, fastmath=True)
def remove(order, m, upper, vectors, scratch, position):
    """Remove the element at ``position`` from the factor of size m and from z = U^-T 1 and y = U^-T h
    (``vectors`` = (z, y)), O(m^2).

    The factor's trailing block gets the rank-1 update U33^T U33 + u u^T (u = U[position, position+1:]) by
    rotations (Golub and Van Loan, *Matrix Computations*, 4th ed., section 6.5.4); the same rotations applied
    to (z3, z_position) give the new trailing part of z, and likewise of y.
    """
    z, y = vectors
    p = position
    x = scratch
    for j in range(p + 1, m):
        x[j] = upper[p, j]
    t = z[p]
    v = y[p]
    for i in range(p + 1, m):
        diagonal = upper[i, i]
        xi = x[i]
        r = math.sqrt(diagonal * diagonal + xi * xi)
        c = r / diagonal
        s = xi / diagonal
        upper[i, i] = r
        row = upper[i, i + 1 : m]
        rest = x[i + 1 : m]
        for j in range(row.size):
            updated = (row[j] + s * rest[j]) / c
            row[j] = updated
            rest[j] = c * rest[j] - s * updated
        zi = (z[i] + s * t) / c
        z[i] = zi
        t = c * t - s * zi
        yi = (y[i] + s * v) / c
        y[i] = yi
        v = c * v - s * yi
    for i in range(p):
        row = upper[i, p:m]
        for j in range(row.size - 1):
            row[j] = row[j + 1]
    for i in range(p, m - 1):
        target = upper[i, i : m - 1]
        source = upper[i + 1, i + 1 : m]
        for j in range(target.size):
            target[j] = source[j]
        z[i] = z[i + 1]
        y[i] = y[i + 1]
        order[i] = order[i + 1]


@njit(cache=True, fastmath=True)
def invert(upper, m, inverse):
    """C_AA^-1 = U^-1 U^-T into ``inverse[:m, :m]`` (both triangles) from the factor ``upper``, O(m^3).

    Row i of W = U^-1 solves U^T w = e_i (zero before i: :func:`forward` on the trailing block), stored in
    row i; then entry (i, j >= i) of W W^T is the dot product of rows i and j of W from column j on, written
    over row i in ascending j (which later entries of row i and later rows no longer read); the lower triangle
    is mirrored from the upper.
    """
    for i in range(m):
        row = inverse[i]
        for a in range(i, m):
            row[a] = 0.0
        row[i] = 1.0
        forward(upper[i:, i:], m - i, row[i:])
    for i in range(m):
        row = inverse[i]
        for j in range(i, m):
            left, right = row[j:m], inverse[j, j:m]
            total = 0.0
            for b in range(left.size):
                total += left[b] * right[b]
            row[j] = total
    for i in range(m):
        for j in range(i):
            inverse[i, j] = inverse[j, i]


@njit(cache=True, fastmath=True)
def symmetric_product(matrix, m, x, out):
    """out[:m] = S x for the symmetric S = ``matrix[:m, :m]`` read from its upper triangle only, once: for
    each block of four rows, their dot products with x's tail and their axpys into out's tail in one pass."""
    for a in range(m):
        out[a] = 0.0
    i = 0
    while i + 4 <= m:
        for p in range(4):
            s = matrix[i + p, i + p] * x[i + p]
            for q in range(p + 1, 4):
                s += matrix[i + p, i + q] * x[i + q]
                out[i + q] += matrix[i + p, i + q] * x[i + p]
            out[i + p] += s
        r0, r1 = matrix[i, i + 4 : m], matrix[i + 1, i + 4 : m]
        r2, r3 = matrix[i + 2, i + 4 : m], matrix[i + 3, i + 4 : m]
        xt, yt = x[i + 4 : m], out[i + 4 : m]
        x0, x1, x2, x3 = x[i], x[i + 1], x[i + 2], x[i + 3]
        s0 = s1 = s2 = s3 = 0.0
        for a in range(xt.size):
            v = xt[a]
            s0 += r0[a] * v
            s1 += r1[a] * v
            s2 += r2[a] * v
            s3 += r3[a] * v
            yt[a] += x0 * r0[a] + x1 * r1[a] + x2 * r2[a] + x3 * r3[a]
        out[i] += s0
        out[i + 1] += s1
        out[i + 2] += s2
        out[i + 3] += s3
        i += 4
    for a in range(i, m):
        s = matrix[a, a] * x[a]
        for b in range(a + 1, m):
            s += matrix[a, b] * x[b]
            out[b] += matrix[a, b] * x[a]
        out[a] += s
