"""The reference impact of any law of the family: DOP853 in contact, exact free flight under the floor.

The scaled motion is ``x'' = A - max(0, f(x, v))`` from ``x = 0``, ``v = 1`` (``forces.py``;
``x'' = A - f`` for a law without the floor, which then never flies before ``x = 0``).
While ``f >= 0`` the kernel integrates the law with DOP853 (the tableau of ``engine/tableau.py``,
SciPy's error norm); every event (maximum compression ``v = 0``, the floor ``f = 0``,
separation ``x = 0``, capture: ``v`` back to 0 from below) is placed by re-taking the step
that crossed it with a shorter length, found by the Illinois method, so it is as accurate as
the step.  While the floor holds (``f < 0``, the load alone acts) the motion is the parabola
``x = x0 + v0 t + A t^2 / 2``: separation and capture are its closed-form roots, and a
re-contact (``f`` back above 0) is found by sampling and bisection, after which the law
takes over again.  An approach to the equilibrium ``x_eq`` without a turn of ``v`` is taken
to its limit (creep after the maximum, no restitution before it).

Stronge's coefficient comes from the energy identity (docs/laws.md):
``eps^2 = (v_e^2 / 2 + A (x_m - x_e)) / (1/2 + A x_m)``; Newton's ``e_N = -v_e`` at separation,
0 otherwise.
"""

import numpy as np
from numba import njit

from contactalpha.engine.codes import (
    CREEP,
    EVENT_FAILED,
    NO_RESTITUTION,
    NON_FINITE,
    NONSEPARATION,
    OK,
    SEPARATION,
    STEP_LIMIT,
    STEP_UNDERFLOW,
)
from contactalpha.engine.rk import ERROR_EXPONENT, MAX_FACTOR, MIN_FACTOR, SAFETY
from contactalpha.engine.tableau import E3, E5, N_STAGES
from contactalpha.engine.tableau import A as RK_A
from contactalpha.engine.tableau import B as RK_B

from .forces import creeps_unloaded, floored, scaled_force

# Slots of the row the kernel returns.
R_EPS2, R_EN, R_STATE, R_STATUS, R_XM, R_XE, R_VE, R_TE, R_STEPS, R_FLOORS = range(10)
N_ROW = 10
# Default tolerances of the reference integration.
RTOL = 1e-12
ATOL = 1e-14
MAX_STEPS = 2_000_000
# Within this relative distance of the equilibrium the law is taken as linear there, and an
# overdamped approach that the linear motion shows to need no further turn of v is taken to its limit.
SETTLE = 1e-6
# Relative margin of the critical damping test, above the finite-difference error of the slope K.
CRITICAL = 1e-8
# Samples of the force along a free flight, to find a re-contact.
FLIGHT_SAMPLES = 64
# A compression standing for 0+ when the law's sign at the rim is needed.
TINY = 1e-300
# Illinois iterations when placing an event inside a step.
LOCATE_ITER = 200
# A law without the floor keeps its damping force, ~x^{1/4} or x^{1/2}, up to x = 0, where the
# motion is not smooth: the step that reaches x = 0 is taken from no larger a compression than this
# (its error ~ LAST_STEP_X^{5/4}); from larger ones the steps halve towards it.
LAST_STEP_X = 1e-12


@njit(cache=True, error_model="numpy")
def _deriv(code, x, v, p, A, s):
    if not floored(code):
        return A - scaled_force(code, x, v, p, A, s)
    return A - max(0.0, scaled_force(code, x, v, p, A, s))


@njit(cache=True, error_model="numpy")
def _step(code, x, v, h, p, A, s, K):
    """One DOP853 step of ``(x, v)``; returns ``(x1, v1, err_ratio_numerators)`` via K rows."""
    # K[j, 0] = dx, K[j, 1] = dv for stage j.
    K[0, 0] = v
    K[0, 1] = _deriv(code, x, v, p, A, s)
    for st in range(1, N_STAGES):
        ax = 0.0
        av = 0.0
        for j in range(st):
            ax += RK_A[st, j] * K[j, 0]
            av += RK_A[st, j] * K[j, 1]
        xs = x + h * ax
        vs = v + h * av
        K[st, 0] = vs
        K[st, 1] = _deriv(code, xs, vs, p, A, s)
    bx = 0.0
    bv = 0.0
    for j in range(N_STAGES):
        bx += RK_B[j] * K[j, 0]
        bv += RK_B[j] * K[j, 1]
    x1 = x + h * bx
    v1 = v + h * bv
    K[N_STAGES, 0] = v1
    K[N_STAGES, 1] = _deriv(code, x1, v1, p, A, s)
    return x1, v1


@njit(cache=True, error_model="numpy")
def _error(K, h, x, v, x1, v1, rtol, atol):
    e5 = 0.0
    e3 = 0.0
    for i in range(2):
        y0 = x if i == 0 else v
        y1 = x1 if i == 0 else v1
        sc = atol + rtol * max(abs(y0), abs(y1))
        a5 = 0.0
        a3 = 0.0
        for j in range(N_STAGES + 1):
            a5 += E5[j] * K[j, i]
            a3 += E3[j] * K[j, i]
        e5 += (a5 / sc) ** 2
        e3 += (a3 / sc) ** 2
    if not (np.isfinite(e5) and np.isfinite(e3)):
        return np.inf
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / np.sqrt((e5 + 0.01 * e3) * 2.0)


@njit(cache=True, error_model="numpy")
def _event_value(code, kind, x, v, p, A, s):
    """Event functions: 0 maximum/capture (v), 1 separation (x), 2 floor (f)."""
    if kind == 0:
        return v
    if kind == 1:
        return x
    return scaled_force(code, x, v, p, A, s)


@njit(cache=True, error_model="numpy")
def _locate(code, kind, x, v, h, g0, p, A, s, K):
    """Length ``h* in (0, h]`` of the step from ``(x, v)`` on which event ``kind`` is 0 (Illinois)."""
    lo = 0.0
    glo = g0
    hi = h
    x1, v1 = _step(code, x, v, hi, p, A, s, K)
    ghi = _event_value(code, kind, x1, v1, p, A, s)
    side = 0
    for _ in range(LOCATE_ITER):
        if ghi == glo:
            mid = 0.5 * (lo + hi)
        else:
            mid = hi - ghi * (hi - lo) / (ghi - glo)
        if not (lo < mid < hi):
            mid = 0.5 * (lo + hi)
        xm, vm = _step(code, x, v, mid, p, A, s, K)
        gm = _event_value(code, kind, xm, vm, p, A, s)
        if gm == 0.0:
            return mid, xm, vm, True
        if (gm > 0.0) == (glo > 0.0):
            lo = mid
            glo = gm
            if side == -1:
                ghi *= 0.5
            side = -1
        else:
            hi = mid
            ghi = gm
            if side == 1:
                glo *= 0.5
            side = 1
        if hi - lo <= 4e-16 * max(hi, 1e-300):
            break
    # Return the end on the crossed side so that the event has happened.
    x1, v1 = _step(code, x, v, hi, p, A, s, K)
    return hi, x1, v1, True


@njit(cache=True, error_model="numpy")
def _trapped(code, x, v, p, A, s, x_eq):
    """True if the law, linearised at ``x_eq``, reaches ``x_eq`` from ``(x, v)`` with no turn of v."""
    if A <= 0.0 or abs(x - x_eq) > SETTLE * x_eq:
        return False
    dx = 1e-4 * x_eq
    K = (scaled_force(code, x_eq + dx, 0.0, p, A, s) - scaled_force(code, x_eq - dx, 0.0, p, A, s)) / (
        2.0 * dx
    )
    C = scaled_force(code, x_eq, 1.0, p, A, s) - scaled_force(code, x_eq, 0.0, p, A, s)
    disc = 0.25 * C * C - K
    if K <= 0.0 or C <= 0.0 or disc < -CRITICAL * K:
        return False  # oscillates about x_eq: v turns within half a period
    u = x - x_eq
    r = np.sqrt(max(disc, 0.0))
    slow = -0.5 * C + r
    fast = -0.5 * C - r
    if r == 0.0:
        # u = (a + b t) e^{lam t}: v = 0 at t = -(a lam + b) / (b lam)
        b = v - slow * u
        return b == 0.0 or -(slow * u + b) / (b * slow) <= 0.0
    a = (v - fast * u) / (slow - fast)
    b = (slow * u - v) / (slow - fast)
    if a == 0.0:
        return True
    # v(t) = a slow e^{slow t} + b fast e^{fast t} = 0  <=>  e^{(slow - fast) t} = -b fast / (a slow)
    return -b * fast / (a * slow) <= 1.0


@njit(cache=True, error_model="numpy")
def _flight(code, x0, v0, p, A, s):
    """Free flight under the load from ``(x0, v0)``, ``v0 < 0``: (kind, t, x, v).

    kind 0: capture (v = 0 at x > 0); 1: separation (x = 0); 2: re-contact (f = 0 rising).
    """
    disc = v0 * v0 - 2.0 * A * x0
    t_end = np.inf
    kind = -1
    if disc >= 0.0:
        t_end = 2.0 * x0 / (-v0 + np.sqrt(disc))  # the first root of x(t) = 0, rounding-safe
        kind = 1
    if A > 0.0 and -v0 / A < t_end:
        t_end = -v0 / A
        kind = 0
    # Re-contact: the force argument back above 0 before t_end.
    prev = 0.0
    for i in range(1, FLIGHT_SAMPLES + 1):
        t = t_end * i / FLIGHT_SAMPLES
        # The law's sign just inside the contact (x > 0 tiny) at the separation end, too.
        xt = max(x0 + t * (v0 + 0.5 * A * t), TINY)
        ft = scaled_force(code, xt, v0 + A * t, p, A, s)
        if ft > 0.0:
            lo = prev
            hi = t
            for _ in range(200):
                mid = 0.5 * (lo + hi)
                xm = max(x0 + mid * (v0 + 0.5 * A * mid), TINY)
                if scaled_force(code, xm, v0 + A * mid, p, A, s) > 0.0:
                    hi = mid
                else:
                    lo = mid
                if hi - lo <= 4e-16 * hi:
                    break
            return 2, hi, x0 + hi * (v0 + 0.5 * A * hi), v0 + A * hi
        prev = t
    if kind == 1:
        return 1, t_end, 0.0, v0 + A * t_end
    return 0, t_end, x0 + t_end * (v0 + 0.5 * A * t_end), 0.0


@njit(cache=True, error_model="numpy")
def impact_kernel(code, p, A, s, x_eq, rtol, atol, max_steps):
    """One impact of the law with kernel code ``code`` at damping ``p``, scaled load ``A``, shape ``s``.

    Returns a row: eps^2, e_N, end state code, status code, x_m, x_e, v_e, t_e, steps, and the
    number of times the force reached its floor (the tables' build splits its plane by it).
    """
    out = np.full(N_ROW, np.nan)
    K = np.empty((N_STAGES + 1, 2))
    x = 0.0
    v = 1.0
    t = 0.0
    x_m = np.nan
    compressing = True
    h = 1e-3
    steps = 0
    state = -1
    status = OK
    x_e = np.nan
    v_e = np.nan
    floor = False  # True when the last event put the motion on the floor (f = 0, falling)
    floors = 0
    while state < 0:
        if steps >= max_steps:
            status = STEP_LIMIT
            break
        if floor:
            floor = False
            kind, dt, x, v = _flight(code, x, v, p, A, s)
            t += dt
            if kind == 1:
                state = SEPARATION
                x_e = 0.0
                v_e = v
            elif kind == 0:
                state = NONSEPARATION
                x_e = x
                v_e = 0.0
            else:
                h = 1e-6
            continue
        # Settled next to the equilibrium without a turn of v: the limit.
        if _trapped(code, x, v, p, A, s, x_eq):
            if compressing:
                state = NO_RESTITUTION
                x_m = x_eq
            else:
                state = CREEP
            x_e = x_eq
            v_e = 0.0
            t = np.inf
            break
        steps += 1
        x1, v1 = _step(code, x, v, h, p, A, s, K)
        err = _error(K, h, x, v, x1, v1, rtol, atol)
        if not np.isfinite(err) or err > 1.0:
            fac = MIN_FACTOR if not np.isfinite(err) else max(MIN_FACTOR, SAFETY * err**ERROR_EXPONENT)
            h *= fac
            if h < 1e-300 or h <= 1e-15 * abs(t):
                status = STEP_UNDERFLOW
                break
            continue
        # Earliest event crossed on this step.
        best = np.inf
        bk = -1
        bx = 0.0
        bv = 0.0
        for kind in range(3):
            g0 = _event_value(code, kind, x, v, p, A, s)
            g1 = _event_value(code, kind, x1, v1, p, A, s)
            if kind == 0:
                hit = (compressing and g1 <= 0.0) or ((not compressing) and g1 >= 0.0 and g0 < 0.0)
            elif kind == 1:
                hit = g1 <= 0.0 < g0
            else:
                hit = (not compressing) and g1 < 0.0 <= g0 and x1 > 0.0 and floored(code)
            if hit:
                hs, xs, vs, good = _locate(code, kind, x, v, h, g0, p, A, s, K)
                if not good:
                    status = EVENT_FAILED
                if hs < best:
                    best = hs
                    bk = kind
                    bx = xs
                    bv = vs
        if bk == -1:
            t += h
            x = x1
            v = v1
            fac = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err**ERROR_EXPONENT)
            h *= fac
            if not (np.isfinite(x) and np.isfinite(v)):
                status = NON_FINITE
                break
            continue
        if bk == 0 and not compressing and bx < 0.0:
            # v turned below x = 0: the motion left the contact inside the step (a parabola that
            # dips under x = 0 and back), so separation came first, on [0, best].
            best, bx, bv, good = _locate(code, 1, x, v, best, x, p, A, s, K)
            bk = 1
        if bk == 1 and x > LAST_STEP_X and not floored(code):
            h = 0.5 * best  # approach x = 0 by steps the error control checks
            continue
        t += best
        if bk == 0 and compressing and A == 0.0 and creeps_unloaded(code, p):
            # No load and no floor, overdamped: the motion approaches x = 0 without reaching it.
            x_m = bx
            state = CREEP
            x_e = 0.0
            v_e = 0.0
            t = np.inf
        elif bk == 0 and compressing:
            x = bx
            v = 0.0
            x_m = bx
            compressing = False
            h = max(best, 1e-6)
        elif bk == 0:
            state = NONSEPARATION
            x_e = bx
            v_e = 0.0
        elif bk == 1:
            state = SEPARATION
            x_e = 0.0
            v_e = bv
        else:
            x = bx
            v = bv
            floor = True
            floors += 1
    if status != OK or state < 0:
        out[R_STATUS] = status if status != OK else EVENT_FAILED
        out[R_STATE] = 0
        out[R_STEPS] = steps
        return out
    eps2 = (0.5 * v_e * v_e + A * (x_m - x_e)) / (0.5 + A * x_m)
    out[R_EPS2] = eps2
    out[R_EN] = -v_e if state == SEPARATION else 0.0
    out[R_STATE] = state
    out[R_STATUS] = OK
    out[R_XM] = x_m
    out[R_XE] = x_e
    out[R_VE] = v_e
    out[R_TE] = t
    out[R_STEPS] = steps
    out[R_FLOORS] = floors
    return out


@njit(cache=True, error_model="numpy")
def impact_rows(code, p, A, s, x_eq, rtol, atol, max_steps):
    """``impact_kernel`` over flat arrays ``p``, ``A``, ``x_eq`` (``s`` one value)."""
    n = p.size
    out = np.empty((n, N_ROW))
    for i in range(n):
        row = impact_kernel(code, p[i], A[i], s, x_eq[i], rtol, atol, max_steps)
        for j in range(N_ROW):
            out[i, j] = row[j]
    return out
