import numpy as np
import pytest

from contactalpha.engine.rk import (
    MAX_FACTOR,
    MIN_FACTOR,
    N_STAGES,
    N_STATE,
    dop853_step,
    error_norm,
    rhs,
    step_factor,
)


def _fixed_steps(y0, A, alpha, T, n):
    y = y0.copy()
    K = np.empty((N_STAGES + 1, N_STATE))
    y_new = np.empty(N_STATE)
    tmp = np.empty(N_STATE)
    h = T / n
    for _ in range(n):
        rhs(y, A, alpha, 0, K[0])
        dop853_step(y, h, A, alpha, 0, K, y_new, tmp)
        y[:] = y_new
    return y


def test_rhs_matches_equation_24_scaled():
    out = np.empty(6)
    y = np.array([0.3, 0.7, -0.4, 0.1, 0.2, 0.0])
    A, alpha = 0.6, 2.5
    rhs(y, A, alpha, 0, out)
    assert out[0] == 1.0 and out[1] == y[2] and out[3] == y[4]
    assert out[2] == pytest.approx(A - 1.25 * 0.7**1.5 * (1 + alpha * -0.4), rel=1e-15)
    # sensitivity: derivative of the acceleration with respect to alpha along (p, q)
    da = -1.25 * (1.5 * 0.7**0.5 * 0.1 * (1 + alpha * -0.4) + 0.7**1.5 * (-0.4 + alpha * 0.2))
    assert out[4] == pytest.approx(da, rel=1e-14)


def test_rhs_other_independent_variable_divides_by_its_rate():
    y = np.array([0.3, 0.7, -0.4, 0.1, 0.2, 0.0])
    f0 = np.empty(6)
    f2 = np.empty(6)
    rhs(y, 0.6, 2.5, 0, f0)
    rhs(y, 0.6, 2.5, 2, f2)
    np.testing.assert_allclose(f2[:5], f0[:5] / f0[2], rtol=1e-15)
    assert f2[2] == 1.0


def test_no_contact_force_below_zero_compression():
    out = np.empty(6)
    rhs(np.array([0.0, -1e-3, -0.5, 0.0, 0.0, 0.0]), 0.4, 3.0, 0, out)
    assert out[2] == 0.4


def test_measured_convergence_order_is_eight():
    # Away from x = 0 (where x^{3/2} is not smooth) the step must show order 8.
    y0 = np.array([0.0, 0.5, 0.6, 0.0, 0.0, 0.0])
    A, alpha, T = 0.3, 0.8, 6.0
    ref = _fixed_steps(y0, A, alpha, T, 2048)
    ns = np.array([8, 12, 16, 24, 32])
    errs = np.array([abs(_fixed_steps(y0, A, alpha, T, n)[1] - ref[1]) for n in ns])
    order = -np.polyfit(np.log(ns), np.log(errs), 1)[0]
    assert 7.5 < order < 9.0, (order, errs)


def test_error_norm_is_small_for_smooth_small_step_and_inf_for_nan():
    y = np.array([0.0, 0.5, 0.6, 0.0, 0.0, 0.0])
    K = np.empty((N_STAGES + 1, N_STATE))
    y_new = np.empty(N_STATE)
    tmp = np.empty(N_STATE)
    rhs(y, 0.3, 0.8, 0, K[0])
    dop853_step(y, 1e-2, 0.3, 0.8, 0, K, y_new, tmp)
    small = error_norm(K, 1e-2, y, y_new, 1e-10, 1e-12)
    dop853_step(y, 2e-1, 0.3, 0.8, 0, K, y_new, tmp)
    large = error_norm(K, 2e-1, y, y_new, 1e-10, 1e-12)
    assert small < 1.0 < large
    K[3, 1] = np.nan
    assert error_norm(K, 1e-2, y, y_new, 1e-10, 1e-12) == np.inf


def test_step_factor_limits():
    assert step_factor(np.inf, False) == MIN_FACTOR
    assert step_factor(1e9, False) == MIN_FACTOR
    assert step_factor(0.0, False) == MAX_FACTOR
    assert step_factor(0.0, True) == 1.0
    assert step_factor(1e-6, True) == 1.0  # no growth right after a rejection
    assert 1.0 < step_factor(1e-3, False) <= MAX_FACTOR
    assert step_factor(2.0, False) < 1.0
