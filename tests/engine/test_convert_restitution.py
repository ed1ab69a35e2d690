"""convert_restitution: NaN where its solve fails, and only the solver options it can pass (issue 29, N6)."""

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.baselines.reference import impact_scipy


def test_a_failed_solve_gives_nan_as_the_docstring_promises():
    s = ca.solve_alpha(0.5, 1 - 1e-12, restitution="kinematic")
    assert not s.ok  # the solve fails here ...
    assert np.isnan(ca.convert_restitution(0.5, 1 - 1e-12, to="energetic"))  # ... so no number
    both = ca.convert_restitution([0.5, 0.5], [0.2, 1 - 1e-12], to="energetic")
    assert np.isfinite(both[0]) and np.isnan(both[1])


def test_the_conversion_is_the_scipy_impacts_other_coefficient():
    e_n = ca.convert_restitution(0.5, 0.2)
    alpha = ca.solve_alpha(0.5, 0.2).alpha
    ref = impact_scipy(alpha, 0.2, rtol=1e-13, atol=1e-16)
    assert ref.state == "separation" and ref.eps == pytest.approx(0.5, abs=1e-9)
    assert e_n == pytest.approx(-ref.v_end, abs=1e-9)  # e_N = v_end / v_minus, v_minus = 1 scaled
    assert e_n == pytest.approx(0.3321, abs=1e-4)


@pytest.mark.parametrize(
    "option", [{"restitution": "kinematic"}, {"guess": "formula"}, {"exact_at_zero": False}]
)
def test_options_that_change_what_is_solved_are_refused(option):
    with pytest.raises(ValueError, match=f"solver option\\(s\\) {next(iter(option))} not taken"):
        ca.convert_restitution(0.5, 0.2, to="kinematic", **option)


def test_solver_options_are_checked():
    with pytest.raises(ValueError, match="rtol = 0.5 is outside the valid range"):
        ca.convert_restitution(0.5, 0.2, rtol=0.5)
    assert ca.convert_restitution(0.5, 0.2, tol=1e-10, rtol=1e-11) == pytest.approx(0.3321, abs=1e-4)
