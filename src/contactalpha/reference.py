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

from .validation import check_alpha, check_positive, check_range


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

    hit_v.terminal = True
    hit_v.direction = sign_v

    def hit_x(t, y, *args):
        return y[0]

    hit_x.terminal = True
    hit_x.direction = -1
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
