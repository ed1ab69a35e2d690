"""The exact inverse delivers its target or says it failed (issue 34, L1 and L2)."""

import numpy as np
import pytest

from contactalpha.laws import get_law
from contactalpha.parameters.front_door import contact_parameters


@pytest.mark.parametrize("law", ["kelvin_voigt", "mujoco_soft"])
@pytest.mark.parametrize("accel", [1e5, 1e7])
def test_far_past_the_load_range_a_damping_is_right_or_flagged(law, accel):
    law = get_law(law)
    xi = law.scene_load_factor(1.0, 1e4, 0.5, accel)
    sol = law.damping_for(0.5, xi, "kinematic")
    if sol.ok:  # then it delivers the target (before: e_N 0.9959 at 1e5 and 0.0 at 1e7, status ok)
        assert sol.e_n == pytest.approx(0.5, abs=1e-8) and sol.damping > 0.0
    else:
        assert np.isnan(sol.damping) and sol.status == "root tolerance not reached"


def test_a_damping_of_zero_is_never_returned_for_a_target_below_one():
    # Not solved, and the message says what to change (issue 44, S15: it was a bare RuntimeError).
    with pytest.raises(ValueError, match="mujoco_soft.* e_N = 0.5 .*a faster approach or a smaller load"):
        contact_parameters(e_N=0.5, mass=1.0, stiffness=1e4, approach_speed=0.5, accel=1e7, law="mujoco_soft")


def test_kelvin_voigt_meets_a_small_target_across_the_integrators_jump():
    # e_N = 0.01 at A = 4 (xi = 0.985): the integrator's e_N(zeta) jumps by ~2e-6 next to the root and
    # the root finder stopped on the jump, 5.8e-8 from the target.
    law = get_law("kelvin_voigt")
    xi = law.load_factor(4.0)
    sol = law.damping_for(0.01, xi, "kinematic")
    closed = float(law.fast_restitution(float(sol.damping), xi, "kinematic"))
    assert closed == pytest.approx(0.01, abs=1e-11)
    assert sol.e_n == pytest.approx(0.01, abs=1e-8)
