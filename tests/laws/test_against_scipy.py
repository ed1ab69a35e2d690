"""Every law against an independent SciPy integration: forward map, inverse, end state."""

import numpy as np
import pytest
from scipy_reference import SETTLED, reference_impact

from contactalpha.laws import LAWS

FAMILY = [law for law in LAWS if law.name != "hunt_crossley"]  # n = 3/2 has its own engine tests


def _points(law, n, seed):
    rng = np.random.default_rng(seed)
    lo, hi = law.restitution_domain
    target = lo + (hi - lo) * rng.random(n)
    xi = law.load_domain[1] * rng.random(n) ** 2  # denser at light loads, where the ridge is
    kinematic = rng.random(n) < 0.5
    return target, xi, kinematic


def _settled(law, ours, i, A):
    """Our end state, with a capture within 1e-9 of the equilibrium called creep, as the reference does."""
    x_eq = law.equilibrium(A)
    near = abs(ours.x_end[i] - x_eq) <= SETTLED * max(x_eq, 1.0)
    return "creep" if ours.state[i] == "nonseparation" and near else ours.state[i]


def _check(law, n, seed):
    target, xi, kinematic = _points(law, n, seed)
    p = np.empty(n)
    for kind in (False, True):
        sel = kinematic == kind
        sol = law.damping_for(target[sel], xi[sel], restitution="kinematic" if kind else "energetic")
        assert np.all(sol.ok), sol.status
        p[sel] = sol.damping
    ours = law.impact(p, xi)
    A = law.scaled_load(xi)
    for i in range(n):
        eps, e_n, state = reference_impact(law.name, p[i], A[i], law.impedance)
        reached = e_n if kinematic[i] else eps
        where = f"{law.name} at p = {p[i]!r}, xi = {xi[i]!r}"
        assert state == _settled(law, ours, i, A[i]), where
        assert abs(eps - ours.eps[i]) <= 1e-9, where
        assert abs(e_n - ours.e_n[i]) <= 1e-9, where
        assert abs(reached - target[i]) <= 1e-9, where


@pytest.mark.parametrize("law", FAMILY, ids=lambda law: law.name)
def test_forward_and_inverse_agree_with_scipy(law):
    _check(law, 12, seed=26)


@pytest.mark.integration
@pytest.mark.parametrize("law", FAMILY, ids=lambda law: law.name)
def test_forward_and_inverse_agree_with_scipy_over_the_domain(law):
    _check(law, 200, seed=2026)
