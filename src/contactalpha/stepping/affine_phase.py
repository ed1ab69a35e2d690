"""The phase mean of a piecewise-affine step map, exactly, for the cost of a few drops.

MuJoCo's and PyBullet's steps are affine in the state ``(z, w)`` on each branch, and linear forms
in the state pick the branch (``kernels.engine_branches``, ``kernels.engine_branch``).  A drop's start
``flight.touchdown_state`` is a polynomial of degree 2 in the touchdown phase ``phi`` (z) and 1 (w).
So along one sequence of branches every state of the drop is a quadratic in ``phi``, and every
test the drop makes (the branch forms, ``z > 0``, ``w' > 0``, the rest test of ``drop.run_drop``)
is the sign of a quadratic in ``phi`` (``phase_polynomials``).

``_sweep`` runs the drop on these polynomials from a phase ``lo``: at each step the roots of the
tests whose outcome can change split what is left, and the first split past which the branch or
the drop's decision differs ends the piece (decisions are taken inside, where no test changes
sign).  On the piece ``[lo, end)`` the drop takes the same steps for every phase, and e_N is the
closed form ``flight.rebound_speed`` of the final state's polynomials over ``v_in``, integrated by
adaptive Gauss-Legendre quadrature (``phase_polynomials.integrate_piece``; no drop is run at a
node), so the mean is exact across every jump and kink to the quadrature's tolerance.  The next
piece resumes the stored drop from the step whose test ended the last one.  The cost is about one
polynomial drop per piece, a few pieces where ``phase.phase_mean`` runs 700-7,000 drops.

The row it returns has ``codes.P_*`` slots: mean, minimum and maximum (over the quadrature's nodes
and both ends of every piece), standard deviation, steps in contact, jumps, pieces (in
``P_EVALS``), status.  Stronge's eps is not computed here (its deepest penetration is a maximum
over steps; ``phase.phase_mean`` has it): its slots are NaN.
"""

import math

import numpy as np
from numba import njit

from .codes import (
    CAPTURED,
    N_PHASE,
    NON_FINITE,
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
    STEP_LIMIT,
)
from .drop import CREEP_FRACTION
from .flight import REST_FRACTION
from .kernels import MAX_BRANCHES, MAX_FORMS, engine_affine_map, engine_branch, engine_branches, for_engine
from .phase_polynomials import ROOT_GAP, integrate_piece, poly, roots_into, sort_roots

# Columns of the per-step workspace of ``_sweep``: the state's polynomials at the step's start, the
# steps in contact before it, the first change of its tests, the smallest change of the steps before.
W_Z, W_W, W_N, W_ROOT, W_PREFIX = 0, 3, 6, 7, 8
W_COLS = 9
# Default tolerance per unit phase of the adaptive quadrature, and the budget of intervals and pieces.
QUAD_TOL = 1e-12
MAX_PIECES = 5000


@njit(cache=True)
def _grow(a, n):
    """``a`` (2-D) with room for ``n`` rows (doubling)."""
    if a.shape[0] >= n:
        return a
    b = np.empty((2 * n, a.shape[1]), dtype=a.dtype)
    for i in range(a.shape[0]):  # element by element: a slice assignment compiles numba's shape error
        for j in range(a.shape[1]):
            b[i, j] = a[i, j]
    return b


@njit(cache=True)
def _branch_at(code, forms, nf, z, w, vals):
    """The branch at the state ``(z, w)``."""
    for i in range(nf):
        vals[i] = forms[i, 0] * z + forms[i, 1] * w + forms[i, 2]
    return engine_branch(code, vals)


@njit(cache=True, inline="always")  # compiled inside its callers, not once more apart
def _branch_change(code, forms, nf, z0, z1, z2, w0, w1, w2, lo, hi, buf, nb, vals):
    """The branch on ``(lo, first change)`` and the first root in ``buf[:nb]`` past which it differs.

    The first change is 1 if none.
    """
    sort_roots(buf, nb)
    t = 0.5 * (lo + (buf[0] if nb > 0 else hi))
    b0 = _branch_at(code, forms, nf, poly(z0, z1, z2, t), poly(w0, w1, w2, t), vals)
    for i in range(nb):
        t = 0.5 * (buf[i] + (buf[i + 1] if i + 1 < nb else hi))
        if _branch_at(code, forms, nf, poly(z0, z1, z2, t), poly(w0, w1, w2, t), vals) != b0:
            return b0, buf[i]
    return b0, 1.0


@njit(cache=True)
def _outcome(z, w, w1, n, forced, rest):
    """``drop.run_drop``'s decision after a step: SEPARATED, CAPTURED or -1 (go on).

    Its "rising" flag is "the step before ended moving up after a force" here: from the first
    rising step on, every step rises until the body separates (the first state above the surface,
    a short hop's included) or is captured (a step from below the surface ends below it).
    """
    if n > 0 and z > 0.0:
        return SEPARATED
    n1 = n + 1 if forced else n
    if n1 > 0 and w1 <= 0.0 and ((n > 0 and w > 0.0) or (abs(w1) <= rest and abs(w1 - w) <= rest)):
        return CAPTURED
    return -1


@njit(cache=True, inline="always")  # compiled inside its callers, not once more apart
def _decision_change(z0, z1, z2, w0, w1, w2, u0, u1, u2, n, forced, rest, lo, hi, buf, nb):
    """The first of the roots ``buf[:nb]`` past which ``_outcome`` differs; 1 if none.

    ``u``: w after the step.
    """
    sort_roots(buf, nb)
    t = 0.5 * (lo + buf[0])
    o0 = _outcome(poly(z0, z1, z2, t), poly(w0, w1, w2, t), poly(u0, u1, u2, t), n, forced, rest)
    for i in range(nb):
        t = 0.5 * (buf[i] + (buf[i + 1] if i + 1 < nb else hi))
        if _outcome(poly(z0, z1, z2, t), poly(w0, w1, w2, t), poly(u0, u1, u2, t), n, forced, rest) != o0:
            return buf[i]
    return 1.0


@njit(cache=True)
def _sweep(code, forms, nf, maps, h, v_in, accel, max_steps, tol, acc, ws, zn, wn, buf, vals):
    """Every piece of ``[0, 1)`` in order, each integrated into ``acc``: ``(int e, int e^2, error, ws)``.

    ``ws`` (``W_COLS`` columns) is the per-step workspace, returned grown where a drop needed more rows.

    A piece's drop is stored step by step (state polynomials, steps in contact, and the first
    change of each step's tests above the piece's start).  The next piece starts at the
    smallest of those roots; the steps before the first one whose root that is keep their branches
    (no test of theirs changes sign there), so its drop resumes from that step.
    """
    ws[0, W_Z], ws[0, W_Z + 1], ws[0, W_Z + 2] = 0.0, v_in * h, -0.5 * accel * h * h  # touchdown_state in phi
    ws[0, W_W], ws[0, W_W + 1], ws[0, W_W + 2] = -v_in + 0.5 * accel * h, accel * h, 0.0
    ws[0, W_N] = 0.0
    ws[0, W_PREFIX] = 1.0
    rest = REST_FRACTION * v_in
    lo = 0.0
    k = 0
    s0 = s1 = err = 0.0
    pieces = 0
    last_n = -1
    while lo < 1.0:
        j = k
        hi = ws[k, W_PREFIX]
        status = STEP_LIMIT
        while j < max_steps:
            if j + 1 >= ws.shape[0]:
                ws = _grow(ws, j + 2)
            z0, z1, z2 = ws[j, W_Z], ws[j, W_Z + 1], ws[j, W_Z + 2]
            w0, w1, w2 = ws[j, W_W], ws[j, W_W + 1], ws[j, W_W + 2]
            n = int(ws[j, W_N])
            # Every test below is a quadratic in the phase; its value and slope at the middle of what
            # is left bound it there, so most steps find no root without solving for one.
            lg = lo + ROOT_GAP
            m = 0.5 * (lg + hi)
            rr = 0.5 * (hi - lg)
            if rr <= 0.0:  # a sliver narrower than ROOT_GAP: no test is cut in it
                m, rr = 0.5 * (lo + hi), 0.0
            zm, zd = z0 + m * (z1 + m * z2), z1 + 2.0 * z2 * m
            wm, wd = w0 + m * (w1 + m * w2), w1 + 2.0 * w2 * m
            # The branch: the forms' roots split what is left; the first split whose branch differs cuts it.
            nb = 0
            for i in range(nf):
                al, be, ga = forms[i, 0], forms[i, 1], forms[i, 2]
                c2 = al * z2 + be * w2
                vals[i] = al * zm + be * wm + ga
                if abs(vals[i]) <= abs(al * zd + be * wd) * rr + abs(c2) * rr * rr:
                    nb = roots_into(al * z0 + be * w0 + ga, al * z1 + be * w1, c2, lo, hi, buf, nb)
            if nb == 0:
                br, r = engine_branch(code, vals), 1.0
            else:
                br, r = _branch_change(code, forms, nf, z0, z1, z2, w0, w1, w2, lo, hi, buf, nb, vals)
            forced = br != 0
            m0, m1, m2, m3, m4, m5 = (
                maps[br, 0],
                maps[br, 1],
                maps[br, 2],
                maps[br, 3],
                maps[br, 4],
                maps[br, 5],
            )
            y0, y1, y2 = m0 * z0 + m1 * w0 + m2, m0 * z1 + m1 * w1, m0 * z2 + m1 * w2
            u0, u1, u2 = m3 * z0 + m4 * w0 + m5, m3 * z1 + m4 * w1, m3 * z2 + m4 * w2
            if not math.isfinite(y0 + y1 + y2 + u0 + u1 + u2):
                status = NON_FINITE
                break
            um, ud = m3 * zm + m4 * wm + m5, m3 * zd + m4 * wd
            # The drop's decision: the roots of every test it reads split what is left likewise.
            top = min(hi, r)
            nb = 0
            if n > 0 and abs(zm) <= abs(zd) * rr + abs(z2) * rr * rr:
                nb = roots_into(z0, z1, z2, lo, top, buf, nb)
            if n > 0 or forced:
                bound = abs(ud) * rr + abs(u2) * rr * rr
                if abs(um) <= bound:
                    nb = roots_into(u0, u1, u2, lo, top, buf, nb)
                if abs(wm) <= abs(wd) * rr + abs(w2) * rr * rr:
                    nb = roots_into(w0, w1, w2, lo, top, buf, nb)
                if abs(um) <= rest + bound:  # the rest test |w'| <= rest and |w' - w| <= rest
                    nb = roots_into(u0 - rest, u1, u2, lo, top, buf, nb)
                    nb = roots_into(u0 + rest, u1, u2, lo, top, buf, nb)
                    nb = roots_into(u0 - w0 - rest, u1 - w1, u2 - w2, lo, top, buf, nb)
                    nb = roots_into(u0 - w0 + rest, u1 - w1, u2 - w2, lo, top, buf, nb)
            if nb > 0:
                r = min(
                    r, _decision_change(z0, z1, z2, w0, w1, w2, u0, u1, u2, n, forced, rest, lo, top, buf, nb)
                )
            ws[j, W_ROOT] = r
            if r < hi:
                hi = r
                t = lo + 0.5 * (hi - lo)
                zm, wm, um = poly(z0, z1, z2, t), poly(w0, w1, w2, t), poly(u0, u1, u2, t)
            outcome = _outcome(zm, wm, um, n, forced, rest)
            if outcome == SEPARATED and forced:  # read at the state above the surface (``drop.run_drop``)
                y0, y1, y2, u0, u1, u2 = z0, z1, z2, w0, w1, w2
            elif forced:
                n += 1
            if outcome == SEPARATED or outcome == CAPTURED:
                status = outcome
                zn[0], zn[1], zn[2] = y0, y1, y2
                wn[0], wn[1], wn[2] = u0, u1, u2
                break
            ws[j + 1, W_Z], ws[j + 1, W_Z + 1], ws[j + 1, W_Z + 2] = y0, y1, y2
            ws[j + 1, W_W], ws[j + 1, W_W + 1], ws[j + 1, W_W + 2] = u0, u1, u2
            ws[j + 1, W_N] = n
            ws[j + 1, W_PREFIX] = hi
            j += 1
        if status == STEP_LIMIT:
            mid = lo + 0.5 * (hi - lo)
            i = min(j, max_steps)
            z, w = (
                poly(ws[i, W_Z], ws[i, W_Z + 1], ws[i, W_Z + 2], mid),
                poly(ws[i, W_W], ws[i, W_W + 1], ws[i, W_W + 2], mid),
            )
            if n > 0 and z < 0.0 and abs(w) <= CREEP_FRACTION * v_in:
                status = CAPTURED
        pieces += 1
        if status != SEPARATED and status != CAPTURED:
            acc[P_STATUS] = status
            break
        acc[P_STEPS_MIN] = min(acc[P_STEPS_MIN], n)
        acc[P_STEPS_MAX] = max(acc[P_STEPS_MAX], n)
        if last_n >= 0 and n != last_n:
            acc[P_JUMPS] += 1
        last_n = n
        if status == SEPARATED:
            q0, q1, e, limited = integrate_piece(zn, wn, accel, h, v_in, lo, hi, tol, acc)
            s0 += q0
            s1 += q1
            err += e
            if limited:
                acc[P_STATUS] = QUAD_LIMIT
        else:
            acc[P_MIN] = min(acc[P_MIN], 0.0)
            acc[P_MAX] = max(acc[P_MAX], 0.0)
        if pieces >= MAX_PIECES and hi < 1.0:
            acc[P_STATUS] = QUAD_LIMIT
            break
        lo = hi
        k = 0
        while k < j and ws[k, W_ROOT] > lo + ROOT_GAP:
            k += 1
    acc[P_EVALS] = pieces
    return s0, s1, err, ws


@njit(cache=True)
def workspace(rows: int = 64) -> tuple[np.ndarray, ...]:
    """The arrays ``phase_row`` works in: ``(ws, forms, maps, zn, wn, buf, vals, acc)``; ``rows`` steps."""
    return (np.empty((rows, W_COLS)), np.empty((MAX_FORMS, 3)), np.empty((MAX_BRANCHES, 6)), np.empty(3),
            np.empty(3), np.empty(2 * (MAX_FORMS + 6)), np.empty(MAX_FORMS), np.empty(N_PHASE))  # fmt: skip


@njit(cache=True, inline="always")  # compiled inside its callers, not once more apart
def phase_row(
    code: int,
    p: np.ndarray,
    h: float,
    v_in: float,
    accel: float,
    max_steps: int,
    tol: float,
    ws: np.ndarray,
    forms: np.ndarray,
    maps: np.ndarray,
    zn: np.ndarray,
    wn: np.ndarray,
    buf: np.ndarray,
    vals: np.ndarray,
    acc: np.ndarray,
) -> np.ndarray:
    """``acc`` filled with the ``codes.P_*`` row of e_N over a uniform touchdown phase; returns ``ws``.

    The arrays come from ``workspace`` (a caller evaluating many means reuses them).
    """
    acc[:] = 0.0
    acc[P_MIN] = acc[P_STEPS_MIN] = math.inf
    acc[P_MAX] = acc[P_STEPS_MAX] = -math.inf
    for j in (P_EPS_MEAN, P_EPS_MIN, P_EPS_MAX, P_EPS_STD):
        acc[j] = math.nan
    nf = engine_branches(code, p, h, accel, forms, maps)
    s0, s1, err, ws = _sweep(
        code, forms, nf, maps, h, v_in, accel, max_steps, tol, acc, ws, zn, wn, buf, vals
    )
    acc[P_ERR] = err
    if acc[P_STATUS] != 0.0:
        for j in (P_MEAN, P_STD, P_MIN, P_MAX, P_ERR):
            acc[j] = math.nan
        return ws
    acc[P_MEAN] = s0
    acc[P_STD] = math.sqrt(max(s1 - s0 * s0, 0.0))
    return ws


def phase_mean_affine(
    code: int, p: np.ndarray, h: float, v_in: float, accel: float, max_steps: int, tol: float
) -> np.ndarray:
    """The row of ``codes.P_*`` slots of e_N over a uniform touchdown phase (module docstring)."""
    engine_affine_map(code)
    return for_engine(code, phase_mean_affine_kernel)(code, p, h, v_in, accel, max_steps, tol)


@njit(cache=True)
def phase_mean_affine_kernel(
    code: int, p: np.ndarray, h: float, v_in: float, accel: float, max_steps: int, tol: float
) -> np.ndarray:
    """``phase_mean_affine``'s kernel (a template of ``kernels.for_engine``)."""
    ws, forms, maps, zn, wn, buf, vals, acc = workspace()
    phase_row(code, p, h, v_in, accel, max_steps, tol, ws, forms, maps, zn, wn, buf, vals, acc)
    return acc
