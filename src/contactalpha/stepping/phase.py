"""Restitution over the touchdown phase: the mean over a uniform phase, exact across the jumps.

A drop's e_N is a function of the phase ``phi`` in [0, 1) at which touchdown falls within a step.
It is smooth except where the number of steps in contact changes: there a step's start crosses
the contact surface and e_N jumps.  ``phase_mean`` finds every such phase to machine precision
and integrates each smooth piece by adaptive Gauss-Lobatto quadrature:

1. ``GRID`` evenly spaced phases give the steps in contact; between two neighbours that differ,
   bisection on the count places the jump (to ``JUMP_TOL`` in phase), repeated until the count
   just right of the last jump is the right neighbour's;
2. each piece, first cut at multiples of ``1/SPLIT``, is integrated adaptively: the
   ``GL_NODES``-point Gauss-Lobatto rule on an interval is compared with the same rule on its two
   halves; an interval whose two estimates differ by more than ``tol`` times its length is split
   (the force floor's kinks, where a step's force reaches zero, are found this way: Lobatto's
   nodes include the interval's ends, so no kink hides between the last node and an end), else
   the halves' sum is kept and the difference added to the error estimate ``P_ERR``.

Every drop evaluated (grid, both sides of each jump, every node) enters the minimum and maximum a
single drop sees; the standard deviation comes from the same quadrature of e_N^2.  Stronge's eps
is integrated alongside.
"""

import math

import numpy as np
from numba import njit

from .codes import (
    CAPTURED,
    D_EN,
    D_EPS,
    D_STATUS,
    D_STEPS,
    N_PHASE,
    P_EPS_MAX,
    P_EPS_MEAN,
    P_EPS_MIN,
    P_EPS_STD,
    P_ERR,
    P_EVALS,
    P_JUMPS,
    P_MAX,
    P_MEAN,
    P_MIN,
    P_STATUS,
    P_STD,
    P_STEPS_MAX,
    P_STEPS_MIN,
    QUAD_LIMIT,
    SEPARATED,
)
from .drop import drop_kernel
from .kernels import for_engine

# Phases sampled first to find the pieces.
GRID = 64
# Jumps are placed to this width in phase.
JUMP_TOL = 1e-15
# Nodes of the Gauss-Lobatto rule on each interval (exact for polynomials of degree 2n - 3).
GL_NODES = 9
# The pieces are first cut at multiples of 1/SPLIT, so no interval starts longer than that.
SPLIT = 16
# Default error tolerance per unit phase of the adaptive quadrature, and its interval budget.
QUAD_TOL = 1e-11
MAX_INTERVALS = 4000


def lobatto(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Lobatto nodes and weights on [-1, 1]: the ends and the roots of P'_{n-1}."""
    c = np.zeros(n)
    c[-1] = 1.0  # P_{n-1}
    inner = np.sort(np.polynomial.legendre.legroots(np.polynomial.legendre.legder(c)))
    x = np.concatenate(([-1.0], inner, [1.0]))
    w = 2.0 / (n * (n - 1) * np.polynomial.legendre.legval(x, c) ** 2)
    return x, w


GL_X, GL_W = lobatto(GL_NODES)
# The end nodes at phase 0 and 1 are evaluated at these: the limits from inside [0, 1).  A drop
# whose touchdown falls exactly on a step's start (phase 0) starts at z = 0, which an engine whose
# contact includes z = 0 (Drake) treats as the limit from phase 1; 1e-300 of a step is a touchdown
# just after the start (still a normal float once multiplied by the step).
FIRST_PHASE = 1e-300
LAST_PHASE = float(np.nextafter(1.0, 0.0))


@njit(cache=True)
def _gl(code, p, h, v_in, accel, max_steps, a, b, acc, xs, ws):
    """GL on [a, b] of (e, e^2, eps, eps^2); drops folded into ``acc`` (min/max/status/evals)."""
    q = np.zeros(4)
    half = 0.5 * (b - a)
    mid = 0.5 * (a + b)
    for i in range(xs.size):
        row = drop_kernel(
            code, p, h, min(max(mid + half * xs[i], FIRST_PHASE), LAST_PHASE), v_in, accel, max_steps
        )
        _fold(row, acc)
        e, s = row[D_EN], row[D_EPS]
        wgt = half * ws[i]
        q[0] += wgt * e
        q[1] += wgt * e * e
        q[2] += wgt * s
        q[3] += wgt * s * s
    return q


@njit(cache=True)
def _fold(row, acc):
    """Fold one drop into the running min/max/steps/status/evaluations of ``acc``."""
    e, s, n, st = row[D_EN], row[D_EPS], row[D_STEPS], row[D_STATUS]
    acc[P_MIN] = min(acc[P_MIN], e)
    acc[P_MAX] = max(acc[P_MAX], e)
    acc[P_EPS_MIN] = min(acc[P_EPS_MIN], s)
    acc[P_EPS_MAX] = max(acc[P_EPS_MAX], s)
    acc[P_STEPS_MIN] = min(acc[P_STEPS_MIN], n)
    acc[P_STEPS_MAX] = max(acc[P_STEPS_MAX], n)
    if st != SEPARATED and st != CAPTURED:
        acc[P_STATUS] = max(acc[P_STATUS], st)
    acc[P_EVALS] += 1


@njit(cache=True)
def _count(code, p, h, v_in, accel, max_steps, phase, acc):
    row = drop_kernel(code, p, h, phase, v_in, accel, max_steps)
    _fold(row, acc)
    return row[D_STEPS]


@njit(cache=True, inline="always")  # one call site: compiled inside it, not once more apart
def _jumps(code, p, h, v_in, accel, max_steps, grid, acc):
    """0, the phases in (0, 1) where the steps in contact change, in order, and 1."""
    counts = np.empty(grid + 1)
    for i in range(grid):
        counts[i] = _count(code, p, h, v_in, accel, max_steps, i / grid, acc)
    counts[grid] = _count(code, p, h, v_in, accel, max_steps, np.nextafter(1.0, 0.0), acc)
    cuts = [0.0]
    for i in range(grid):
        lo, n_lo = i / grid, counts[i]
        hi, n_hi = (i + 1) / grid, counts[i + 1]
        while n_lo != n_hi:
            a, b, n_b = lo, hi, n_hi
            while b - a > JUMP_TOL:
                m = 0.5 * (a + b)
                if m <= a or m >= b:
                    break
                n_m = _count(code, p, h, v_in, accel, max_steps, m, acc)
                if n_m == n_lo:
                    a = m
                else:
                    b, n_b = m, n_m
            cuts.append(b)
            if b >= hi:
                break
            lo, n_lo = b, n_b
    if cuts[-1] < 1.0:
        cuts.append(1.0)
    return np.array(cuts)


def phase_mean(
    code: int,
    p: np.ndarray,
    h: float,
    v_in: float,
    accel: float,
    max_steps: int,
    tol: float,
    grid: int,
    max_intervals: int,
    xs: np.ndarray,
    ws: np.ndarray,
) -> np.ndarray:
    """The row of ``codes.P_*`` slots for one scene: mean, range, std of e_N and eps over the phase."""
    kernel = for_engine(code, phase_mean_kernel)
    return kernel(code, p, h, v_in, accel, max_steps, tol, grid, max_intervals, xs, ws)


@njit(cache=True)
def phase_mean_kernel(
    code: int,
    p: np.ndarray,
    h: float,
    v_in: float,
    accel: float,
    max_steps: int,
    tol: float,
    grid: int,
    max_intervals: int,
    xs: np.ndarray,
    ws: np.ndarray,
) -> np.ndarray:
    """``phase_mean``'s kernel (a template of ``kernels.for_engine``)."""
    acc = np.zeros(N_PHASE)
    acc[P_MIN] = acc[P_EPS_MIN] = acc[P_STEPS_MIN] = math.inf
    acc[P_MAX] = acc[P_EPS_MAX] = acc[P_STEPS_MAX] = -math.inf
    cuts = _jumps(code, p, h, v_in, accel, max_steps, grid, acc)
    acc[P_JUMPS] = cuts.size - 2
    if acc[P_STATUS] != 0.0:  # a drop failed (non-finite, step limit): no mean
        for j in (P_MEAN, P_STD, P_EPS_MEAN, P_EPS_STD, P_MIN, P_MAX, P_EPS_MIN, P_EPS_MAX, P_ERR):
            acc[j] = math.nan
        return acc
    total = np.zeros(4)
    err = 0.0
    used = 0
    stack_a = [0.0]  # typed by their first element, emptied at once
    stack_b = [0.0]
    whole = [np.zeros(4)]
    stack_a.clear()
    stack_b.clear()
    whole.clear()
    for k in range(cuts.size - 1):
        lo = cuts[k]
        while lo < cuts[k + 1]:
            hi = min(cuts[k + 1], (math.floor(lo * SPLIT) + 1.0) / SPLIT)
            stack_a.append(lo)
            stack_b.append(hi)
            whole.append(_gl(code, p, h, v_in, accel, max_steps, lo, hi, acc, xs, ws))
            lo = hi
        while len(stack_a) > 0:
            a = stack_a.pop()
            b = stack_b.pop()
            q = whole.pop()
            m = 0.5 * (a + b)
            left = _gl(code, p, h, v_in, accel, max_steps, a, m, acc, xs, ws)
            right = _gl(code, p, h, v_in, accel, max_steps, m, b, acc, xs, ws)
            used += 1
            d = max(abs(left[0] + right[0] - q[0]), abs(left[2] + right[2] - q[2]))
            if d <= tol * (b - a) or used >= max_intervals or m <= a or m >= b:
                total += left + right
                err += d
                if d > tol * (b - a) and used >= max_intervals:
                    acc[P_STATUS] = max(acc[P_STATUS], QUAD_LIMIT)
            else:
                stack_a.append(a)
                stack_b.append(m)
                whole.append(left)
                stack_a.append(m)
                stack_b.append(b)
                whole.append(right)
    acc[P_MEAN] = total[0]
    acc[P_STD] = math.sqrt(max(total[1] - total[0] * total[0], 0.0))
    acc[P_EPS_MEAN] = total[2]
    acc[P_EPS_STD] = math.sqrt(max(total[3] - total[2] * total[2], 0.0))
    acc[P_ERR] = err
    if acc[P_STATUS] != 0.0 and acc[P_STATUS] != QUAD_LIMIT:
        for j in (P_MEAN, P_STD, P_EPS_MEAN, P_EPS_STD, P_MIN, P_MAX, P_EPS_MIN, P_EPS_MAX):
            acc[j] = math.nan
    return acc
