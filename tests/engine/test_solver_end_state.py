"""A solve never accepts an impact that ended in another end state than its target's (issue 29, N1).

An impact without restitution reaches eps = 0, which an absolute tolerance on eps used to accept
for any target 0 < eps <= tol: the formula guess alpha ~ 1/eps then came back with status "ok".
"""

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.baselines.reference import impact_scipy
from contactalpha.cli import main


def test_loose_tolerance_finds_the_root_not_an_impact_without_restitution():
    s = ca.solve_alpha(5e-4, 0.2, tol=1e-3)
    assert s.ok and s.state != "no_restitution"
    # SciPy's DOP853 at the alpha found: an impact that restitutes, with eps within tol.
    ref = impact_scipy(s.alpha, 0.2, rtol=1e-13, atol=1e-16)
    assert ref.state != "no_restitution" and abs(ref.eps - 5e-4) <= 1e-3
    # The root at the default tolerance is alpha ~ 109.69, not the guess 1/eps = 2000.
    assert s.alpha == pytest.approx(ca.solve_alpha(5e-4, 0.2).alpha, rel=1e-3)


@pytest.mark.parametrize("restitution", ["energetic", "kinematic"])
def test_target_below_tol_is_not_met_by_zero(restitution):
    s = ca.solve_alpha(1e-12, 0.2, restitution=restitution)
    assert s.ok
    assert s.state == ("separation" if restitution == "kinematic" else "creep")
    # Just below the onset (energetic) or the separation boundary (kinematic), not 1/eps = 1e12.
    assert s.alpha < 200.0
    ref = impact_scipy(s.alpha, 0.2, rtol=1e-13, atol=1e-16)
    assert ref.status == "ok" and ref.state != "no_restitution"
    if restitution == "energetic":
        # eps^2 is linear in alpha at the onset: eps = 1e-12 sits on it to ~1e-9 relative.
        assert s.alpha == pytest.approx(ca.solve_alpha(0.0, 0.2).alpha, rel=1e-6)
        assert ref.eps < 1e-4
    else:
        # e_N = 1e-12 sits on the separation boundary: SciPy separates just below alpha, not above.
        assert impact_scipy(s.alpha * (1 - 1e-4), 0.2, rtol=1e-13, atol=1e-16).state == "separation"
        assert impact_scipy(s.alpha * (1 + 1e-4), 0.2, rtol=1e-13, atol=1e-16).state != "separation"


def test_array_solve_rejects_the_zero_end_state_too():
    s = ca.solve_alpha(np.array([5e-4, 0.5]), 0.2, tol=1e-3)
    assert np.all(s.ok) and "no_restitution" not in set(s.state)
    assert s.alpha[0] < 200.0


def test_params_damping_at_a_tiny_eps_is_the_onset_not_one_over_eps(capsys):
    args = ["params", "--eps", "1e-12", "--mass", "0.5", "--stiffness", "1.4e8", "--speed", "1"]
    assert main([*args, "--accel", "129.81", "--json"]) == 0
    import json

    cp = json.loads(capsys.readouterr().out)
    onset = ca.solve_alpha(0.0, cp["xi"])
    assert onset.ok
    assert cp["damping_name"] == "alpha" and cp["damping"] == pytest.approx(onset.alpha, rel=1e-6)
    assert cp["physical_damping"] == pytest.approx(onset.alpha / 1.0, rel=1e-6)  # d = alpha / v, s/m
