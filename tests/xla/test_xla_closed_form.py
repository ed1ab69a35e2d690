"""MuJoCo's law and the spring-dashpot in JAX: the closed form, its inverse and their derivatives."""

import numpy as np
import pytest

from contactalpha.laws import get_law
from contactalpha.laws.closed_form import closed_form_states


def _numba_states(zeta, A, d):
    out = np.empty((zeta.size, 4))
    closed_form_states(zeta, A, d, out)
    return out


@pytest.mark.parametrize("d", [0.0, 0.5, 0.9])
def test_closed_form_matches_numba(jax, d):
    from contactalpha.xla import closed_form as cf

    rng = np.random.default_rng(11)
    zeta, A = rng.uniform(0.0, 2.5, 1500), 10.0 ** rng.uniform(-3.0, 1.0, 1500)
    zeta[:2] = (0.0, 1.0)  # undamped; critically damped
    eps, e_n, state, floors, ended = (
        np.asarray(x) for x in jax.jit(lambda z, a: cf.impact(z, a, d))(zeta, A)
    )
    ref = _numba_states(zeta, A, d)
    assert ended.all()
    np.testing.assert_array_equal(state, ref[:, 2])
    np.testing.assert_array_equal(floors, ref[:, 3])
    # The numba form stops its Newton steps at 1e-10 relative in time: its own rounding bound.
    np.testing.assert_allclose(e_n, ref[:, 1], rtol=0.0, atol=1e-9)
    np.testing.assert_allclose(eps, np.sqrt(np.maximum(ref[:, 0], 0.0)), rtol=0.0, atol=1e-9)


def _fd5(f, x, h):
    return (f(x - 2 * h) - 8 * f(x - h) + 8 * f(x + h) - f(x + 2 * h)) / (12 * h)


@pytest.mark.parametrize("kinematic", [True, False])
def test_closed_form_gradient_matches_finite_differences(jax, kinematic):
    """jax.grad in zeta and A against 5-point differences of the numba closed form, off the kinks."""
    from contactalpha.xla import closed_form as cf

    d = 0.9
    rng = np.random.default_rng(5)
    zeta, A = rng.uniform(0.05, 2.0, 800), 10.0 ** rng.uniform(-2.0, 0.5, 800)
    col = 1 if kinematic else 0

    def value(z, a):
        r = _numba_states(z, a, d)[:, col]
        return r if kinematic else np.sqrt(r)

    g = jax.jit(jax.vmap(jax.grad(lambda z, a: cf.restitution(z, a, d, kinematic), argnums=(0, 1))))
    gz, gA = (np.asarray(x) for x in g(zeta, A))
    assert np.all(np.isfinite(gz)) and np.all(np.isfinite(gA))
    for got, fd in (
        (gz, lambda h: _fd5(lambda x: value(x, A), zeta, h)),
        (gA, lambda h: _fd5(lambda x: value(zeta, x), A, h * A) / 1.0),
    ):
        f1, f2 = fd(1e-3), fd(5e-4)
        # Off the kinks: where halving the step moves the 5-point quotient by under 1e-8.
        smooth = np.abs(f1 - f2) <= 1e-8 * (1.0 + np.abs(f2))
        assert smooth.sum() > 400
        np.testing.assert_allclose(got[smooth], f2[smooth], rtol=1e-6, atol=1e-6)


@pytest.mark.parametrize("d", [0.5])
def test_inverse_meets_the_target(jax, d):
    """The JAX inverse at any impedance, through the numba closed form's forward map."""
    from contactalpha.xla.inverse import closed_form_damping

    law = get_law("mujoco_soft", impedance=d)
    rng = np.random.default_rng(2)
    target, xi = rng.uniform(0.05, 0.95, 200), rng.uniform(0.0, 0.9, 200)
    zeta = np.asarray(jax.jit(lambda t, x: closed_form_damping(law, t, x))(target, xi))
    ok = np.isfinite(zeta)
    assert ok.mean() > 0.5
    A = np.atleast_1d(law.scaled_load(xi))
    np.testing.assert_allclose(_numba_states(zeta[ok], A[ok], d)[:, 1], target[ok], atol=1e-12)
    # Where there is no answer (NaN), the numba inverse finds none either.
    ref = law.fast_damping(target[~ok], xi[~ok], "kinematic", exact=True)
    assert np.all(np.isnan(ref))


def test_inverse_gradient_is_the_implicit_one(jax):
    """d zeta / d target = 1 / (d e_N / d zeta), from the numba forward map's differences."""
    from contactalpha.xla.inverse import closed_form_damping

    law = get_law("mujoco_soft")
    target, xi = np.array([0.3, 0.5, 0.7, 0.85]), np.array([0.05, 0.2, 0.4, 0.1])
    zeta = np.asarray(closed_form_damping(law, target, xi))
    dz = np.asarray(jax.vmap(jax.grad(lambda t, x: closed_form_damping(law, t, x)))(target, xi))
    A = np.atleast_1d(law.scaled_load(xi))
    slope = _fd5(lambda z: _numba_states(z, A, law.impedance)[:, 1], zeta, 1e-4)
    np.testing.assert_allclose(dz, 1.0 / slope, rtol=1e-6)
