"""The explicit exact unloaded alpha (engine.unloaded): the same root as the solver, to rounding."""

import mpmath
import numpy as np

from contactalpha.engine import unloaded as u
from contactalpha.engine.exact import alpha_exact


def test_equals_a_50_digit_root_to_rounding():
    rng = np.random.default_rng(5)
    eps = np.r_[
        10 ** rng.uniform(-2, np.log10(u.FIXED_POINT_LIMIT), 60),  # fixed-point branch
        rng.uniform(u.FIXED_POINT_LIMIT, 1.0, 200),
        1 - 10 ** rng.uniform(-12, -1, 60),  # alpha -> 0: relative accuracy kept
        np.exp(np.log(u.FIXED_POINT_LIMIT) * np.arange(u.POLY_PIECES + 1) / u.POLY_PIECES),  # piece edges
    ]
    ref = np.array([float(u.reference_g(e) * (1 - mpmath.mpf(e)) / e) if e < 1 else 0.0 for e in eps])
    got = np.array([u.alpha_unloaded_scalar(e) for e in eps])
    rel = np.abs(got / np.where(ref > 0, ref, 1.0) - 1)
    assert np.max(rel[eps < 1]) <= 1e-15
    assert u.alpha_unloaded_scalar(1.0) == 0.0


def test_agrees_with_the_solver_and_the_asymptote():
    eps = np.r_[np.geomspace(1e-6, 0.01, 30), np.linspace(0.01, 0.99, 99)]
    got = np.array([u.alpha_unloaded_scalar(e) for e in eps])
    np.testing.assert_allclose(got, alpha_exact(eps), rtol=2e-15, atol=0)
    assert u.alpha_unloaded_scalar(1e-300) == 1.0 / 1e-300  # alpha = 1/eps to rounding as eps -> 0


def test_shipped_polynomial_is_the_generators():
    # The generator's least-squares Chebyshev fit runs in the machine's LAPACK, whose summation
    # order moves the high coefficients by ~1e-13 between CPUs; the polynomials' values agree to
    # rounding, and a wrong shipped polynomial would differ by far more.
    t = np.linspace(-1.0, 1.0, 201)
    powers = t[:, None] ** np.arange(u.UNLOADED_POLY.shape[1])
    generated, shipped = u.unloaded_polynomial() @ powers.T, u.UNLOADED_POLY @ powers.T
    np.testing.assert_allclose(generated, shipped, rtol=4e-15, atol=0)
