"""Independent reference: the same impact with SciPy's ``solve_ivp`` and its event finder.

This is the oracle of the tests and the baseline of the benchmarks.  It shares
no numerical code with the jitted engine: its right-hand side, events and
end-state logic are written out again here, in plain NumPy, in physical units
when asked.  Creep and no-restitution, which only end as t -> inf, are
recognised when the run reaches ``t_max`` resting within ``rest_tol`` of the
static equilibrium.
"""

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from contactalpha.validation import check_alpha, check_positive, check_range


@dataclass(frozen=True)
class ReferenceResult:
    """Outcome of ``impact_scipy``/``impact_physical`` (scaled or SI units, as asked)."""

    eps: float
    state: str
    x_max: float
    x_end: float
    v_end: float
    nfev: int
    status: str


def _events(sign_v):
    def hit_v(t, y, *args):
        return y[1]

    hit_v.terminal = True  # type: ignore[attr-defined]  # solve_ivp reads an event's attributes
    hit_v.direction = sign_v  # type: ignore[attr-defined]

    def hit_x(t, y, *args):
        return y[0]

    hit_x.terminal = True  # type: ignore[attr-defined]
    hit_x.direction = -1  # type: ignore[attr-defined]
    return hit_v, hit_x


def _run(fun, x_eq, v_scale, energy, *, method, rtol, atol, t_max, rest_tol):
    """Drive the two phases; ``energy(x_m, x_e, v_e)`` gives ``eps^2``."""
    kw = dict(method=method, rtol=rtol, atol=atol, dense_output=False)
    hit_v, _ = _events(-1)
    first = solve_ivp(fun, (0.0, t_max), [0.0, v_scale], events=[hit_v], **kw)
    nfev = first.nfev
    if not first.success:
        return ReferenceResult(np.nan, "failed", np.nan, np.nan, np.nan, nfev, first.message)
    if first.t_events[0].size == 0:
        x, v = first.y[:, -1]
        if abs(x - x_eq) <= rest_tol * x_eq and v >= 0:
            return ReferenceResult(0.0, "no_restitution", x_eq, x_eq, 0.0, nfev, "ok")
        return ReferenceResult(np.nan, "failed", np.nan, np.nan, np.nan, nfev, "no max compression by t_max")
    x_m = first.y_events[0][0][0]
    t_m = first.t_events[0][0]
    up, down = _events(+1)
    second = solve_ivp(fun, (t_m, t_m + t_max), [x_m, 0.0], events=[down, up], **kw)
    nfev += second.nfev
    if not second.success:
        return ReferenceResult(np.nan, "failed", x_m, np.nan, np.nan, nfev, second.message)
    if second.t_events[0].size:
        x_e, v_e, state = 0.0, second.y_events[0][0][1], "separation"
    elif second.t_events[1].size:
        x_e, v_e, state = second.y_events[1][0][0], 0.0, "nonseparation"
    else:
        x, v = second.y[:, -1]
        if abs(x - x_eq) > rest_tol * x_eq:
            return ReferenceResult(np.nan, "failed", x_m, np.nan, np.nan, nfev, "no end state by t_max")
        x_e, v_e, state = x_eq, 0.0, "creep"
    return ReferenceResult(float(np.sqrt(energy(x_m, x_e, v_e))), state, x_m, x_e, v_e, nfev, "ok")


def impact_scipy(alpha, xi, *, method="DOP853", rtol=1e-12, atol=1e-14, t_max=1e4, rest_tol=1e-9):
    """Scaled impact (same equation as ``impact``) integrated by ``scipy.integrate.solve_ivp``.

    Parameters
    ----------
    alpha, xi : float
        Damping factor and influence factor.
    method : str
        Any ``solve_ivp`` method: "RK45", "DOP853", "Radau", "LSODA", ...
    rtol, atol : float
        ``solve_ivp`` tolerances.
    t_max : float
        Scaled time limit of each phase.
    rest_tol : float
        Relative distance to ``x_eq`` that counts as having reached it.
    """
    alpha = float(check_alpha(alpha))
    xi = float(check_range("xi", xi, 0.0, 1.0, hi_open=True))
    A = 0.5 * xi * (1.0 - xi) ** -0.6

    def fun(t, y):
        x = max(y[0], 0.0)
        return [y[1], A - 1.25 * x**1.5 * (1.0 + alpha * y[1])]

    x_eq = (A / 1.25) ** (2.0 / 3.0) if A > 0 else np.inf

    def energy(x_m, x_e, v_e):
        return (0.5 * v_e**2 + A * (x_m - x_e)) / (0.5 + A * x_m)

    return _run(fun, x_eq, 1.0, energy, method=method, rtol=rtol, atol=atol, t_max=t_max, rest_tol=rest_tol)


def impact_physical(alpha, m_e, k, v0, a, *, method="DOP853", rtol=1e-12, atol=None, t_max=None):
    """Eq. 24 in SI units, ``m_e d'' + (alpha k / v0) d^{3/2} d' + k d^{3/2} = m_e a``.

    Returns a ``ReferenceResult`` with ``x_*`` in metres and ``v_end`` in m/s;
    ``eps`` is Stronge's coefficient from the works of the contact force.
    """
    alpha = float(check_alpha(alpha))
    m_e, k, v0 = (float(check_positive(n, v)) for n, v in (("m_e", m_e), ("k", k), ("v0", v0)))
    a = float(check_range("a", a, 0.0, np.inf, hi_open=True))
    d_star = (1.25 * m_e * v0**2 / k) ** 0.4
    atol = 1e-14 * d_star if atol is None else atol
    t_max = 1e4 * d_star / v0 if t_max is None else t_max

    def fun(t, y):
        d = max(y[0], 0.0)
        return [y[1], a - k / m_e * d**1.5 * (1.0 + alpha * y[1] / v0)]

    x_eq = (m_e * a / k) ** (2.0 / 3.0) if a > 0 else np.inf

    def energy(x_m, x_e, v_e):
        return (0.5 * m_e * v_e**2 + m_e * a * (x_m - x_e)) / (0.5 * m_e * v0**2 + m_e * a * x_m)

    return _run(fun, x_eq, v0, energy, method=method, rtol=rtol, atol=atol, t_max=t_max, rest_tol=1e-9)


class _BudgetExceeded(Exception):
    """Raised inside ``solve_ivp`` when an impact has used its RHS budget."""


# The function of SciPy's solve_ivp that places an event (a bracketing root-finder).
EVENT_SOLVER = "solve_event_equation"


def _from_event_location(err):
    """True if ``err`` was raised while SciPy placed an event, not by a bad argument."""
    tb = err.__traceback__
    while tb is not None:
        if tb.tb_frame.f_code.co_name == EVENT_SOLVER:
            return True
        tb = tb.tb_next
    return False


def impact_scipy_limited(
    alpha, xi, *, method="DOP853", rtol=1e-12, atol=1e-14, max_nfev=200_000, t_max=1e4, rest_tol=1e-9
):
    """``impact_scipy`` with a budget of right-hand-side evaluations: the step limit of SciPy runs.

    Stiff impacts can cost explicit SciPy methods millions of evaluations at
    ~10 us each.  Past ``max_nfev`` the run stops and returns
    ``status = "step limit exceeded"`` (``nfev`` then equals the budget).
    Other arguments as in ``impact_scipy``.
    """
    alpha = float(check_alpha(alpha))
    xi = float(check_range("xi", xi, 0.0, 1.0, hi_open=True))
    max_nfev = int(check_range("max_nfev", max_nfev, 1.0, np.inf, hi_open=True))
    A = 0.5 * xi * (1.0 - xi) ** -0.6
    count = [0]

    def fun(t, y):
        count[0] += 1
        if count[0] > max_nfev:
            raise _BudgetExceeded
        x = max(y[0], 0.0)
        return [y[1], A - 1.25 * x**1.5 * (1.0 + alpha * y[1])]

    x_eq = (A / 1.25) ** (2.0 / 3.0) if A > 0 else np.inf

    def energy(x_m, x_e, v_e):
        return (0.5 * v_e**2 + A * (x_m - x_e)) / (0.5 + A * x_m)

    try:
        return _run(
            fun, x_eq, 1.0, energy, method=method, rtol=rtol, atol=atol, t_max=t_max, rest_tol=rest_tol
        )
    except _BudgetExceeded:
        return ReferenceResult(np.nan, "failed", np.nan, np.nan, np.nan, max_nfev, "step limit exceeded")
    except ValueError as err:
        # solve_ivp's event root-finder raises when the event function has the
        # same sign at both ends of a step (seen with LSODA near x_eq).  Any other
        # ValueError (a bad method name or tolerance) is the caller's and propagates.
        if not _from_event_location(err):
            raise
        return ReferenceResult(
            np.nan, "failed", np.nan, np.nan, np.nan, count[0], f"event location failed: {err}"
        )


@dataclass(frozen=True)
class BracketedAlpha:
    """Result of ``alpha_bracketed``: alpha and what the last impact at it reported."""

    alpha: float
    eps_reached: float
    state: str
    status: str
    impacts: int
    nfev: int


class _ImpactFailed(Exception):
    """Carries the status of an impact that failed inside the root-finder."""


def alpha_bracketed(eps, impact_fn, *, alpha0, rtol=1e-13, expand=2.0, alpha_max=1e9, alpha_min=1e-8):
    """Find alpha with ``impact_fn(alpha).eps == eps`` by bracketing and Brent's method (no sensitivities).

    The root-finder for integrators without ``deps/dalpha`` (SciPy, fixed-step
    RK4).  From ``alpha0`` the bracket grows (or shrinks) by ``expand`` until
    ``eps(alpha)`` changes side of the target, using ``eps(0) = 1``; then
    ``scipy.optimize.brentq`` closes it to relative width ``rtol``.

    Parameters
    ----------
    eps : float
        Target restitution, 0 < eps < 1.
    impact_fn : callable
        ``impact_fn(alpha)`` returns an object with ``eps``, ``state``,
        ``status`` ("ok" when it succeeded) and ``nfev``.
    alpha0 : float
        Starting guess, > 0.
    rtol : float
        Relative tolerance on alpha of Brent's method, >= 4 machine epsilons.
    expand : float
        Bracket growth factor, > 1.
    alpha_max, alpha_min : float
        The search gives up above ``alpha_max`` ("no root bracketed") and
        takes ``[0, alpha_min]`` as the bracket below ``alpha_min``.

    Returns
    -------
    BracketedAlpha
        ``status`` is "ok", "no root bracketed", or the status of the impact that failed.
    """
    from scipy.optimize import brentq

    eps = float(check_range("eps", eps, 0.0, 1.0, lo_open=True, hi_open=True))
    alpha0 = float(check_positive("alpha0", alpha0))
    expand = float(check_range("expand", expand, 1.0, np.inf, lo_open=True, hi_open=True))
    rtol = float(check_range("rtol", rtol, 4.0 * np.finfo(float).eps, 0.1))
    seen = {}
    count = {"impacts": 0, "nfev": 0}

    def f(alpha):
        if alpha == 0.0:
            return 1.0 - eps
        if alpha not in seen:
            r = impact_fn(alpha)
            count["impacts"] += 1
            count["nfev"] += int(r.nfev)
            seen[alpha] = r
        r = seen[alpha]
        if r.status != "ok":
            raise _ImpactFailed(r.status)
        # ``impact_scipy`` returns NaN when eps^2 < 0 by round-off (a spurious
        # v = 0 event as compression creeps to x_eq): that eps is 0.
        return (r.eps if np.isfinite(r.eps) else 0.0) - eps

    def result(alpha, status):
        r = seen.get(alpha)
        if r is None or status != "ok":
            return BracketedAlpha(np.nan, np.nan, "failed", status, count["impacts"], count["nfev"])
        return BracketedAlpha(alpha, float(r.eps), str(r.state), status, count["impacts"], count["nfev"])

    try:
        a = alpha0
        if f(a) > 0.0:
            lo = a
            while True:
                a *= expand
                if a > alpha_max:
                    return result(np.nan, "no root bracketed")
                if f(a) <= 0.0:
                    hi = a
                    break
                lo = a
        else:
            hi = a
            lo = 0.0
            while a > alpha_min:
                a /= expand
                if f(a) > 0.0:
                    lo = a
                    break
                hi = a
        if f(hi) == 0.0:
            return result(hi, "ok")
        root = brentq(f, lo, hi, xtol=1e-300, rtol=rtol)
        f(root)
        return result(root, "ok")
    except _ImpactFailed as failure:
        return result(np.nan, str(failure))
