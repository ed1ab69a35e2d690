"""Closed-form impacts of the piecewise-linear laws: the spring-dashpot with a floor, MuJoCo's soft contact.

In the scaling of ``law.py`` both move, while the force ``f = d A + x + 2 zeta v`` is positive
(``d = 0`` for the spring-dashpot), as the damped oscillator ``u'' + 2 zeta u' + u = 0`` about the
equilibrium ``x_eq = (1 - d) A`` (``u = x - x_eq``), and as the parabola ``x'' = A`` while the floor
holds (``f < 0``).  With ``C, S`` the solutions of ``y'' = (zeta^2 - 1) y`` with ``C(0) = 1,
C'(0) = 0, S(0) = 0, S'(0) = 1`` (cos/sin, 1/t, cosh/sinh for under-, critically and overdamped)

    u(t) = e^{-zeta t} (u0 C + (v0 + zeta u0) S),   v(t) = e^{-zeta t} (v0 C - (u0 + zeta v0) S),

so any event ``a u + b v + c = 0`` reads ``e^{-zeta t} (P C + Q S) + c = 0``.  With ``c = 0`` (a turn of
``v``) its root is explicit (an arctangent, an artanh, a ratio); otherwise ``z = e^{-zeta t}(P C + Q S)``
is monotone between its own turns, which are explicit, and the root is bracketed there and polished by
safeguarded Newton steps.  Flights are quadratics.  docs/laws.md derives all of it.
"""

import numpy as np
from numba import njit

from contactalpha.engine.codes import CREEP, NO_RESTITUTION, NONSEPARATION, SEPARATION
from contactalpha.engine.firstcall import twin_rows

# Longest chain of contact and flight phases before giving up (NaN); re-contacts are rare.
MAX_PHASES = 200
NEWTON_ITER = 100
# Relative Newton step below which the root is taken as found.
NEWTON_DONE = 1e-10
# Relative size of an event function at t = 0 below which the phase starts on its root (a
# re-contact); its side is then the slope's.
START_ON_ROOT = 1e-10


@njit(cache=True, error_model="numpy")
def _basis(zeta, t):
    """``C(t), S(t)`` and their derivatives for ``y'' = (zeta^2 - 1) y``."""
    if zeta < 1.0:
        w = np.sqrt((1.0 - zeta) * (1.0 + zeta))
        c = np.cos(w * t)
        s = np.sin(w * t)
        return c, s / w, -w * s, c
    if zeta == 1.0:
        return 1.0, t, 0.0, 1.0
    w = np.sqrt((zeta - 1.0) * (zeta + 1.0))
    # e^{-zeta t} cosh(w t) overflows for large t unless combined: the caller multiplies by
    # e^{-zeta t}, so return the pieces already scaled by e^{-w t} and let _z add it back.
    ep = 0.5 * np.exp((w - zeta) * t)
    em = 0.5 * np.exp(-(w + zeta) * t)
    return ep + em, (ep - em) / w, w * (ep - em), ep + em


@njit(cache=True, error_model="numpy")
def _z(zeta, P, Q, t):
    """``z(t) = e^{-zeta t} (P C + Q S)`` and ``z'(t)``."""
    c, s, dc, ds = _basis(zeta, t)
    if zeta > 1.0:  # _basis already carries e^{-zeta t}
        return P * c + Q * s, -zeta * (P * c + Q * s) + P * dc + Q * ds
    e = np.exp(-zeta * t)
    return e * (P * c + Q * s), e * (-zeta * (P * c + Q * s) + P * dc + Q * ds)


@njit(cache=True, error_model="numpy")
def _first_zero(zeta, P, Q):
    """First ``t > 0`` with ``P C(t) + Q S(t) = 0`` (``inf`` if none)."""
    if zeta < 1.0:
        w = np.sqrt((1.0 - zeta) * (1.0 + zeta))
        # P cos(wt) + (Q/w) sin(wt) = 0: wt = atan2(-P w, Q) taken in (0, pi]
        ang = np.arctan2(-P * w, Q) % np.pi  # the roots are this plus k pi
        if ang <= 0.0:
            ang = np.pi  # a root at 0 is the present: the next one
        return ang / w
    if zeta == 1.0:
        return -P / Q if Q != 0.0 and -P / Q > 0.0 else np.inf
    w = np.sqrt((zeta - 1.0) * (zeta + 1.0))
    # P cosh + (Q/w) sinh = 0: tanh(wt) = -P w / Q
    if Q == 0.0:
        return np.inf
    r = -P * w / Q
    if 0.0 < r < 1.0:
        return np.arctanh(r) / w
    return np.inf


@njit(cache=True, error_model="numpy")
def _derivative_coefficients(zeta, P, Q):
    """(P', Q') with ``z' = e^{-zeta t} (P' C + Q' S)``: z' solves the same equation."""
    dz0 = Q - zeta * P  # z'(0)
    ddz0 = -P - 2.0 * zeta * dz0  # z''(0) from z'' + 2 zeta z' + z = 0
    return dz0, ddz0 + zeta * dz0


@njit(cache=True, error_model="numpy")
def _root(zeta, P, Q, c, t_end):
    """First ``t`` in (0, t_end] with ``z(t) + c = 0`` crossing from the sign at 0 (``inf`` if none)."""
    g0 = P + c
    # A re-contact starts on the floor's root, up to the rounding of P (a sum of terms that
    # cancel: x + 2 zeta v with 2 zeta |v| ~ x); 1e-13 let rounding on the wrong side through.
    if abs(g0) <= START_ON_ROOT * (abs(P) + abs(c)):
        g0 = Q - zeta * P  # starting on the root (a re-contact): its side is the slope's
    lo = 0.0
    dP, dQ = _derivative_coefficients(zeta, P, Q)
    for _ in range(8):
        # z is monotone from lo to its next turn.
        tc = lo + _first_zero(zeta, *_shift(zeta, dP, dQ, lo))
        hi = min(tc, t_end)
        zh, _ = _z(zeta, P, Q, hi) if np.isfinite(hi) else (0.0, 0.0)
        gh = zh + c
        if (gh > 0.0) != (g0 > 0.0) or gh == 0.0:
            glo = g0 if lo == 0.0 else _z(zeta, P, Q, lo)[0] + c
            return _polish(zeta, P, Q, c, lo, hi, g0, glo, gh)
        if hi >= t_end:
            return np.inf
        lo = hi
    return np.inf


@njit(cache=True, error_model="numpy")
def _shift(zeta, P, Q, t0):
    """Coefficients of ``z(t0 + t)`` in the basis at t0 (the caller adds t0 back)."""
    z, dz = _z(zeta, P, Q, t0)
    return z, dz + zeta * z


@njit(cache=True, error_model="numpy")
def _polish(zeta, P, Q, c, lo, hi, g0, glo, ghi):
    """The root of ``z + c`` in the bracket [lo, hi] (values glo, ghi): Newton steps kept inside it."""
    if not np.isfinite(hi):
        # Unbounded bracket (overdamped tail, z -> 0): double until bracketed.
        hi = max(2.0 * lo, 1.0)
        for _ in range(2000):
            ghi = _z(zeta, P, Q, hi)[0] + c
            if (ghi > 0.0) != (g0 > 0.0):
                break
            lo = hi
            glo = ghi
            hi *= 2.0
    # Start from the secant through the bracket's ends; a Newton step that leaves the bracket is
    # replaced by the Illinois secant of the bracket (bisection would need ~35 halvings to 1e-10).
    side = 0
    t = hi - ghi * (hi - lo) / (ghi - glo) if ghi != glo else 0.5 * (lo + hi)
    if not (lo < t < hi):
        t = 0.5 * (lo + hi)
    for _ in range(NEWTON_ITER):
        z, dz = _z(zeta, P, Q, t)
        g = z + c
        if g == 0.0:
            return t
        if (g > 0.0) == (g0 > 0.0):
            lo = t
            glo = g
            if side == 1:
                ghi *= 0.5
            side = 1
        else:
            hi = t
            ghi = g
            if side == -1:
                glo *= 0.5
            side = -1
        new = t - g / dz if dz != 0.0 else lo - 1.0
        if not (lo < new < hi):
            new = hi - ghi * (hi - lo) / (ghi - glo) if ghi != glo else 0.5 * (lo + hi)
            if not (lo < new < hi):
                new = 0.5 * (lo + hi)
        # Newton converges quadratically: after a step of 1e-10 t the error is ~1e-20 t.
        if abs(new - t) <= NEWTON_DONE * t or hi - lo <= 4e-16 * hi:
            return new
        t = new
    return t


@njit(cache=True, error_model="numpy")
def closed_form_impact(zeta, A, d):
    """One impact of ``x'' = A - max(0, d A + x + 2 zeta x')`` from (0, 1), in closed form.

    Returns (eps^2, e_N, end state code, x_m, x_e, v_e, floors), ``floors`` the flights from the
    force's floor; NaN where the phases do not end.
    """
    x_eq = (1.0 - d) * A
    x = 0.0
    v = 1.0
    x_m = np.nan
    compressing = True
    floors = 0
    for _ in range(MAX_PHASES):
        u = x - x_eq
        # Contact: the oscillator from (u, v).  Event coefficients (P, Q) of a u + b v:
        # u -> (u, v + zeta u); v -> (v, -(u + zeta v)).
        Pu, Qu = u, v + zeta * u
        Pv, Qv = v, -(u + zeta * v)
        t_v = _first_zero(zeta, Pv, Qv)  # the next turn of v
        if compressing:
            if not np.isfinite(t_v):
                return 0.0, 0.0, NO_RESTITUTION, x_eq, x_eq, 0.0, floors
            zu, _ = _z(zeta, Pu, Qu, t_v)
            x = x_eq + zu
            v = 0.0
            x_m = x
            compressing = False
            continue
        # Restitution: floor f = 0, separation x = 0, capture v = 0 (from below).
        t_f = np.inf
        if zeta > 0.0:
            t_f = _root(zeta, Pu + 2.0 * zeta * Pv, Qu + 2.0 * zeta * Qv, A, t_v)
        # v < 0 until t_v, so x falls monotonically up to the first of the floor and the turn; it
        # reaches 0 before them only if it is <= 0 there.  That needs f = d A + 2 zeta v >= 0 at x = 0:
        # an offset d A, or no damping (where the floor is x = 0 itself).
        t_end = min(t_v, t_f)
        zu, dzu = _z(zeta, Pu, Qu, t_end) if np.isfinite(t_end) else (-x_eq, 0.0)
        t_s = np.inf
        if x <= 0.0:
            t_s = 0.0
        elif (d > 0.0 or zeta == 0.0) and (x_eq + zu <= 0.0 or not np.isfinite(t_end)):
            t_s = _root(zeta, Pu, Qu, x_eq, t_end)
        if t_s <= t_f and np.isfinite(t_s):
            _, dz = _z(zeta, Pu, Qu, t_s)
            v_e = dz
            return (0.5 * v_e * v_e + A * x_m) / (0.5 + A * x_m), -v_e, SEPARATION, x_m, 0.0, v_e, floors
        if np.isfinite(t_f):
            # Flight from the floor.
            floors += 1
            ft, x, v = _flight_step(zeta, A, d, x_eq + zu, dzu)
            if ft == SEPARATION:
                return (0.5 * v * v + A * x_m) / (0.5 + A * x_m), -v, SEPARATION, x_m, 0.0, v, floors
            if ft == NONSEPARATION:
                return A * (x_m - x) / (0.5 + A * x_m), 0.0, NONSEPARATION, x_m, x, 0.0, floors
            continue  # re-contact: the oscillator again
        if np.isfinite(t_v):
            x_e = x_eq + zu
            return A * (x_m - x_e) / (0.5 + A * x_m), 0.0, NONSEPARATION, x_m, x_e, 0.0, floors
        return A * (x_m - x_eq) / (0.5 + A * x_m), 0.0, CREEP, x_m, x_eq, 0.0, floors
    return np.nan, np.nan, 0, np.nan, np.nan, np.nan, floors


@njit(cache=True, error_model="numpy")
def _flight_step(zeta, A, d, x0, v0):
    """Flight ``x'' = A`` from the floor: (SEPARATION, 0, v), (NONSEPARATION, x, 0), (0, x, v) re-contact."""
    # f(t) = f0 + (v0 + 2 zeta A) t + A t^2 / 2 with f0 = 0 at the floor.
    t_r = -2.0 * (v0 + 2.0 * zeta * A) / A if A > 0.0 else np.inf
    if not t_r > 0.0:
        t_r = np.inf
    disc = v0 * v0 - 2.0 * A * x0
    t_s = 2.0 * x0 / (-v0 + np.sqrt(disc)) if disc >= 0.0 else np.inf
    t_c = -v0 / A if A > 0.0 else np.inf
    if t_s <= t_r and t_s <= t_c:
        return SEPARATION, 0.0, v0 + A * t_s
    if t_c < t_r:
        return NONSEPARATION, x0 + t_c * (v0 + 0.5 * A * t_c), 0.0
    return 0, x0 + t_r * (v0 + 0.5 * A * t_r), v0 + A * t_r


@njit(cache=True, error_model="numpy")
def closed_form_restitution(zeta, A, d, kinematic):
    """Restitution (e_N if ``kinematic`` else eps) of one impact; NaN if it did not end."""
    eps2, e_n, _, _, _, _, _ = closed_form_impact(zeta, A, d)
    if kinematic:
        return e_n
    return np.sqrt(max(eps2, 0.0)) if eps2 == eps2 else np.nan


@twin_rows
@njit(cache=True, nogil=True, error_model="numpy")
def closed_form_rows(zeta, A, d, kinematic, out, start, stop):
    """Restitution (e_N if ``kinematic`` else eps) of rows ``start .. stop - 1`` of flat ``zeta``, ``A``."""
    for i in range(start, stop):
        out[i] = closed_form_restitution(zeta[i], A[i], d, kinematic)


@njit(cache=True, error_model="numpy")
def closed_form_states(zeta, A, d, out):
    """(eps^2, e_N, end state code, floors) of each impact at flat ``zeta``, ``A``, into ``out`` (n, 4)."""
    for i in range(zeta.size):
        eps2, e_n, state, _, _, _, floors = closed_form_impact(zeta[i], A[i], d)
        out[i, 0] = eps2
        out[i, 1] = e_n
        out[i, 2] = state
        out[i, 3] = floors
