"""Quintic B-splines on clamped uniform grids, in JAX: the shipped tables' evaluator on device arrays.

The same splines as ``engine.bspline`` (coefficients from the shipped files): the span comes from
the uniform grid (``engine.bspline._uniform_span``: the interval holding ``x``, clamped to the
grid).  A 1-D spline (a table's cut curves) takes its six non-zero basis functions from de Boor's
recursion (L. Piegl & W. Tiller, *The NURBS Book*, algorithm A2.2) on the grid's clamped knots,
which covers the ends too.  A 2-D spline is stored per grid cell as its polynomial: on each cell
a tensor quintic is ``sum_mq P[m, q] dx^m dy^q`` exactly, in the offsets ``dx``, ``dy`` from the
cell's centre, its 36 Taylor coefficients computed once from the B-spline by SciPy (derivatives
at the centre); a point then reads one contiguous row of 36 numbers and runs Horner's scheme,
where the B-spline form gathered 36 scattered coefficients and ran two basis recursions (the
polynomial agrees with it to 3e-14 in the tables' ``L``).  Several splines of one table (its
regions) are stacked, padded to the largest, and picked per point by a region index, so that a
point costs one spline whatever its region.

A stacked spline is a dict of arrays: ``pp`` (R, nx - 1, ny - 1, 36) cell polynomials and ``grid``
(R, 6): (first node, spacing, node count) per direction.  ``stack`` checks that the stored knots
are the grid's (the evaluator computes them).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import jax.numpy as jnp
import numpy as np

if TYPE_CHECKING:
    import jax
    from jax.typing import ArrayLike

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


def eval_1d(c: jax.Array, grid: ArrayLike, x: ArrayLike) -> jax.Array:
    """Value at ``x`` of the spline with coefficients ``c`` on the grid (first, step, count)."""
    j, X, n = _span(x, grid)
    N = _basis(j, X, n)
    rows = j.astype(jnp.int32)[..., None] + jnp.arange(DEGREE + 1)
    return jnp.sum(c[rows] * N, axis=-1)


def eval_2d(spl: dict[str, jax.Array], region: ArrayLike, x: ArrayLike, y: ArrayLike) -> jax.Array:
    """Value at ``(x, y)`` of region ``region``'s tensor spline of the stacked ``spl``."""
    grid = spl["grid"][region]
    jx, X, _ = _span(x, grid[..., :3])
    jy, Y, _ = _span(y, grid[..., 3:])
    dx = (X - jx - 0.5) * grid[..., 1]
    dy = (Y - jy - 0.5) * grid[..., 4]
    P = spl["pp"][region, jx.astype(jnp.int32), jy.astype(jnp.int32)]  # (..., 36): P[m, q] at 6 m + q
    value = jnp.zeros_like(dx)
    for m in range(DEGREE, -1, -1):
        row = P[..., 6 * m + DEGREE]
        for q in range(DEGREE - 1, -1, -1):
            row = row * dy + P[..., 6 * m + q]
        value = value * dx + row
    return value


def cell_polynomials(tx: np.ndarray, ty: np.ndarray, c: np.ndarray, grid: Sequence[float]) -> np.ndarray:
    """Taylor coefficients ``P[jx, jy, 6 m + q]`` of a tensor quintic about each cell's centre.

    ``P[.., 6 m + q]`` multiplies ``dx^m dy^q``; ``(tx, ty, c)`` the B-spline, ``grid`` its
    (first node, spacing, node count) per direction.  Along x, then along y, the m-th derivative
    at the centre over m!: the quintic is one polynomial on each cell, so this is exact.
    """
    from scipy.interpolate import BSpline

    x0, hx, nx, y0, hy, ny = (float(v) for v in grid)
    mid_x = x0 + (np.arange(int(nx) - 1) + 0.5) * hx
    mid_y = y0 + (np.arange(int(ny) - 1) + 0.5) * hy
    along_x = BSpline(tx, c, DEGREE)
    dx = np.stack([along_x(mid_x, nu=m) / math.factorial(m) for m in range(DEGREE + 1)], axis=-1)
    along_y = BSpline(ty, np.moveaxis(dx, 1, 0), DEGREE)  # (ny + 4, nx - 1, 6): y-coefficients
    P = np.stack([along_y(mid_y, nu=q) / math.factorial(q) for q in range(DEGREE + 1)], axis=-1)
    return np.moveaxis(P, 0, 1).reshape(int(nx) - 1, int(ny) - 1, (DEGREE + 1) ** 2)


def grid_knots(grid: Sequence[float]) -> np.ndarray:
    """The clamped uniform knots of a grid (first, step, count): ``DEGREE + 1`` copies at each end."""
    x0, h, n = float(grid[0]), float(grid[1]), int(grid[2])
    return x0 + h * np.clip(np.arange(n + 2 * DEGREE) - DEGREE, 0, n - 1)


def check_knots(t: np.ndarray, grid: Sequence[float], what: str) -> None:
    """Raise unless the stored knots ``t`` are the grid's to rounding (the evaluator computes them)."""
    want = grid_knots(grid)
    if t.shape != want.shape or not np.allclose(t, want, rtol=1e-13, atol=1e-13 * np.abs(want).max()):
        raise ValueError(f"{what}: stored knots are not the clamped uniform knots of its grid {list(grid)}")


def stack(
    regions: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray, Sequence[float]]],
) -> dict[str, jax.Array]:
    """Stacked device arrays of 2-D splines ``[(tx, ty, c, grid6), ...]`` (padding never read)."""
    for r, (tx, ty, _, grid) in enumerate(regions):
        check_knots(tx, grid[:3], f"region {r}, first axis")
        check_knots(ty, grid[3:], f"region {r}, second axis")
    cells = [cell_polynomials(*r) for r in regions]
    cx = max(p.shape[0] for p in cells)
    cy = max(p.shape[1] for p in cells)
    pp = np.stack([np.pad(p, ((0, cx - p.shape[0]), (0, cy - p.shape[1]), (0, 0))) for p in cells])
    grids = np.stack([np.asarray(r[3], dtype=float) for r in regions])
    return {"pp": jnp.asarray(pp), "grid": jnp.asarray(grids)}
