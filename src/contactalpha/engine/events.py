"""Event location and the two end states that are only reached as t -> infinity.

Events (maximum compression ``v = 0``, separation ``x = 0``, non-separation
``v = 0`` again) are placed by re-integrating the step that crossed them with
the event variable as the independent variable, adaptively, to exactly zero.
The placement is then as accurate as the steps themselves.

Creep and no-restitution are proved, not guessed: ``trapped_above`` and
``trapped_below`` test whether the state lies in a sector of the phase plane
that the flow can never leave.  Write ``f(x) = A - (5/4) x^{3/2}`` and
``c(x) = (5/4) alpha x^{3/2}``, so that ``x'' = f(x) - c(x) v``, and
``u = x - x_eq``.  On the line ``v = -s u`` the flow points into the sector
``{-s u <= v <= 0, u > 0}`` when ``s (c - s) >= f / (-u)`` (the secant slope
``g`` of the Hertz force) at every ``x`` between ``x_eq`` and the current
point; with ``c`` increasing and ``g`` increasing in ``x`` it is enough that
``s (c(x_eq) - s) >= g(x)``.  The mirror sector below ``x_eq`` uses ``c(x)``
and the tangent slope at ``x_eq``.  Inside either sector ``v`` keeps its sign
for ever and ``x -> x_eq``.
"""

import numpy as np
from numba import njit

from .codes import OK, STEP_LIMIT, STEP_UNDERFLOW
from .rk import (
    HERTZ,
    N_STAGES,
    N_STATE,
    dop853_step,
    error_norm,
    rhs,
    step_factor,
)

# Relative margin on the trap tests, so that rounding in the computed
# trajectory can never turn a borderline state into a false proof.
TRAP_MARGIN = 1e-6
# Below this distance from x_eq (relative, in u and in v / sqrt(k)) the
# end of the impact is taken from the linearised equation, whose error in
# x_e is O(u^2 / x_eq) ~ 1e-14 x_eq.  Near critical damping the nonlinear
# path creeps towards x_eq for ever and a v = 0 event there is ill-posed.
LINEAR_ZONE = 1e-7
# Relative gap |c^2 - 4k| / 4k below which damping counts as critical.
CRITICAL_GAP = 1e-12
# A step-size floor relative to the span being integrated.
MIN_REL_STEP = 1e-14


@njit(cache=True, error_model="numpy")
def equilibrium(A):
    """Static equilibrium ``x_eq = (4A/5)^{2/3}`` of the loaded contact."""
    return (A / HERTZ) ** (2.0 / 3.0)


@njit(cache=True, error_model="numpy")
def trapped_above(x, v, A, alpha):
    """True when the restitution phase provably creeps down to ``x_eq``."""
    xeq = equilibrium(A)
    u = x - xeq
    if u <= 0.0 or v > 0.0 or A <= 0.0:
        return False
    c = alpha * A  # c(x_eq), since (5/4) x_eq^{3/2} = A
    g = HERTZ * (x * np.sqrt(x) - A / HERTZ) / u
    disc = c * c - 4.0 * g * (1.0 + TRAP_MARGIN)
    if disc < 0.0:
        return False
    s = 0.5 * (c + np.sqrt(disc))
    return -v <= s * u * (1.0 - TRAP_MARGIN)


@njit(cache=True, error_model="numpy")
def trapped_below(x, v, A, alpha):
    """True when compression provably creeps up to ``x_eq`` and never reverses."""
    xeq = equilibrium(A)
    u = xeq - x
    if u <= 0.0 or v < 0.0 or x <= 0.0:
        return False
    c = HERTZ * alpha * x * np.sqrt(x)
    g = 1.5 * HERTZ * np.sqrt(xeq)  # tangent slope of the Hertz force at x_eq
    disc = c * c - 4.0 * g * (1.0 + TRAP_MARGIN)
    if disc < 0.0:
        return False
    s = 0.5 * (c + np.sqrt(disc))
    return v <= s * u * (1.0 - TRAP_MARGIN)


@njit(cache=True, error_model="numpy")
def linear_constants(A, alpha):
    """Stiffness ``k = (15/8) sqrt(x_eq)`` and damping ``c = alpha A`` of the motion about x_eq."""
    return 1.5 * HERTZ * np.sqrt(equilibrium(A)), alpha * A


@njit(cache=True, error_model="numpy")
def in_linear_zone(x, v, A, alpha):
    """True when ``(x, v)`` is close enough to equilibrium for ``linear_turn``."""
    if A <= 0.0:
        return False
    xeq = equilibrium(A)
    k, _ = linear_constants(A, alpha)
    return abs(x - xeq) + abs(v) / np.sqrt(k) <= LINEAR_ZONE * xeq


@njit(cache=True, error_model="numpy")
def linear_turn(u0, v0, k, c):
    """First turning point of ``u'' + c u' + k u = 0`` from ``(u0, v0)``.

    Returns ``(turns, u_turn)``: whether ``u'`` returns to zero at some
    ``t > 0``, and ``u`` there (0 when it never turns: the approach to
    equilibrium is monotone).  From rest (``v0 = 0``) only an underdamped
    motion turns again, half a period later; the general formulas below are
    0/0 there, and rounding would decide.
    """
    sigma = 0.5 * c
    gap = c * c - 4.0 * k
    if v0 == 0.0:
        if gap >= -CRITICAL_GAP * 4.0 * k:
            return False, 0.0
        return True, -u0 * np.exp(-sigma * np.pi / np.sqrt(-0.25 * gap))
    if abs(gap) <= CRITICAL_GAP * 4.0 * k:
        # u = (a + b t) exp(-sigma t), u' = 0 at t = v0 / (sigma b).
        b = v0 + sigma * u0
        if b == 0.0 or sigma == 0.0:
            return False, 0.0
        t = v0 / (sigma * b)
        if t <= 0.0:
            return False, 0.0
        return True, (u0 + b * t) * np.exp(-sigma * t)
    if gap < 0.0:
        w = np.sqrt(-0.25 * gap)
        d = (k * u0 + sigma * v0) / w
        theta = 0.5 * np.pi - np.arctan(d / v0)
        t = theta / w
        q = (v0 + sigma * u0) / w
        return True, np.exp(-sigma * t) * (u0 * np.cos(theta) + q * np.sin(theta))
    root = np.sqrt(0.25 * gap)
    r1 = -sigma + root
    r2 = -sigma - root
    a1 = (v0 - r2 * u0) / (r1 - r2)
    a2 = u0 - a1
    if a1 == 0.0:
        return False, 0.0
    rho = -r2 * a2 / (r1 * a1)
    if rho <= 1.0:
        return False, 0.0
    t = np.log(rho) / (r1 - r2)
    return True, a1 * np.exp(r1 * t) + a2 * np.exp(r2 * t)


@njit(cache=True, error_model="numpy")
def locate(y, k, A, alpha, rtol, atol, max_steps, K, y_new, ytmp):
    """Integrate from ``y`` with ``y[k]`` as the independent variable until ``y[k] = 0``.

    ``y`` is overwritten with the state at the event.  Returns
    ``(status, steps, nfev)``.  The caller guarantees that ``y[k]`` moves
    monotonically towards zero over the step that crossed the event.
    """
    span = -y[k]
    if span == 0.0:
        return OK, 0, 0
    h = span
    hmin = MIN_REL_STEP * abs(span)
    rejected: np.bool_ = np.bool_(False)
    steps = 0
    nfev = 1
    rhs(y, A, alpha, k, K[0])
    while True:
        remaining = -y[k]
        if abs(h) >= abs(remaining):
            h = remaining
        dop853_step(y, h, A, alpha, k, K, y_new, ytmp)
        nfev += N_STAGES
        err = error_norm(K, h, y, y_new, rtol, atol)
        if err <= 1.0:
            last = h == remaining
            for i in range(N_STATE):
                y[i] = y_new[i]
                K[0, i] = K[N_STAGES, i]
            steps += 1
            if last:
                y[k] = 0.0
                return OK, steps, nfev
            h *= step_factor(err, rejected)
            rejected = np.bool_(False)
        else:
            h *= step_factor(err, np.bool_(True))
            rejected = np.bool_(True)
            if abs(h) < hmin:
                return STEP_UNDERFLOW, steps, nfev
        if steps >= max_steps:
            return STEP_LIMIT, steps, nfev
