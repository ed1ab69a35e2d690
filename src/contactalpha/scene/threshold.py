"""The physical bounce threshold: the approach speed below which an impact cannot separate.

For a scene of mass ``m``, Hertz stiffness ``k`` and constant acceleration ``a`` towards
the contact, the scaled load of an impact at approach speed ``v`` is
``A = a delta_star / v^2 = a L1 v^(-6/5)``, with ``L1`` the length scale at 1 m/s
(``scaling.length_scale``): slower impacts carry a larger load.  With the exact alpha
the impact separates while ``A < A_b(eps)``, the scaled load at which the separation
boundary (``engine.boundary``) passes through ``eps``; so it separates above the
**critical approach speed**

    v_crit(eps; m, k, a) = (a L1 / A_b(eps))^(5/6)

and ends without separation below it.  ``critical_speed`` solves ``eps_b(A) = eps``
for ``A_b`` with Brent's method on ``ln A``.

Each ``eps_b(A)`` starts from the bisection of ``boundary_kernel`` and refines it
(``boundary_point``): within about 1e-5 (relative, in alpha) of the boundary the
kernel's end state is unreliable (it reports non-separation with ``x_end < 0``, then
separation again), so the bisection alone is off by ~1e-5 in alpha and ~1e-6 in
``eps_b``.  The refinement uses the **end gap** ``s(alpha)``, which is smooth across
the boundary: ``x_end`` for a non-separating impact and ``-v_end^2 / (2A)`` for a
separating one (the lowest point of the flight parabola that continues it; the Hertz
force vanishes at ``x = 0``).  A cubic through ``s`` at four dampings outside the
unreliable band, ``alpha_0 (1 + k h)`` with ``k = -2, -1, 1, 2`` and ``h =
BOUNDARY_STEP``, gives ``alpha_b`` as its root, and the cubic through Stronge's
``eps`` at the same four points gives ``eps_b`` there; halving ``h`` moves ``eps_b`` by
less than 1e-12, so ``v_crit`` is good to better than 1e-8 relative.

``boundary_load_fit`` is a compact fit of the same boundary: six constants times the
exact limits ``A_b ~ c0 eps^(3/2)`` (eps -> 0) and ``A_b ~ 2^(-3/5) / 2 (1 - eps)^(-3/5)``
(eps -> 1, where ``1 - xi_b ~ 2 (1 - eps)``), good to ``BOUNDARY_FIT_RTOL`` in ``A_b``
(so 5/6 of that in ``v_crit``) over ``BOUNDARY_FIT_DOMAIN``.
"""

import warnings

import numpy as np

from contactalpha.engine.boundary import LIMIT_EPS_POWER, LIMIT_ONE_MINUS_EPS_POWER, boundary_kernel
from contactalpha.engine.codes import (
    N_REC,
    NO_BRACKET,
    NONSEPARATION,
    NOT_CONVERGED,
    OK,
    OUT_EPS2,
    OUT_STATE,
    OUT_STATUS,
    OUT_V_END,
    OUT_X_END,
    SEPARATION,
    STATUS,
    STEP_LIMIT,
)
from contactalpha.engine.driver import ATOL, MAX_STEPS, RTOL
from contactalpha.engine.kernel import impact_kernel
from contactalpha.engine.scaling import length_scale
from contactalpha.laws import DEFAULT_LAW, get_law
from contactalpha.validation import (
    FloatOrArray,
    RealLike,
    check_max_steps,
    check_positive,
    check_range,
    check_scalar,
    check_tolerances,
)

from .law_scene import law_critical_speed

# Exponents of the fit's limits (derived, not fitted: ``engine.boundary.LIMIT_*``).
FIT_EPS_POWER = LIMIT_EPS_POWER
FIT_ONE_MINUS_EPS_POWER = -LIMIT_ONE_MINUS_EPS_POWER
# ln(A_b / (eps^1.5 (1 - eps)^-0.6)) as a polynomial in eps, highest power first (np.polyval);
# least squares (``fit_boundary``) on the exact boundary (``boundary_point``) at 400 log-spaced
# 1e-6 <= A <= 1e3 (398 solved, 1.9e-4 <= eps_b <= 0.999998): max error 4.5e-4 in A_b.  Six
# constants: degree 4 misses 1e-3 (1.6e-3), degree 5 is the smallest that meets it.
BOUNDARY_FIT = (-0.4531406681, 1.35106537, -1.273176153, 0.2781702426, -0.08713314998, -0.9248571271)
# Degree of that polynomial.
BOUNDARY_FIT_DEGREE = len(BOUNDARY_FIT) - 1
# Range of eps where the fit is checked (tests, the workflow's report) ...
BOUNDARY_FIT_DOMAIN = (1e-3, 0.9999)
# ... and the relative error in A_b it is good to there.
BOUNDARY_FIT_RTOL = 1e-3
# First relative step in alpha of the end-gap stencil around the bisected boundary: 10x the
# width of the band where the kernel's end state is unreliable at moderate loads (~1e-5), small
# enough that the cubic's error is below 1e-12 in eps_b (h = 1e-4 and 3e-5 agree to 1e-12 at
# A = 0.005, 0.2 and 2).  At large loads (tiny alpha_b) the band is wider (the bisection misses by
# 0.17% at A = 83) and the step grows until the stencil clears it; the root moves by < 1e-8 in
# alpha_b and not in eps_b's 9th digit between h = 3e-3 and 0.1 there.
BOUNDARY_STEP = 1e-4
# If a stencil point still falls in the band, the step grows by this factor, at most this often
# (1e-4 * 3^7 = 0.22).
BOUNDARY_STEP_GROWTH = 3.0
BOUNDARY_STEP_TRIES = 8
# The bisection that starts the refinement can itself meet a failed event location in the band
# (A = 2.418: 'event location failed' at rtol 1e-12, fine at 1e-11); it is retried with the
# tolerances loosened by these factors.  Only the start is loose: the stencil runs at rtol.
START_RTOL_FACTORS = (1.0, 10.0, 100.0)
# Stencil points, in units of the step (two on each side of the boundary).
STENCIL = np.array([-2.0, -1.0, 1.0, 2.0])
# No trajectory is recorded.
NO_RECORD = np.empty((0, N_REC))
# Root of eps_b(A) = eps: absolute tolerance on ln A (v_crit then to 5/6 of it, relative).
LOG_LOAD_XTOL = 1e-12
# First bracket around the fit's ln A_b, widened by this factor of A until it holds the root.
BRACKET_WIDTH = 0.05
# Widenings of the bracket before giving up (NO_BRACKET).
BRACKET_TRIES = 40
# Smallest restitution ``critical_speed`` takes: below it the boundary sits at loads A_b < 1e-6
# (A_b ~ eps^1.5), outside the range the fit and the refinement were checked on, and the damping
# there is so heavy that one search takes minutes (eps = 1e-5: 81 s) or divides by zero (1e-6).
CRITICAL_EPS_MIN = 1e-4


def end_gap(alpha, A, *, rtol=RTOL, atol=ATOL, max_steps=MAX_STEPS):
    """End gap ``s``, Stronge's ``eps``, end-state and status codes of one scaled impact.

    ``s = x_end`` without separation and ``-v_end^2 / (2 A)`` with it: smooth across the
    separation boundary, where it is 0.
    """
    out, _ = impact_kernel(float(alpha), float(A), rtol, atol, max_steps, NO_RECORD, np.inf)
    state, status = int(out[OUT_STATE]), int(out[OUT_STATUS])
    gap = -(out[OUT_V_END] ** 2) / (2.0 * A) if state == SEPARATION else out[OUT_X_END]
    return gap, np.sqrt(max(out[OUT_EPS2], 0.0)), state, status


def boundary_point(A, *, rtol=RTOL, atol=ATOL, max_steps=MAX_STEPS):
    """Damping ``alpha_b`` and restitution ``eps_b`` on the separation boundary at scaled load ``A > 0``.

    Returns
    -------
    alpha_b, eps_b : float
        NaN if the search failed.
    status : int
        ``codes.OK`` or the failure code.
    """
    for factor in START_RTOL_FACTORS:
        alpha0, _, status = boundary_kernel(float(A), rtol * factor, atol * factor, max_steps)
        if status == OK:
            break
    else:
        return np.nan, np.nan, int(status)
    h = BOUNDARY_STEP
    for _ in range(BOUNDARY_STEP_TRIES):
        dalpha = alpha0 * h * STENCIL
        rows = [end_gap(alpha0 + d, A, rtol=rtol, atol=atol, max_steps=max_steps) for d in dalpha]
        gap, eps, state, stat = (np.array(c) for c in zip(*rows, strict=True))
        # A failed event location next to the boundary is the same band: widen the stencil too.
        failure = int(stat[stat != OK][0]) if np.any(stat != OK) else OK
        # Lighter damping separates, heavier does not, and the gaps agree with the states (a
        # non-separation with x_end < 0 is the kernel's misclassification); else the stencil
        # still touches the unreliable band (or the bisection missed by more than h): widen it.
        sides = np.all(state[:2] == SEPARATION) and np.all(state[2:] == NONSEPARATION)
        if failure == OK and sides and np.all(gap[:2] < 0.0) and np.all(gap[2:] > 0.0):
            break
        h *= BOUNDARY_STEP_GROWTH
    else:
        return np.nan, np.nan, failure if failure != OK else NO_BRACKET
    roots = np.roots(np.polyfit(dalpha, gap, STENCIL.size - 1))
    roots = roots[np.isreal(roots)].real
    roots = roots[(roots > dalpha[1]) & (roots < dalpha[2])]
    if roots.size != 1:
        return np.nan, np.nan, NOT_CONVERGED
    eps_b = float(np.polyval(np.polyfit(dalpha, eps, STENCIL.size - 1), roots[0]))
    return float(alpha0 + roots[0]), eps_b, OK


def boundary_eps(A, *, rtol=RTOL, atol=ATOL, max_steps=MAX_STEPS):
    """Restitution ``eps_b`` on the separation boundary at scaled load ``A > 0``, and its status code."""
    _, eps_b, status = boundary_point(A, rtol=rtol, atol=atol, max_steps=max_steps)
    return eps_b, status


def boundary_load_fit(eps):
    """Scaled load ``A_b`` on the separation boundary for restitution ``eps``, from the compact fit.

    Parameters
    ----------
    eps : array_like
        Restitution, 0 < eps < 1.

    Returns
    -------
    float or ndarray
        Good to ``BOUNDARY_FIT_RTOL`` relative over ``BOUNDARY_FIT_DOMAIN``.
    """
    e = check_range("eps", eps, 0.0, 1.0, lo_open=True, hi_open=True)
    g = np.polyval(BOUNDARY_FIT, e)
    out = e**FIT_EPS_POWER * (1.0 - e) ** FIT_ONE_MINUS_EPS_POWER * np.exp(g)
    return out[()] if np.ndim(out) == 0 else out


def fit_boundary(eps_b, A_b, degree=BOUNDARY_FIT_DEGREE):
    """Least-squares constants of ``boundary_load_fit`` from exact boundary points ``(eps_b, A_b)``."""
    e = np.asarray(eps_b, dtype=float)
    g = np.log(np.asarray(A_b, dtype=float) / (e**FIT_EPS_POWER * (1.0 - e) ** FIT_ONE_MINUS_EPS_POWER))
    return tuple(float(c) for c in np.polyfit(e, g, degree))


def boundary_load(eps, *, rtol=RTOL, atol=ATOL, max_steps=MAX_STEPS):
    """Exact scaled load ``A_b`` at which the separation boundary passes through ``eps``.

    Parameters
    ----------
    eps : float
        Restitution, 0 < eps < 1.

    Returns
    -------
    A_b : float
        NaN where the boundary search failed.
    status : str
        ``"ok"`` or the reason (``codes.STATUS``).
    """
    from scipy.optimize import brentq  # lazy: 0.2-0.7 s of import in every job

    e = float(check_range("eps", eps, 0.0, 1.0, lo_open=True, hi_open=True))
    failed = []

    def residual(log_A):
        eps_b, status = boundary_eps(np.exp(log_A), rtol=rtol, atol=atol, max_steps=max_steps)
        if status != OK:
            failed.append(status)
            return np.nan
        return eps_b - e

    guess = np.log(boundary_load_fit(e))
    lo, hi = guess - BRACKET_WIDTH, guess + BRACKET_WIDTH
    f_lo, f_hi = residual(lo), residual(hi)
    for _ in range(BRACKET_TRIES):
        if failed or f_lo * f_hi <= 0.0:
            break
        # eps_b grows with A: move the end on the wrong side outwards.
        if f_lo > 0.0:
            lo -= hi - lo
            f_lo = residual(lo)
        else:
            hi += hi - lo
            f_hi = residual(hi)
    if failed:
        return np.nan, STATUS[failed[0]]
    if not f_lo * f_hi <= 0.0:
        return np.nan, STATUS[NO_BRACKET]
    log_A = brentq(residual, lo, hi, xtol=LOG_LOAD_XTOL, rtol=4 * np.finfo(float).eps)
    if failed:
        return np.nan, STATUS[failed[0]]
    return float(np.exp(log_A)), STATUS[OK]


def speed_for_load(A, mass, stiffness, accel):
    """Approach speed at which acceleration ``accel`` gives scaled load ``A``: ``(a L1 / A)^(5/6)``."""
    A = check_positive("A", A)
    a = check_positive("accel", accel)
    unit = length_scale(mass, stiffness, 1.0)  # delta_star at 1 m/s; delta_star ~ v^(4/5)
    return (a * unit / A) ** (5.0 / 6.0)


def critical_speed(
    eps: RealLike,
    mass: float,
    stiffness: float,
    accel: float,
    *,
    rtol: float = RTOL,
    atol: float = ATOL,
    max_steps: int = MAX_STEPS,
    law: str | None = None,
) -> FloatOrArray:
    """Critical approach speed: above it an impact with the exact alpha separates, below it not.

    Parameters
    ----------
    eps : float or array_like
        Restitution (Stronge), ``CRITICAL_EPS_MIN`` (1e-4) <= eps <= 1; at eps = 1 every impact
        separates (v_crit = 0).
    mass, stiffness, accel : float
        Mass (kg, > 0), Hertz stiffness (N/m^1.5, > 0) and the constant acceleration
        towards the contact (m/s^2, > 0; gravity plus force over mass).
    rtol, atol, max_steps
        Impact integrator settings of the boundary search, as in ``impact`` (rtol in
        [1e-15, 0.1], atol in (0, 1], max_steps a whole number in [1, 1e15]).
    law : str or ContactLaw, optional
        The contact law (``contactalpha.laws``); default Hunt-Crossley n = 3/2.  Another law
        bisects its own boundary (``scene.law_scene.law_critical_speed``; stiffness in its units).

    Returns
    -------
    v_crit : float or ndarray, m/s
        Good to 1e-8 relative; NaN where the boundary search failed (then see
        ``critical_speed_status``).
    """
    v, status = critical_speed_status(
        eps, mass, stiffness, accel, rtol=rtol, atol=atol, max_steps=max_steps, law=law
    )
    bad = np.atleast_1d(status).ravel() != STATUS[OK]
    if np.any(bad):
        at = np.atleast_1d(np.asarray(eps, dtype=float)).ravel()[bad]
        reason = np.atleast_1d(status).ravel()[bad][0]
        warnings.warn(
            f"critical_speed: the boundary search failed at eps = {float(at[0])!r} ({int(bad.sum())} of "
            f"{bad.size} points): {reason}; the speed is NaN there (critical_speed_status gives each status)",
            RuntimeWarning,
            stacklevel=2,
        )
    return v


def critical_speed_status(
    eps, mass, stiffness, accel, *, rtol=RTOL, atol=ATOL, max_steps=MAX_STEPS, law=None
):
    """``critical_speed`` and a status (``"ok"`` or why it is NaN) per point."""
    e = check_range("eps", eps, CRITICAL_EPS_MIN, 1.0)
    for name, value in (("mass", mass), ("stiffness", stiffness), ("accel", accel)):
        check_scalar(name, value, 0.0, np.inf, lo_open=True, hi_open=True)
    rtol, atol = check_tolerances(rtol, atol)
    max_steps = check_max_steps(max_steps)
    flat = np.atleast_1d(e).ravel()
    if law is not None and get_law(law).name != DEFAULT_LAW:
        v, status = law_critical_speed(
            law, flat, mass, stiffness, accel, rtol=rtol, atol=atol, max_steps=max_steps
        )
    else:
        v, status = _hertz_critical_speed(flat, mass, stiffness, accel, rtol, atol, max_steps)
    for i in np.flatnonzero(status == STATUS[STEP_LIMIT]):
        status[i] = f"{status[i]} (max_steps = {max_steps}): give a larger max_steps"
    if np.ndim(e) == 0:
        return float(v[0]), status[0]
    return v.reshape(np.shape(e)), status.reshape(np.shape(e))


def _hertz_critical_speed(flat, mass, stiffness, accel, rtol, atol, max_steps):
    v = np.zeros(flat.shape)
    status = np.full(flat.shape, STATUS[OK], dtype=object)
    for i, value in enumerate(flat):
        if value == 1.0:
            continue
        A_b, status[i] = boundary_load(value, rtol=rtol, atol=atol, max_steps=max_steps)
        v[i] = speed_for_load(A_b, mass, stiffness, accel) if np.isfinite(A_b) else np.nan
    return v, status


def critical_speed_fit(eps, mass, stiffness, accel):
    """``critical_speed`` from the compact fit (``boundary_load_fit``): 5/6 of its error, no integration."""
    return speed_for_load(boundary_load_fit(eps), mass, stiffness, accel)
