"""Quintic B-splines on clamped uniform grids, in JAX: the shipped tables' evaluator on device arrays.

The same splines as ``engine.bspline`` (knots and coefficients from the shipped files): the span
comes from the uniform grid (``engine.bspline._uniform_span``: the interval holding ``x``, clamped
to the grid), the six non-zero basis functions from de Boor's recursion (L. Piegl & W. Tiller,
*The NURBS Book*, algorithm A2.2) on the stored knots, which covers the clamped ends too.  Several
splines of one table (its regions) are stacked, padded to the largest, and picked per point by a
region index, so that a point costs one spline whatever its region.

A stacked spline is a dict of arrays: ``t`` (R, L) knots, ``c`` (R, n + 4) or (R, nx + 4, ny + 4)
coefficients, ``grid`` (R, 3) or (R, 6): (first node, spacing, node count) per direction.
"""

import jax.numpy as jnp
import numpy as np

DEGREE = 5


def _span(x, grid):
    """Span ``m`` (knot index, ``t[m] <= x < t[m + 1]``) of ``x`` on the grid (first, step, count)."""
    x0, h, n = grid[..., 0], grid[..., 1], grid[..., 2]
    j = jnp.clip(jnp.floor((x - x0) / h), 0.0, n - 2.0)
    return j.astype(jnp.int32) + DEGREE


def _basis(t, m, x):
    """The six non-zero quintic basis functions at ``x`` on span ``m`` (shape (..., 6))."""
    left = [None] + [x - _take(t, m + 1 - j) for j in range(1, DEGREE + 1)]
    right = [None] + [_take(t, m + j) - x for j in range(1, DEGREE + 1)]
    N = [jnp.ones_like(x)]
    for j in range(1, DEGREE + 1):
        saved = jnp.zeros_like(x)
        nxt = []
        for r in range(j):
            temp = N[r] / (right[r + 1] + left[j - r])
            nxt.append(saved + right[r + 1] * temp)
            saved = left[j - r] * temp
        N = [*nxt, saved]
    return jnp.stack(N, axis=-1)


def _take(t, idx):
    """``t[..., idx]`` per point: ``t`` is (P, L) (one knot row per point) or (L,)."""
    if t.ndim == 1:
        return t[idx]
    return jnp.take_along_axis(t, idx[..., None], axis=-1)[..., 0]


def eval_1d(t, c, grid, x):
    """Value at ``x`` of the spline (knots ``t``, coefficients ``c``, grid (first, step, count))."""
    m = _span(x, grid)
    N = _basis(t, m, x)
    rows = m[..., None] - DEGREE + jnp.arange(DEGREE + 1)
    return jnp.sum(c[rows] * N, axis=-1)


def eval_2d(spl, region, x, y):
    """Value at ``(x, y)`` of region ``region``'s tensor spline of the stacked ``spl``."""
    grid = spl["grid"][region]
    mx = _span(x, grid[..., :3])
    my = _span(y, grid[..., 3:])
    Nx = _basis(spl["tx"][region], mx, x)
    Ny = _basis(spl["ty"][region], my, y)
    k = jnp.arange(DEGREE + 1)
    ix = (mx[..., None] - DEGREE + k)[..., :, None]
    iy = (my[..., None] - DEGREE + k)[..., None, :]
    block = spl["c"][region[..., None, None], ix, iy]
    return jnp.einsum("...i,...ij,...j->...", Nx, block, Ny)


def stack(regions):
    """Stacked device arrays of 2-D splines ``[(tx, ty, c, grid6), ...]`` (padding never read)."""
    lx = max(r[0].size for r in regions)
    ly = max(r[1].size for r in regions)
    cx = max(r[2].shape[0] for r in regions)
    cy = max(r[2].shape[1] for r in regions)
    tx = np.stack([np.pad(r[0], (0, lx - r[0].size), mode="edge") for r in regions])
    ty = np.stack([np.pad(r[1], (0, ly - r[1].size), mode="edge") for r in regions])
    c = np.stack([np.pad(r[2], ((0, cx - r[2].shape[0]), (0, cy - r[2].shape[1]))) for r in regions])
    grid = np.stack([np.asarray(r[3], dtype=float) for r in regions])
    return {k: jnp.asarray(v) for k, v in (("tx", tx), ("ty", ty), ("c", c), ("grid", grid))}
