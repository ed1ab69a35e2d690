"""Forward map and exact inverse of any law of the family, on the reference integrator.

``impact_kernel`` (``integrate.py``) gives both restitutions of one impact.  The inverse finds
the damping ``p`` with ``e(p) = target`` by the Illinois method inside a bracket that starts at
``p = 0`` (``e = 1``) and grows by factors of 4; ``e(p)`` falls monotonically with ``p`` for
every law of the family (the tests check it at random points), so the bracket cannot be lost.
Newton's ``e_N`` is 0 for every ``p`` past the separation boundary, which the bracket handles
like any other value.
"""

import numpy as np
from numba import njit

from contactalpha.engine.codes import NO_BRACKET, NOT_CONVERGED, OK
from contactalpha.engine.firstcall import twin_rows
from contactalpha.engine.threads import run_rows

from .closed_form import closed_form_restitution
from .integrate import R_EN, R_EPS2, R_STATUS, impact_kernel

# Largest damping the bracket grows to before giving up.
P_MAX = 1e8
# First upper end of the bracket.
P_START = 1.0
# Relative width of the bracket, and distance to the target, at which the root is accepted.
P_RTOL = 1e-14
E_TOL = 1e-15
# Every BISECT_EVERY-th step bisects, so that rounding noise near the root cannot stall the bracket.
BISECT_EVERY = 4
MAX_ITER = 300
# Fewer points than this run in the calling thread.
PARALLEL_MIN = 32


@njit(cache=True, error_model="numpy")
def _value(code, p, A, s, x_eq, rtol, atol, max_steps, kinematic, closed):
    """Restitution at damping ``p``: closed form (``closed``, linear laws) or the integrator."""
    if closed:
        return closed_form_restitution(p, A, s, kinematic)
    row = impact_kernel(code, p, A, s, x_eq, rtol, atol, max_steps)
    if row[R_STATUS] != OK:
        return np.nan
    if kinematic:
        return row[R_EN]
    return np.sqrt(max(row[R_EPS2], 0.0))


@njit(cache=True, error_model="numpy")
def damping_kernel(code, target, kinematic, A, s, x_eq, rtol, atol, max_steps, closed=False):
    """Damping ``p`` at which the law's restitution is ``target``; returns (p, status)."""
    if target >= 1.0:
        return 0.0, OK
    lo = 0.0
    glo = 1.0 - target
    hi = P_START
    ghi = _value(code, hi, A, s, x_eq, rtol, atol, max_steps, kinematic, closed) - target
    while ghi > 0.0:
        lo = hi
        glo = ghi
        hi *= 4.0
        if hi > P_MAX:
            return np.nan, NO_BRACKET
        ghi = _value(code, hi, A, s, x_eq, rtol, atol, max_steps, kinematic, closed) - target
    if ghi != ghi:
        return np.nan, NOT_CONVERGED
    if ghi == 0.0:
        return hi, OK
    last = 0
    for it in range(MAX_ITER):
        mid = hi - ghi * (hi - lo) / (ghi - glo)
        if not (lo < mid < hi) or it % BISECT_EVERY == BISECT_EVERY - 1:
            mid = 0.5 * (lo + hi)
        gm = _value(code, mid, A, s, x_eq, rtol, atol, max_steps, kinematic, closed) - target
        if gm != gm:
            return np.nan, NOT_CONVERGED
        if gm == 0.0:
            return mid, OK
        if gm > 0.0:
            lo = mid
            glo = gm
            if last == 1:
                ghi *= 0.5  # Illinois: the other end kept twice
            last = 1
        else:
            hi = mid
            ghi = gm
            if last == -1:
                glo *= 0.5
            last = -1
        if hi - lo <= P_RTOL * hi or abs(gm) <= E_TOL:
            return mid, OK
    return 0.5 * (lo + hi), NOT_CONVERGED


@twin_rows
@njit(cache=True, nogil=True, error_model="numpy")
def damping_rows(code, target, kinematic, A, s, x_eq, rtol, atol, max_steps, closed, p, status, start, stop):
    """``damping_kernel`` over rows ``start .. stop - 1`` of flat arrays, into ``p`` and ``status``."""
    for i in range(start, stop):
        p[i], status[i] = damping_kernel(
            code, target[i], kinematic, A[i], s, x_eq[i], rtol, atol, max_steps, closed
        )


def solve_damping(code, target, kinematic, A, s, x_eq, rtol, atol, max_steps, closed=False, threads=None):
    """``damping_kernel`` over flat arrays in ``threads`` threads; returns (p, status) arrays."""
    n = target.size
    p = np.empty(n)
    status = np.empty(n, dtype=np.int64)
    run_rows(
        damping_rows,
        n,
        code,
        target,
        kinematic,
        A,
        s,
        x_eq,
        rtol,
        atol,
        max_steps,
        closed,
        p,
        status,
        threads=threads if n >= PARALLEL_MIN else 1,
    )
    return p, status
