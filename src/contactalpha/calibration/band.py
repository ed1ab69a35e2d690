"""Newton's restitution at the recorded approach speeds, with its delta-method interval.

Each contact's ``e_N`` is a function of the fitted coordinates ``x`` (the law's parameters and
the nuisance ones); its variance is ``g' C g`` with ``g`` the gradient of ``e_N`` in ``x``
(central differences) and ``C = (J'J)^-1 RSS / (n - p)`` the least-squares covariance from the
fit's Jacobian ``J``.  The interval is ``e_N +- t(n - p) se``: a Wald interval, cheaper than a
profile of each contact and exact only for a model linear in ``x`` (stated in the report).
"""

import numpy as np
from scipy.stats import t as t_dist

# Relative step of the central differences of e_N in the fitting coordinates.
BAND_STEP = 1e-5
METHOD = "Wald (delta method), t(n - p) quantile"


def e_n_band(problem, best, level, interval=True):
    """``(e_N, lo, hi)`` arrays over the fitted sequence's contacts that separate.

    Parameters
    ----------
    problem : fit.Problem
    best : scipy.optimize.OptimizeResult of the fit (``x``, ``jac``, ``cost``).
    level : float
        Confidence level in (0, 1).
    interval : bool
        False: only ``e_N`` (the interval ends are NaN).
    """
    x = np.asarray(best.x, dtype=float)
    e = _e_n(problem, x)
    jac = np.asarray(best.jac, dtype=float)
    dof = jac.shape[0] - jac.shape[1]
    nan = np.full(e.size, np.nan)
    if not interval or dof < 1 or e.size == 0:
        return e, nan, nan
    try:
        cov = np.linalg.inv(jac.T @ jac) * (2.0 * best.cost / dof)
    except np.linalg.LinAlgError:
        return e, nan, nan
    grad = np.empty((e.size, x.size))
    for j in range(x.size):
        h = BAND_STEP * max(1.0, abs(x[j]))
        up, down = x.copy(), x.copy()
        up[j] += h
        down[j] -= h
        e_up, e_down = _e_n(problem, up), _e_n(problem, down)
        k = min(e.size, e_up.size, e_down.size)
        grad[:, j] = np.nan
        grad[:k, j] = (e_up[:k] - e_down[:k]) / (2.0 * h)
    se = np.sqrt(np.maximum(np.einsum("ij,jk,ik->i", grad, cov, grad), 0.0))
    half = t_dist.ppf(0.5 + 0.5 * level, dof) * se
    return e, e - half, e + half


def _e_n(problem, x):
    s = problem.sequence(x)
    n = s.v_out.size if not s.ended else s.v_out.size - 1
    return np.asarray(s.e_n[:n], dtype=float)
