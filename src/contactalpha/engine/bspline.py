"""Jitted evaluation of 1-D and tensor-product 2-D B-splines (de Boor's basis recursion).

The splines themselves are built by SciPy (``make_interp_spline``,
``RectBivariateSpline``); only their knots and coefficients are stored, and
these kernels evaluate them inside numba code.  Basis functions follow
L. Piegl & W. Tiller, *The NURBS Book*, algorithm A2.2.
"""

import numpy as np
from numba import njit

# Largest spline degree supported by the fixed-size work arrays.
MAX_DEGREE = 5


@njit(cache=True, error_model="numpy")
def find_span(t, k, n, x):
    """Index ``m`` with ``t[m] <= x < t[m+1]``, clamped to ``k <= m <= n - 1``."""
    if x >= t[n]:
        return n - 1
    if x <= t[k]:
        return k
    lo = k
    hi = n
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if x >= t[mid]:
            lo = mid
        else:
            hi = mid
    return lo


@njit(cache=True, error_model="numpy")
def basis(t, k, m, x, N, left, right):
    """Fill ``N[0..k]`` with the non-zero degree-``k`` basis functions on span ``m``."""
    N[0] = 1.0
    for j in range(1, k + 1):
        left[j] = x - t[m + 1 - j]
        right[j] = t[m + j] - x
        saved = 0.0
        for r in range(j):
            temp = N[r] / (right[r + 1] + left[j - r])
            N[r] = saved + right[r + 1] * temp
            saved = left[j - r] * temp
        N[j] = saved


@njit(cache=True, error_model="numpy")
def eval_1d(t, c, k, x):
    """Value at ``x`` of the spline with knots ``t``, coefficients ``c``, degree ``k``."""
    n = c.size
    N = np.empty(MAX_DEGREE + 1)
    left = np.empty(MAX_DEGREE + 1)
    right = np.empty(MAX_DEGREE + 1)
    m = find_span(t, k, n, x)
    basis(t, k, m, x, N, left, right)
    acc = 0.0
    for r in range(k + 1):
        acc += c[m - k + r] * N[r]
    return acc


@njit(cache=True, error_model="numpy")
def eval_2d(tx, ty, c, kx, ky, x, y):
    """Value at ``(x, y)`` of a tensor-product spline; ``c`` has shape (nx, ny)."""
    nx, ny = c.shape
    Nx = np.empty(MAX_DEGREE + 1)
    Ny = np.empty(MAX_DEGREE + 1)
    left = np.empty(MAX_DEGREE + 1)
    right = np.empty(MAX_DEGREE + 1)
    mx = find_span(tx, kx, nx, x)
    my = find_span(ty, ky, ny, y)
    basis(tx, kx, mx, x, Nx, left, right)
    basis(ty, ky, my, y, Ny, left, right)
    acc = 0.0
    for i in range(kx + 1):
        row = 0.0
        for j in range(ky + 1):
            row += c[mx - kx + i, my - ky + j] * Ny[j]
        acc += Nx[i] * row
    return acc


# Fast path for quintic splines whose knots are the nodes of a uniform grid
# (clamped at both ends): inside, the six non-zero basis functions are the
# cardinal quintic B-spline pieces, polynomials in the local coordinate.
@njit(cache=True, error_model="numpy", inline="always")
def _cardinal_quintic(t):
    t2 = t * t
    t3 = t2 * t
    t4 = t3 * t
    t5 = t4 * t
    s = 1.0 - t
    s2 = s * s
    return (
        s2 * s2 * s / 120.0,
        (26.0 - 50.0 * t + 20.0 * t2 + 20.0 * t3 - 20.0 * t4 + 5.0 * t5) / 120.0,
        (66.0 - 60.0 * t2 + 30.0 * t4 - 10.0 * t5) / 120.0,
        (26.0 + 50.0 * t + 20.0 * t2 - 20.0 * t3 - 20.0 * t4 + 10.0 * t5) / 120.0,
        (1.0 + 5.0 * t + 10.0 * t2 + 10.0 * t3 + 5.0 * t4 - 5.0 * t5) / 120.0,
        t5 / 120.0,
    )


@njit(cache=True, error_model="numpy", inline="always")
def _uniform_span(x, x0, h, n):
    """Interval ``j`` of a uniform grid of ``n`` nodes holding ``x``, and the local coordinate."""
    s = (x - x0) / h
    j = int(np.floor(s))
    if j < 0:
        j = 0
    elif j > n - 2:
        j = n - 2
    return j, s - j


@njit(cache=True, error_model="numpy")
def eval_1d_uniform(t, c, x0, h, n, x):
    """Quintic spline on a clamped uniform grid of ``n`` nodes (``c`` has ``n + 4`` entries)."""
    j, loc = _uniform_span(x, x0, h, n)
    if j < 5 or j > n - 7:
        return eval_1d(t, c, 5, x)
    b = _cardinal_quintic(loc)
    acc = 0.0
    for r in range(6):
        acc += c[j + r] * b[r]
    return acc


@njit(cache=True, error_model="numpy")
def eval_2d_uniform(tx, ty, c, x0, hx, nx, y0, hy, ny, x, y):
    """Tensor quintic spline on clamped uniform grids (``c`` has shape ``(nx + 4, ny + 4)``)."""
    jx, lx = _uniform_span(x, x0, hx, nx)
    jy, ly = _uniform_span(y, y0, hy, ny)
    if jx < 5 or jx > nx - 7 or jy < 5 or jy > ny - 7:
        return eval_2d(tx, ty, c, 5, 5, x, y)
    bx = _cardinal_quintic(lx)
    by = _cardinal_quintic(ly)
    acc = 0.0
    for i in range(6):
        row = 0.0
        for r in range(6):
            row += c[jx + i, jy + r] * by[r]
        acc += bx[i] * row
    return acc


def clamp_to_uniform(t, c, k, nodes, axis=0):
    """Insert every grid node missing from the knot vector ``t`` (exact knot refinement).

    SciPy's not-a-knot interpolants leave out the nodes next to each end; with
    them inserted every interior knot is a node, which ``eval_*_uniform`` need.
    Returns the new knots and coefficients (``axis`` is the coefficient axis).
    """
    from scipy.interpolate import BSpline

    c = np.moveaxis(np.asarray(c, dtype=float), axis, 0)
    spl = BSpline(t, c, k)
    for node in nodes[1:-1]:
        if not np.any(spl.t == node):
            spl = spl.insert_knot(node)
    return spl.t, np.moveaxis(spl.c, 0, axis)
