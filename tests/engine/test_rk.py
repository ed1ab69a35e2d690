import numpy as np
import pytest

from contactalpha.engine.rk import (
    MIN_FACTOR,
    N_CONTROLLED,
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


def _scipy_dop853_step(y, h, A, alpha):
    """SciPy's own DOP853 step and error norm (its tableau, its code) on the engine's right-hand side."""
    from types import SimpleNamespace

    from scipy.integrate._ivp import dop853_coefficients as dc
    from scipy.integrate._ivp.rk import DOP853, rk_step

    def fun(t, state):
        out = np.empty(N_STATE)
        rhs(state, A, alpha, 0, out)
        return out

    K = np.empty((dc.N_STAGES + 1, N_STATE))
    y_new, _ = rk_step(fun, 0.0, y, fun(0.0, y), h, dc.A[: dc.N_STAGES, : dc.N_STAGES], dc.B, dc.C, K)
    return y_new, lambda rtol, atol: DOP853._estimate_error_norm(
        SimpleNamespace(E5=dc.E5, E3=dc.E3),
        K[:, :N_CONTROLLED],
        h,
        atol + rtol * np.maximum(abs(y), abs(y_new))[:N_CONTROLLED],
    )


@pytest.mark.parametrize("h", [1e-2, 2e-1, 1.0])
def test_step_and_error_norm_equal_scipys_dop853(h):
    # An independent oracle: SciPy's DOP853 step and error estimate, restricted to the components the
    # engine controls (t, x, v).  A wrong stage weight or embedded weight moves both.
    y = np.array([0.0, 0.5, 0.6, 0.1, -0.2, 0.0])
    K = np.empty((N_STAGES + 1, N_STATE))
    y_new = np.empty(N_STATE)
    rhs(y, 0.3, 0.8, 0, K[0])
    dop853_step(y, h, 0.3, 0.8, 0, K, y_new, np.empty(N_STATE))
    ref, ref_norm = _scipy_dop853_step(y, h, 0.3, 0.8)
    np.testing.assert_allclose(y_new, ref, rtol=0, atol=2e-15)  # summation order: a few ulp
    # The estimate is a sum of O(1) stages that cancels to ~1e-10 of them: summation order alone
    # moves it by ~1e-8 relative; a wrong weight moves it by O(1).  At h = 1e-2 the local error
    # (~1e-21) is below the stages' rounding (~1e-18), so the estimate is rounding noise whose value
    # depends on the summation order of the machine's BLAS: only the step is compared there.
    if h < 0.1:
        return
    for rtol, atol in [(1e-10, 1e-12), (1e-4, 1e-6)]:
        assert error_norm(K, h, y, y_new, rtol, atol) == pytest.approx(ref_norm(rtol, atol), rel=1e-6)


def test_error_norm_is_inf_for_nan():
    y = np.array([0.0, 0.5, 0.6, 0.0, 0.0, 0.0])
    K = np.empty((N_STAGES + 1, N_STATE))
    y_new = np.empty(N_STATE)
    rhs(y, 0.3, 0.8, 0, K[0])
    dop853_step(y, 1e-2, 0.3, 0.8, 0, K, y_new, np.empty(N_STATE))
    assert np.isfinite(error_norm(K, 1e-2, y, y_new, 1e-10, 1e-12))
    K[3, 1] = np.nan
    assert error_norm(K, 1e-2, y, y_new, 1e-10, 1e-12) == np.inf


def test_step_factor_is_scipys_rule():
    # SciPy's DOP853 controller (scipy.integrate._ivp.rk): SAFETY err^(-1/8), clipped to
    # [MIN_FACTOR, MAX_FACTOR], no growth right after a rejection.
    from scipy.integrate._ivp import rk as srk

    def scipy_factor(err, rejected):
        if err >= 1:
            return max(srk.MIN_FACTOR, srk.SAFETY * err ** (-1 / 8))
        f = srk.MAX_FACTOR if err == 0 else min(srk.MAX_FACTOR, srk.SAFETY * err ** (-1 / 8))
        return min(1.0, f) if rejected else f

    for err in (0.0, 1e-12, 1e-6, 1e-3, 0.2, 0.99, 1.01, 2.0, 1e3, 1e9):
        for rejected in (False, True):
            assert step_factor(err, rejected) == pytest.approx(scipy_factor(err, rejected), rel=1e-15)
    assert step_factor(np.inf, False) == MIN_FACTOR
