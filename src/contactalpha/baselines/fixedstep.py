"""Fixed-step classical RK4 for one impact: the baseline of the benchmarks.

This is what a user would write without an adaptive engine: the scaled
impact equation (docs/science.md, "Scaling"; paper Eq. 24 after scaling)

    x'' = A - (5/4) x^{3/2} (1 + alpha x'),   x(0) = 0,  x'(0) = 1,

stepped with the classical fourth-order Runge-Kutta method at a constant step
``h``, events found by a sign change of ``v`` or ``x`` over a step and placed
on the step's cubic Hermite interpolant, and creep or no-restitution accepted
once the state rests within ``rest_tol`` of the static equilibrium.  Its force
law, scaled load and equilibrium are written out again here (``acceleration``,
``load_of_xi``, ``rest_position``) rather than imported from the engine, so a
wrong constant in the engine shows up as a disagreement with this baseline; it
borrows only the engine's names of end states and its result type.

It fails in the ways explicit fixed-step methods fail, and says so in
``status`` rather than returning a plausible number:

- "missed event": a stage of a step crossed an event that the step's end
  points do not show (the sign changed twice inside one step);
- "step limit exceeded": no end state within ``max_steps`` (a slow creep,
  or a step too small for the time span);
- "non-finite state": the step exceeds the stability limit of RK4 for the
  damping ``c = (5/4) alpha x^{3/2}`` and the solution blows up.
"""

import numpy as np
from numba import njit

from contactalpha.engine.driver import END_STATES, ImpactResult
from contactalpha.validation import check_alpha, check_count, check_range, check_xi

# Status codes: shared meaning with ``impact.STATUS``, plus a missed event.
OK = 0
MAX_STEPS = 1
NON_FINITE = 3
MISSED_EVENT = 7
STATUS = {
    OK: "ok",
    MAX_STEPS: "step limit exceeded",
    NON_FINITE: "non-finite state",
    MISSED_EVENT: "missed event",
}
# End-state codes, as in ``kernel.py``.
FAILED = 0
SEPARATION = 1
NONSEPARATION = 2
CREEP = 3
NO_RESTITUTION = 4
# Default step in scaled time: an impact lasts ~3-6 time units.
STEP = 1e-3
# Step budget: 1e8 steps (~3 s) cover a creep to 1e4 time units at h = 1e-4.
MAX_STEP_COUNT = 100_000_000
# Relative distance to x_eq (in x, and in v / x_eq) accepted as "at rest",
# as in ``reference.impact_scipy``.
REST_TOL = 1e-9
# Bisection steps placing an event on the Hermite interpolant (to 2^-60 of h).
EVENT_BISECTIONS = 60
# Number of fields returned by ``rk4_impact_kernel``.
N_RK4_OUT = 10


@njit(cache=True, error_model="numpy")
def acceleration(x, v, A, alpha):
    """Scaled Eq. 24: load minus Hertz force ``(5/4) x^1.5`` minus its damping ``alpha x' (5/4) x^1.5``."""
    if x <= 0.0:
        return A  # out of contact: the load alone
    hertz = 1.25 * x**1.5
    return A - hertz - alpha * v * hertz


@njit(cache=True, error_model="numpy")
def rest_position(A):
    """Static equilibrium of the scaled contact, where ``(5/4) x^1.5 = A``."""
    return (0.8 * A) ** (2.0 / 3.0)


def load_of_xi(xi):
    """Scaled load ``A = a delta_star / v0^2 = xi (1 - xi)^(-3/5) / 2`` (paper Eqs. 10, 11 scaled)."""
    return 0.5 * xi / (1.0 - xi) ** 0.6


@njit(cache=True, error_model="numpy")
def rk4_step(x, v, h, A, alpha):
    """One classical RK4 step from ``(x, v)``.

    Returns
    -------
    x1, v1 : float
        State after the step.
    v_lo, v_hi, x_lo : float
        Smallest and largest ``v`` and smallest ``x`` among the stage states,
        which reveal a sign change the end points hide.
    """
    k1x = v
    k1v = acceleration(x, v, A, alpha)
    x2 = x + 0.5 * h * k1x
    v2 = v + 0.5 * h * k1v
    k2x = v2
    k2v = acceleration(x2, v2, A, alpha)
    x3 = x + 0.5 * h * k2x
    v3 = v + 0.5 * h * k2v
    k3x = v3
    k3v = acceleration(x3, v3, A, alpha)
    x4 = x + h * k3x
    v4 = v + h * k3v
    k4x = v4
    k4v = acceleration(x4, v4, A, alpha)
    x1 = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x)
    v1 = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v)
    v_lo = min(v2, v3, v4)
    v_hi = max(v2, v3, v4)
    x_lo = min(x2, x3, x4)
    return x1, v1, v_lo, v_hi, x_lo


@njit(cache=True, error_model="numpy")
def hermite(y0, d0, y1, d1, h, theta):
    """Cubic Hermite interpolant at fraction ``theta`` of a step of length ``h``."""
    t2 = theta * theta
    t3 = t2 * theta
    return (
        (2.0 * t3 - 3.0 * t2 + 1.0) * y0
        + (t3 - 2.0 * t2 + theta) * h * d0
        + (-2.0 * t3 + 3.0 * t2) * y1
        + (t3 - t2) * h * d1
    )


@njit(cache=True, error_model="numpy")
def event_fraction(y0, d0, y1, d1, h):
    """Fraction of the step where the Hermite interpolant of ``y`` crosses zero (bisection)."""
    lo = 0.0
    hi = 1.0
    for _ in range(EVENT_BISECTIONS):
        mid = 0.5 * (lo + hi)
        if (hermite(y0, d0, y1, d1, h, mid) > 0.0) == (y0 > 0.0):
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@njit(cache=True, error_model="numpy")
def at_rest(x, v, xeq, rest_tol):
    """True when ``(x, v)`` lies within ``rest_tol`` of the equilibrium (relative to ``x_eq``)."""
    if not np.isfinite(xeq):
        return False
    return abs(x - xeq) <= rest_tol * xeq and abs(v) <= rest_tol * xeq


@njit(cache=True, error_model="numpy")
def rk4_impact_kernel(alpha, A, h, max_steps, rest_tol):
    """Integrate one impact with fixed-step RK4 and naive events.

    Returns
    -------
    out : ndarray, shape (10,)
        ``eps2, state, status, x_m, x_e, v_e, t_m, t_e, steps, nfev``.
    """
    out = np.full(N_RK4_OUT, np.nan)
    xeq = rest_position(A) if A > 0.0 else np.inf
    x = 0.0
    v = 1.0
    t = 0.0
    a = acceleration(x, v, A, alpha)
    compressing = True
    state = FAILED
    status = MAX_STEPS
    x_m = np.nan
    t_m = np.nan
    x_e = np.nan
    v_e = np.nan
    t_e = np.nan
    steps = 0
    while steps < max_steps:
        x1, v1, v_lo, v_hi, x_lo = rk4_step(x, v, h, A, alpha)
        a1 = acceleration(x1, v1, A, alpha)
        steps += 1
        if not (np.isfinite(x1) and np.isfinite(v1)):
            status = NON_FINITE
            break
        if compressing:
            if v1 <= 0.0:
                th = event_fraction(v, a, v1, a1, h)
                x_m = hermite(x, v, x1, v1, h, th)
                t_m = t + th * h
                compressing = False
            elif v_lo < 0.0:
                status = MISSED_EVENT
                break
            elif at_rest(x1, v1, xeq, rest_tol):
                state = NO_RESTITUTION
                x_m = xeq
                x_e = xeq
                v_e = 0.0
                t_m = np.inf
                t_e = np.inf
        elif x1 <= 0.0:
            th = event_fraction(x, v, x1, v1, h)
            state = SEPARATION
            x_e = 0.0
            v_e = hermite(v, a, v1, a1, h, th)
            t_e = t + th * h
        elif v1 > 0.0:
            th = event_fraction(v, a, v1, a1, h)
            state = NONSEPARATION
            x_e = hermite(x, v, x1, v1, h, th)
            v_e = 0.0
            t_e = t + th * h
        elif v_hi > 0.0 or x_lo < 0.0:
            status = MISSED_EVENT
            break
        elif at_rest(x1, v1, xeq, rest_tol):
            state = CREEP
            x_e = xeq
            v_e = 0.0
            t_e = np.inf
        if state != FAILED:
            status = OK
            break
        x = x1
        v = v1
        a = a1
        t += h
    if status == OK:
        if state == NO_RESTITUTION:
            out[0] = 0.0
        else:
            out[0] = (0.5 * v_e * v_e + A * (x_m - x_e)) / (0.5 + A * x_m)
    out[1] = state
    out[2] = status
    out[3] = x_m
    out[4] = x_e
    out[5] = v_e
    out[6] = t_m
    out[7] = t_e
    out[8] = steps
    out[9] = 4 * steps + 1
    return out


def impact_rk4(alpha, xi, *, h=STEP, max_steps=MAX_STEP_COUNT, rest_tol=REST_TOL):
    """One impact of the scaled Eq. 24 by fixed-step RK4 (scalar inputs).

    Parameters
    ----------
    alpha : float
        Hysteresis damping factor, >= 0.
    xi : float
        Influence factor of the load, 0 <= xi < 1.
    h : float
        Step in scaled time, in (0, 1].
    max_steps : int
        Step budget; running out is reported as "step limit exceeded".
    rest_tol : float
        Relative distance to ``x_eq`` accepted as creep or no restitution.

    Returns
    -------
    ImpactResult
        Same fields as ``impact``; ``deps_dalpha`` is NaN (no sensitivities)
        and ``status`` may also read "missed event".
    """
    alpha = float(check_alpha(alpha))
    xi = float(check_xi(xi))
    h = float(check_range("h", h, 0.0, 1.0, lo_open=True))
    rest_tol = float(check_range("rest_tol", rest_tol, 0.0, 1e-3, lo_open=True))
    max_steps = check_count("max_steps", max_steps, 1, 1e10)
    out = rk4_impact_kernel(alpha, load_of_xi(xi), h, max_steps, rest_tol)
    status = int(out[2])
    return ImpactResult(
        eps=np.sqrt(out[0]) if status == OK else np.nan,
        state=END_STATES[int(out[1])],
        x_max=out[3],
        x_end=out[4],
        v_end=out[5],
        t_max=out[6],
        t_end=out[7],
        steps=int(out[8]),
        nfev=int(out[9]),
        status=STATUS[status],
        deps_dalpha=np.nan,
    )
