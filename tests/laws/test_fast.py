"""Fast evaluators: the closed form of the linear laws against the reference integrator, and the inverse."""

import numpy as np
import pytest

from contactalpha.laws import LAWS, get_law

LINEAR = [law for law in LAWS if law.piecewise_linear]


def _sample(n, seed):
    rng = np.random.default_rng(seed)
    return np.exp(rng.uniform(np.log(1e-3), np.log(30.0), n)), 0.99 * rng.random(n) ** 2


@pytest.mark.parametrize("law", LINEAR, ids=lambda law: law.name)
def test_closed_form_agrees_with_the_integrator(law):
    zeta, xi = _sample(300, 7)
    zeta[:3] = [0.0, 1.0, 1.0]  # undamped and critically damped phases
    ref = law.impact(zeta, xi)
    for kind, want in (("energetic", ref.eps), ("kinematic", ref.e_n)):
        np.testing.assert_allclose(law.fast_restitution(zeta, xi, kind), want, rtol=0, atol=1e-9)
    assert set(ref.state) >= {"separation", "nonseparation", "creep", "no_restitution"}


@pytest.mark.parametrize("law", LINEAR, ids=lambda law: law.name)
@pytest.mark.parametrize("restitution", ["energetic", "kinematic"])
def test_inverses_deliver_their_target(law, restitution):
    rng = np.random.default_rng(11)
    target = rng.uniform(0.01, 1.0, 200)
    xi = 0.99 * rng.random(200) ** 2
    exact = law.damping_for(target, xi, restitution=restitution)
    assert np.all(exact.ok)
    # The exact inverse through the fast evaluator, and the fast inverse through the integrator.
    np.testing.assert_allclose(
        law.fast_restitution(exact.damping, xi, restitution), target, rtol=0, atol=1e-7
    )
    fast = law.fast_damping(target, xi, restitution)
    np.testing.assert_allclose(law.restitution(fast, xi, restitution), target, rtol=0, atol=1e-9)


def test_laws_without_a_fast_evaluator_say_so():
    from dataclasses import replace

    bare = replace(get_law("hertz_tsuji"), fast=None)
    with pytest.raises(
        ValueError, match="law 'hertz_tsuji' has no fast evaluator yet; law.impact and law.damping_for"
    ):
        bare.fast_damping(0.5, 0.1)
    with pytest.raises(ValueError, match="law 'hunt_crossley' has no fast forward map"):
        get_law("hunt_crossley").fast_restitution(0.5, 0.1)


def test_hunt_crossley_fast_inverse_is_the_engine_table():
    from contactalpha.engine.table import alpha_tabulated

    law = get_law("hunt_crossley")
    assert law.fast_damping(0.5, 0.2325) == alpha_tabulated(0.5, 0.2325)
    np.testing.assert_array_equal(
        law.fast_damping([0.3, 0.6], 0.5, "kinematic"),
        alpha_tabulated([0.3, 0.6], 0.5, restitution="kinematic"),
    )
