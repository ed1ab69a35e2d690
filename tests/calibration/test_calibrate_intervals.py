"""Profile-likelihood intervals against independent answers: a flat profile and a linear model."""

import math
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.optimize import brentq, least_squares
from scipy.stats import t as t_dist

from contactalpha.calibration.fit import _profile, _threshold

# Residuals that do not depend on the parameters: the fit's noise floor (n = 12, p = 2).
FLOOR = np.array([0.1, -0.1, 0.05, -0.05, 0.08, -0.02, 0.03, -0.07, 0.01, 0.04])
SLOPE = 1e-4  # a nearly flat parameter: its Wald standard error is huge


def _flat(x):
    u, w = x
    return np.concatenate([[10.0 * (w - 1.0), SLOPE * (u - 9.0) - max(0.0, 5.0 - u)], FLOOR])


def _problem(residuals, bounds):
    return SimpleNamespace(residuals=residuals, bounds=bounds, scale=1.0)


def test_flat_profile_lower_end_is_where_the_profile_crosses():
    # Estimate at u = 9; the profile stays under the threshold down to u ~ 4.9, then rises.
    problem = _problem(_flat, [(0.0, 10.0), (-5.0, 5.0)])
    best = least_squares(_flat, [9.0, 1.0], xtol=1e-14, ftol=1e-14, gtol=1e-14)
    rss = float(best.fun @ best.fun)
    limit = _threshold(12, 2, 0.95) * rss
    lo, hi, blo, bhi = _profile(problem, best, 0, limit)

    def excess(u):  # independent: w is at its optimum 1 for every u
        r = _flat([u, 1.0])
        return float(r @ r) - limit

    truth = brentq(excess, 0.0, 9.0, xtol=1e-13)
    assert truth == pytest.approx(5.0 - math.sqrt(limit - FLOOR @ FLOOR), rel=1e-3)
    assert lo == pytest.approx(truth, abs=0.01 * (9.0 - truth))
    assert blo and not bhi and hi == 10.0


def test_linear_model_profile_is_the_t_interval():
    # For a linear model with unknown sigma the F(1, n - p) threshold gives exactly the t interval.
    rng = np.random.default_rng(3)
    x = np.linspace(0.0, 1.0, 15)
    y = 0.7 + 2.0 * x + rng.normal(0.0, 0.05, x.size)

    def res(p):
        return y - (p[0] + p[1] * x)

    problem = _problem(res, [(-10.0, 10.0), (-10.0, 10.0)])
    best = least_squares(res, [0.0, 0.0], xtol=1e-15, ftol=1e-15, gtol=1e-15)
    n, p = x.size, 2
    rss = float(best.fun @ best.fun)
    design = np.column_stack([np.ones_like(x), x])
    cov = np.linalg.inv(design.T @ design) * rss / (n - p)
    q = t_dist.ppf(0.975, n - p)
    for j in range(2):
        lo, hi, blo, bhi = _profile(problem, best, j, _threshold(n, p, 0.95) * rss)
        half = q * math.sqrt(cov[j, j])
        assert blo and bhi
        assert lo == pytest.approx(best.x[j] - half, abs=1e-3 * half)
        assert hi == pytest.approx(best.x[j] + half, abs=1e-3 * half)
