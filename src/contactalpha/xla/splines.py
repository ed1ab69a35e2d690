"""Quintic B-splines on clamped uniform grids, in JAX: the shipped tables' evaluator on device arrays.

The same splines as ``engine.bspline`` (coefficients from the shipped files): the span comes from
the uniform grid (``engine.bspline._uniform_span``: the interval holding ``x``, clamped to the
grid), the six non-zero basis functions from de Boor's recursion (L. Piegl & W. Tiller, *The NURBS
Book*, algorithm A2.2) on the grid's clamped knots, which covers the ends too.  Several
splines of one table (its regions) are stacked, padded to the largest, and picked per point by a
region index, so that a point costs one spline whatever its region.

A stacked spline is a dict of arrays: ``c`` (R, nx + 4, ny + 4) coefficients and ``grid`` (R, 6):
(first node, spacing, node count) per direction.  ``stack`` checks that the stored knots are the
grid's (the evaluator computes them).
"""

import jax.numpy as jnp
import numpy as np

DEGREE = 5


def _span(x, grid):
    """Interval ``j`` of ``x`` on the grid (first, step, count), clamped, and ``x`` in steps from x0."""
    x0, h, n = grid[..., 0], grid[..., 1], grid[..., 2]
    X = (x - x0) / h
    return jnp.clip(jnp.floor(X), 0.0, n - 2.0), X, n


def _basis(j, X, n):
    """The six non-zero quintic basis functions on interval ``j`` at ``X`` (shape (..., 6)).

    The clamped uniform knots are ``T_i = clip(i, 0, n - 1)`` nodes from the first (``DEGREE + 1``
    copies at each end), so that no knot is read from memory; in units of the step the recursion
    is de Boor's on the stored knots (which are these nodes).
    """
    knot = lambda i: jnp.clip(j + i, 0.0, n - 1.0)  # noqa: E731
    left = [None] + [X - knot(1 - k) for k in range(1, DEGREE + 1)]
    right = [None] + [knot(k) - X for k in range(1, DEGREE + 1)]
    N = [jnp.ones_like(X)]
    for k in range(1, DEGREE + 1):
        saved = jnp.zeros_like(X)
        nxt = []
        for r in range(k):
            temp = N[r] / (right[r + 1] + left[k - r])
            nxt.append(saved + right[r + 1] * temp)
            saved = left[k - r] * temp
        N = [*nxt, saved]
    return jnp.stack(N, axis=-1)


def eval_1d(c, grid, x):
    """Value at ``x`` of the spline with coefficients ``c`` on the grid (first, step, count)."""
    j, X, n = _span(x, grid)
    N = _basis(j, X, n)
    rows = j.astype(jnp.int32)[..., None] + jnp.arange(DEGREE + 1)
    return jnp.sum(c[rows] * N, axis=-1)


def eval_2d(spl, region, x, y):
    """Value at ``(x, y)`` of region ``region``'s tensor spline of the stacked ``spl``."""
    grid = spl["grid"][region]
    jx, X, nx = _span(x, grid[..., :3])
    jy, Y, ny = _span(y, grid[..., 3:])
    Nx = _basis(jx, X, nx)
    Ny = _basis(jy, Y, ny)
    k = jnp.arange(DEGREE + 1)
    ix = (jx.astype(jnp.int32)[..., None] + k)[..., :, None]
    iy = (jy.astype(jnp.int32)[..., None] + k)[..., None, :]
    block = spl["c"][region[..., None, None], ix, iy]
    return jnp.einsum("...i,...ij,...j->...", Nx, block, Ny)


def grid_knots(grid):
    """The clamped uniform knots of a grid (first, step, count): ``DEGREE + 1`` copies at each end."""
    x0, h, n = float(grid[0]), float(grid[1]), int(grid[2])
    return x0 + h * np.clip(np.arange(n + 2 * DEGREE) - DEGREE, 0, n - 1)


def check_knots(t, grid, what):
    """Raise unless the stored knots ``t`` are the grid's to rounding (the evaluator computes them)."""
    want = grid_knots(grid)
    if t.shape != want.shape or not np.allclose(t, want, rtol=1e-13, atol=1e-13 * np.abs(want).max()):
        raise ValueError(f"{what}: stored knots are not the clamped uniform knots of its grid {list(grid)}")


def stack(regions):
    """Stacked device arrays of 2-D splines ``[(tx, ty, c, grid6), ...]`` (padding never read)."""
    for r, (tx, ty, _, grid) in enumerate(regions):
        check_knots(tx, grid[:3], f"region {r}, first axis")
        check_knots(ty, grid[3:], f"region {r}, second axis")
    cx = max(r[2].shape[0] for r in regions)
    cy = max(r[2].shape[1] for r in regions)
    c = np.stack([np.pad(r[2], ((0, cx - r[2].shape[0]), (0, cy - r[2].shape[1]))) for r in regions])
    grid = np.stack([np.asarray(r[3], dtype=float) for r in regions])
    return {"c": jnp.asarray(c), "grid": jnp.asarray(grid)}
